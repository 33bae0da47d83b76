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
