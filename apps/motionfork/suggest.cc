#include "suggest.h"

#include <algorithm>

namespace motionfork::app {
namespace {

// Optimal-string-alignment distance: insertions, deletions, substitutions and swaps of two
// neighbours ("predcit") each count one.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1] ? 1 : 0)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

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

std::string ClosestName(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = 3;  // at most 2 edits
  for (const std::string& c : candidates) {
    const size_t d = EditDistance(word, c);
    if (d < best_distance && 2 * d < word.size()) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

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
