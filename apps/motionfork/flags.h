// One grammar for the command line: the spellings many subcommands share (the motion argument,
// -o/--out, --json [FILE]) and old spellings kept for one release with a deprecation note.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "commands.h"
#include "generator/kernels/precision.h"
#include "launch/worker_launcher.h"
#include "launch/worker_place.h"

namespace motionfork::app {

// Checks of option values with readable messages: numbers > 0 or >= 0 (CLI11's own print the
// largest double in full), seeds (0..2^64-1, no silent wrap of -1), input files (regular files:
// io/file_util.h InputFileProblem) and a mark on output paths (checked by RequireSeparateOutputs).
extern const CLI::Validator PositiveNumber, NonNegativeNumber, Seed, InputFile, OutputFile;

// Refuses (std::invalid_argument) an output path (an option checked with OutputFile) that is
// empty, names only a folder, or names one of the input files (options checked with InputFile).
void RequireSeparateOutputs(CLI::App* cmd);

// A subcommand and the options its flags fill (they live as long as the callback that runs it).
template <typename Options>
struct Subcommand {
  CLI::App* cmd;
  std::shared_ptr<Options> options;
};

// Adds subcommand `name` with its --help description to `parent`; when it is chosen,
// run(options, global) runs.
template <typename Options, typename Run>
Subcommand<Options> AddSubcommand(CLI::App* parent, GlobalOptions& global, Run run,
                                  const std::string& name, const std::string& description) {
  auto options = std::make_shared<Options>();
  CLI::App* cmd = parent->add_subcommand(name, description);
  cmd->callback([cmd, options, run, &global] {
    RequireSeparateOutputs(cmd);
    run(*options, global);
  });
  return {cmd, options};
}

// Prints on stderr that `old_spelling` is deprecated and what to write instead (the old spelling
// goes away in the next release).
void NoteDeprecated(const std::string& old_spelling, const std::string& new_spelling);

// A hidden option `old_flag` that sets *target like `new_spelling` does and prints the note.
template <typename T>
CLI::Option* AddDeprecatedOption(CLI::App* cmd, const std::string& old_flag,
                                 const std::string& new_spelling, T* target) {
  return cmd
      ->add_option_function<T>(
          old_flag,
          [old_flag, new_spelling, target](const T& value) {
            NoteDeprecated(old_flag, new_spelling);
            *target = value;
          },
          "Deprecated: " + new_spelling)
      ->group("");  // hidden from --help
}

// The motion file a subcommand reads, named by its first argument (MOTION); `old_flag` (e.g.
// --history) is accepted for one release. Call RequireMotion(path) in the subcommand's callback.
// Path: std::string, or std::vector<std::string> for several files.
template <typename Path>
void AddMotionArgument(CLI::App* cmd, Path* path, const std::string& help,
                       const std::string& old_flag = "") {
  cmd->add_option("MOTION", *path, help)->check(InputFile);
  if (!old_flag.empty())
    AddDeprecatedOption(cmd, old_flag, "the motion file as the first argument", path)
        ->check(InputFile);
}
// Throws CLI::RequiredError when no motion was named.
void RequireMotion(const std::string& path);
// Throws CLI::RequiredError naming `name` when `value` is empty (an option required in one of
// two spellings, which CLI11 cannot require itself).
void RequireArgument(const std::string& value, const std::string& name);

// A file the subcommand reads, named by a required positional argument (e.g. "MOTION").
CLI::Option* AddInputFile(CLI::App* cmd, const std::string& name, std::string* path,
                          const std::string& help);
// --model BUNDLE, required.
CLI::Option* AddModelOption(CLI::App* cmd, std::string* dir, const std::string& help);
// --data DIR, required, an existing folder.
CLI::Option* AddDataOption(CLI::App* cmd, std::string* dir, const std::string& help);
// --data DIR and --split FILE, a split file overriding the protocol's.
void AddDataOptions(CLI::App* cmd, std::string* dir, std::string* split_file,
                    const std::string& data_help);
// -o,--out FILE, required.
CLI::Option* AddOutOption(CLI::App* cmd, std::string* path, const std::string& help);
// --threads N: threads sharing the windows (0, the default, = every core; experiment_common.h
// WindowThreads).
void AddThreadsOption(CLI::App* cmd, int* threads);
// --precision fp32|bf16|auto (generator/kernels/precision.h).
// help: "" = the generator's products at inference (auto the default).
CLI::Option* AddPrecisionOption(CLI::App* cmd, Precision* precision, const std::string& help = "");
// --forecaster BUNDLE, --forecast-windows N, -k K: the forecasting figures of the history-repair
// experiments.
void AddForecasterOptions(CLI::App* cmd, std::string* forecaster, int* windows, int* k,
                          const std::string& windows_help);

// The flags of a training run that resumes: --data, --out, --split, --epochs, --stop-after, and
// the launcher's (AddLauncherOptions).
struct TrainingRunFlags {
  std::string data, out, split_file;
  int epochs = 0;      // overrides the config's; 0 = the config's
  int stop_after = 0;  // epochs of this run; 0 = all
  LaunchOptions launch;
};
void AddTrainingRunOptions(CLI::App* cmd, TrainingRunFlags* f, const std::string& out_help);
// --nproc-per-node, --nnodes, --node-rank, --master-addr, --master-port (torchrun's spellings).
void AddLauncherOptions(CLI::App* cmd, LaunchOptions* o);
// When `o` asks for several workers: starts this machine's workers on the same command line
// (without the launcher's flags), waits for them, sets g.exit_code and returns true.
bool LaunchIfRequested(const LaunchOptions& o, GlobalOptions& g);

// --json [FILE]: the report as JSON, written to FILE, or printed on stdout when FILE is '-' or
// left out.
void AddJsonOption(CLI::App* cmd, std::string* destination, const std::string& what);
// Prints on one line (destination "-") or writes atomically, indented (any other path), the
// report; "" = nothing.
void EmitJson(const std::string& destination, const nlohmann::ordered_json& report);

}  // namespace motionfork::app
