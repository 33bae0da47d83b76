#include "flags.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "io/file_util.h"

namespace motionfork::app {

void NoteDeprecated(const std::string& old_spelling, const std::string& new_spelling) {
  std::fprintf(stderr,
               "motionfork: note: %s is deprecated, write %s instead (the old spelling goes away "
               "in the next release)\n",
               old_spelling.c_str(), new_spelling.c_str());
}

void AddMotionArgument(CLI::App* cmd, std::string* path, const std::string& help,
                       const std::string& old_flag) {
  cmd->add_option("MOTION", *path, help)->check(CLI::ExistingFile);
  if (!old_flag.empty()) {
    AddDeprecatedOption(cmd, old_flag, "the motion file as the first argument", path);
  }
}

void RequireMotion(const std::string& path) {
  RequireArgument(path, "MOTION (the motion file, first argument)");
}

void RequireArgument(const std::string& value, const std::string& name) {
  if (value.empty()) throw CLI::RequiredError(name);
}

CLI::Option* AddInputFile(CLI::App* cmd, const std::string& name, std::string* path,
                          const std::string& help) {
  return cmd->add_option(name, *path, help)->required()->check(CLI::ExistingFile);
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
  return cmd->add_option("-o,--out", *path, help)->required();
}

void AddThreadsOption(CLI::App* cmd, int* threads) {
  cmd->add_option("--threads", *threads, "Threads (default 1)")->check(CLI::PositiveNumber);
}

void AddForecasterOptions(CLI::App* cmd, std::string* forecaster, int* windows, int* k,
                          const std::string& windows_help) {
  cmd->add_option("--forecaster", *forecaster,
                  "Generator bundle for the downstream figures (e.g. models/bandai)");
  cmd->add_option("--forecast-windows", *windows, windows_help)->check(CLI::PositiveNumber);
  cmd->add_option("-k", *k, "Futures per history (default 50)")->check(CLI::PositiveNumber);
}

void AddTrainingRunOptions(CLI::App* cmd, TrainingRunFlags* f, const std::string& out_help) {
  AddDataOption(cmd, &f->data, "Data folder of the config's protocol");
  cmd->add_option("--out", f->out, out_help)->required();
  cmd->add_option("--split", f->split_file, "Split file overriding the protocol's");
  cmd->add_option("--epochs", f->epochs, "Override the config's epoch count")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stop-after", f->stop_after,
                  "Stop after this many epochs of this run (resume later)")
      ->check(CLI::PositiveNumber);
}

void AddJsonOption(CLI::App* cmd, std::string* destination, const std::string& what) {
  cmd->add_option("--json", *destination,
                  what + " as JSON: written to FILE, or printed on stdout with '-' or no FILE")
      ->expected(0, 1)
      ->default_str("-")
      ->type_name("[FILE]");
}

namespace {

// One line, with ", " and ": " between items (as the commands printed JSON before nlohmann).
std::string OneLine(const nlohmann::ordered_json& j) {
  if (!j.is_structured() || j.empty()) return j.dump();
  std::string out = j.is_object() ? "{" : "[";
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it != j.begin()) out += ", ";
    if (j.is_object()) out += nlohmann::ordered_json(it.key()).dump() + ": ";
    out += OneLine(it.value());
  }
  return out + (j.is_object() ? "}" : "]");
}

}  // namespace

void EmitJson(const std::string& destination, const nlohmann::ordered_json& report) {
  if (destination.empty()) return;
  if (destination == "-") {
    std::printf("%s\n", OneLine(report).c_str());
  } else {
    WriteFileAtomically(destination, report.dump(2) + "\n");
  }
}

}  // namespace motionfork::app
