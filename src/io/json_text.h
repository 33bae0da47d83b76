// JSON reports as text: on one line (what the commands print for `--json -`) or indented (what they
// write to a file). Invalid UTF-8 (e.g. in a file name) is replaced by U+FFFD, never thrown.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace motionfork {

// One line, with ", " and ": " between items (as the commands printed JSON before nlohmann).
// Strings are escaped by nlohmann (a newline in a file name prints as \n).
std::string OneLineJson(const nlohmann::ordered_json& j);

// Indented by 2, with a final newline.
std::string IndentedJson(const nlohmann::ordered_json& j);

}  // namespace motionfork
