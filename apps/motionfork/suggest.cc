#include "suggest.h"

#include <algorithm>
#include <vector>

#include "core/closest_name.h"

namespace motionfork::app {
namespace {

// Every long option name of `cmd` and of its parents (global options are accepted anywhere).
std::vector<std::string> LongOptions(const CLI::App* cmd) {
  std::vector<std::string> names;
  for (; cmd; cmd = cmd->get_parent()) {
    for (const CLI::Option* o : cmd->get_options()) {
      for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
    }
  }
  return names;
}

// Global options that take a value (their value is not a subcommand name).
bool TakesValue(const CLI::App* cmd, const std::string& arg) {
  for (; cmd; cmd = cmd->get_parent()) {
    for (const CLI::Option* o : cmd->get_options()) {
      if (o->get_type_size() != 0 && o->check_name(arg)) return true;
    }
  }
  return false;
}

}  // namespace

std::string SuggestFix(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* cmd = &app;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    if (arg.rfind("--", 0) == 0) {
      const std::string name = arg.substr(0, arg.find('='));
      const std::vector<std::string> known = LongOptions(cmd);
      if (std::find(known.begin(), known.end(), name) == known.end()) {
        const std::string close = ClosestName(name, known);
        if (!close.empty()) return "unknown option '" + name + "'; did you mean '" + close + "'?";
        return "";
      }
      if (arg.find('=') == std::string::npos && TakesValue(cmd, name)) ++i;  // skip its value
      continue;
    }
    if (arg[0] == '-') continue;
    std::vector<std::string> names;
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : cmd->get_subcommands({})) {
      names.push_back(sub->get_name());
      if (sub->get_name() == arg) next = sub;
    }
    if (next) {
      cmd = next;
      continue;
    }
    if (names.empty()) continue;  // a positional argument of a leaf subcommand
    const std::string close = ClosestName(arg, names);
    if (!close.empty()) {
      return "unknown command '" + arg + "'; did you mean '" + close + "'?";
    }
    return "";
  }
  return "";
}

}  // namespace motionfork::app
