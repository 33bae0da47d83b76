#include "flags.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

#include "app_common.h"
#include "io/file_util.h"
#include "io/json_text.h"

namespace motionfork::app {

namespace {

CLI::Validator NumberAbove0(bool zero_too) {
  return CLI::Validator(
      [zero_too](std::string& text) {
        double v = 0;
        const bool ok = CLI::detail::lexical_cast(text, v) && (v > 0 || (zero_too && v == 0));
        return ok ? std::string()
                  : "expected a number " + std::string(zero_too ? ">= 0" : "> 0") + ", found '" +
                        text + "'";
      },
      zero_too ? "NONNEGATIVE" : "POSITIVE");
}

bool Checks(CLI::Option* option, const CLI::Validator& validator) {
  try {
    return option->get_validator(validator.get_name()) != nullptr;
  } catch (const CLI::OptionNotFound&) {
    return false;
  }
}

}  // namespace

const CLI::Validator PositiveNumber = NumberAbove0(false), NonNegativeNumber = NumberAbove0(true);
const CLI::Validator Seed(
    [](std::string& t) {
      const bool ok = !t.empty() && t.size() <= 20 && t.find_first_not_of("0123456789") == t.npos &&
                      (t.size() < 20 || t <= "18446744073709551615");
      return ok ? "" : "expected an integer 0..18446744073709551615, found '" + t + "'";
    },
    "", "SEED");
const CLI::Validator InputFile(
    [](std::string& path) {
      const std::string problem = InputFileProblem(path);
      return problem.empty() ? problem : path + ": " + problem;
    },
    "FILE", "INPUT_FILE");
const CLI::Validator OutputFile([](std::string&) { return std::string(); }, "", "OUTPUT_FILE");

void RequireSeparateOutputs(CLI::App* cmd) {
  std::vector<std::string> inputs, outputs;
  for (CLI::Option* option : cmd->get_options()) {
    const std::vector<std::string>& values = option->results();
    if (Checks(option, InputFile)) inputs.insert(inputs.end(), values.begin(), values.end());
    if (Checks(option, OutputFile)) outputs.insert(outputs.end(), values.begin(), values.end());
  }
  for (const std::string& out : outputs) {
    if (out != "-") RequireSeparateOutput(out, inputs);
  }
}

void NoteDeprecated(const std::string& old_spelling, const std::string& new_spelling) {
  std::fprintf(stderr,
               "motionfork: note: %s is deprecated, write %s instead (the old spelling goes away "
               "in the next release)\n",
               old_spelling.c_str(), new_spelling.c_str());
}

void RequireMotion(const std::string& path) {
  RequireArgument(path, "MOTION (the motion file, first argument)");
}

void RequireArgument(const std::string& value, const std::string& name) {
  if (value.empty()) throw CLI::RequiredError(name);
}

CLI::Option* AddInputFile(CLI::App* cmd, const std::string& name, std::string* path,
                          const std::string& help) {
  return cmd->add_option(name, *path, help)->required()->check(InputFile);
}

CLI::Option* AddModelOption(CLI::App* cmd, std::string* dir, const std::string& help) {
  return cmd->add_option("--model", *dir, help)->required();
}

CLI::Option* AddDataOption(CLI::App* cmd, std::string* dir, const std::string& help) {
  return cmd->add_option("--data", *dir, help)->required()->check(CLI::ExistingDirectory);
}

void AddDataOptions(CLI::App* cmd, std::string* dir, std::string* split_file,
                    const std::string& data_help) {
  AddDataOption(cmd, dir, data_help);
  cmd->add_option("--split", *split_file, "Split file overriding the protocol's");
}

CLI::Option* AddOutOption(CLI::App* cmd, std::string* path, const std::string& help) {
  return cmd->add_option("-o,--out", *path, help)->required()->check(OutputFile);
}

void AddThreadsOption(CLI::App* cmd, int* threads) {
  cmd->add_option("--threads", *threads,
                  "Threads sharing the windows (default: every core); the results do not change")
      ->check(PositiveNumber);
}

CLI::Option* AddPrecisionOption(CLI::App* cmd, Precision* precision, const std::string& help) {
  return cmd
      ->add_option_function<std::string>(
          "--precision", [precision](const std::string& s) { *precision = ParsePrecision(s); },
          !help.empty() ? help
                        : "The generator's products: auto (default: bf16 where the CPU has "
                          "AVX512-BF16, else fp32), fp32, or bf16 (bfloat16 inputs, float32 sums; "
                          "needs AVX512-BF16); RESULTS.md gives bf16's accuracy")
      ->check(CLI::IsMember({"fp32", "bf16", "auto"}));
}

void AddForecasterOptions(CLI::App* cmd, std::string* forecaster, int* windows, int* k,
                          const std::string& windows_help) {
  cmd->add_option("--forecaster", *forecaster,
                  "Generator bundle for the downstream figures (e.g. models/bandai)");
  cmd->add_option("--forecast-windows", *windows, windows_help)->check(PositiveNumber);
  cmd->add_option("-k", *k, "Futures per history (default 50)")->check(PositiveNumber);
}

void AddTrainingRunOptions(CLI::App* cmd, TrainingRunFlags* f, const std::string& out_help) {
  AddDataOption(cmd, &f->data, "Data folder of the config's protocol");
  cmd->add_option("--out", f->out, out_help)->required();
  cmd->add_option("--split", f->split_file, "Split file overriding the protocol's");
  cmd->add_option("--epochs", f->epochs, "Override the config's epoch count")
      ->check(PositiveNumber);
  cmd->add_option("--stop-after", f->stop_after,
                  "Stop after this many epochs of this run (resume later)")
      ->check(PositiveNumber);
  AddLauncherOptions(cmd, &f->launch);
}

void AddLauncherOptions(CLI::App* cmd, LaunchOptions* o) {
  const char* group = "Workers (or torchrun's RANK, WORLD_SIZE, MASTER_ADDR, ... variables)";
  cmd->add_option("--nproc-per-node", o->nproc_per_node, "Worker processes on this machine")
      ->check(PositiveNumber)
      ->group(group);
  cmd->add_option("--nnodes", o->nnodes, "Machines in the run")
      ->check(PositiveNumber)
      ->group(group);
  cmd->add_option("--node-rank", o->node_rank, "This machine's index, 0..nnodes-1")->group(group);
  cmd->add_option("--master-addr", o->master_addr, "Host of node 0 (default 127.0.0.1)")
      ->group(group);
  cmd->add_option("--master-port", o->master_port, "Port of node 0 (default: a free one)")
      ->group(group);
}

bool LaunchIfRequested(const LaunchOptions& o, GlobalOptions& g) {
  if (!LaunchRequested(o)) return false;
  g.exit_code = LaunchWorkers(o, WithoutLauncherFlags(g.argv), PrintMessage);
  return true;
}

void AddJsonOption(CLI::App* cmd, std::string* destination, const std::string& what) {
  cmd->add_option("--json", *destination,
                  what + " as JSON: written to FILE, or printed on stdout with '-' or no FILE")
      ->expected(0, 1)
      ->default_str("-")
      ->type_name("[FILE]")
      ->check(OutputFile);
}

void EmitJson(const std::string& destination, const nlohmann::ordered_json& report) {
  if (destination.empty()) return;
  if (destination == "-") {
    std::printf("%s\n", OneLineJson(report).c_str());
  } else {
    WriteFileAtomically(destination, IndentedJson(report));
  }
}

}  // namespace motionfork::app
