// "Did you mean ...?" for mistyped subcommands and options, as git and cargo answer.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace motionfork::app {

// When argv names an unknown subcommand (at any level) or an unknown --option of the subcommand it
// follows, a message naming it and the closest known name; "" when nothing looks mistyped.
std::string SuggestFix(const CLI::App& app, int argc, const char* const* argv);

}  // namespace motionfork::app
