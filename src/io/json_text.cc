#include "io/json_text.h"

namespace motionfork {

namespace {

// Invalid UTF-8 (e.g. in a file name) is replaced, not thrown: the report is always written.
constexpr auto kReplaceInvalid = nlohmann::ordered_json::error_handler_t::replace;

}  // namespace

std::string OneLineJson(const nlohmann::ordered_json& j) {
  if (!j.is_structured() || j.empty()) return j.dump(-1, ' ', false, kReplaceInvalid);
  std::string out = j.is_object() ? "{" : "[";
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it != j.begin()) out += ", ";
    if (j.is_object())
      out += nlohmann::ordered_json(it.key()).dump(-1, ' ', false, kReplaceInvalid) + ": ";
    out += OneLineJson(it.value());
  }
  return out + (j.is_object() ? "}" : "]");
}

std::string IndentedJson(const nlohmann::ordered_json& j) {
  return j.dump(2, ' ', false, kReplaceInvalid) + "\n";
}

}  // namespace motionfork
