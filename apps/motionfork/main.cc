// motionfork: diverse, controllable human motion prediction. One command, many subcommands.
//
// Exit status: 0 success; 2 bad input or usage (the message names the file and what was wrong);
// subcommands may define 1 (e.g. a check that found problems).
#include <cstdio>
#include <exception>

#include "app_common.h"
#include "commands.h"
#include "core/error.h"
#include "launch/worker_place.h"
#include "suggest.h"
#include "torch_util/blas_core.h"
#include "torch_util/error_text.h"
#include "torch_util/malloc_tuning.h"

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);  // OpenBLAS's fast kernels on CPUs it does not know
  motionfork::KeepFreedMemory();         // no page faults on every new tensor
  using namespace motionfork::app;
  using motionfork::UserErrorMessage;
  CLI::App app{"motionfork " MOTIONFORK_VERSION
               ": diverse, controllable human motion prediction.\n"
               "Run 'motionfork SUBCOMMAND --help' for each subcommand's options."};
  app.require_subcommand(1);
  // Global options are accepted after the subcommand too (`motionfork info x.csv --quiet`), as
  // git and cargo accept theirs; every subcommand made below inherits this.
  app.fallthrough();
  app.set_version_flag("--version", MOTIONFORK_VERSION);
  GlobalOptions global;
  global.argv.assign(argv, argv + argc);
  app.add_option(
      "--config-dir", global.config_dir,
      "Folder of YAML configs (default: $MOTIONFORK_CONFIG_DIR or the source tree's configs/)");
  app.add_option(
      "--cache-dir", global.cache_dir,
      "Folder for parsed-dataset caches ('none' disables; default: $MOTIONFORK_CACHE_DIR or "
      "~/.cache/motionfork)");
  app.add_flag("-q,--quiet", global.quiet, "No progress bars");
  // In the order --help lists them.
  for (auto add :
       {AddInfoCommand, AddConvertCommand, AddDatasetCommand, AddEvalCommand, AddTrainCommand,
        AddPredictCommand, AddPriorCommand, AddCheckCommand, AddConstraintsCommand,
        AddExportCommand, AddRenderCommand, AddSynthCommand, AddHgvaeCommand, AddImputeCommand,
        AddOodCommand, AddDvaeCommand, AddDenoiseCommand, AddBundleCommand}) {
    add(app, global);
  }
  std::string worker;  // "rank N: " in a run of several workers, whose rank 0 alone prints
  try {
    worker = motionfork::FollowRankZeroOutput(&global.quiet);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (const std::string fix = SuggestFix(app, argc, argv); !fix.empty()) {
      std::fprintf(stderr, "motionfork: error: %s\n", fix.c_str());
      return kExitBadInput;
    }
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  } catch (const std::exception& e) {  // one error path: no stack trace, no bare library text
    std::fflush(stdout);
    std::string doing = "running 'motionfork";
    for (const CLI::App* s = &app; !s->get_subcommands().empty(); s = s->get_subcommands()[0])
      doing += " " + s->get_subcommands()[0]->get_name();
    std::fprintf(stderr, "motionfork: error: %s%s\n", worker.c_str(),
                 UserErrorMessage(e, doing + "'").c_str());
    return kExitBadInput;
  }
  return global.exit_code;
}
