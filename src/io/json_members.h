// Members of a struct into a JSON object under their own names, in the order written, for reports
// that name their fields as the struct does. nlohmann's NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE does the
// same for nlohmann::json only, whose keys come out sorted; reports use nlohmann::ordered_json so
// that a reader sees them in the order they are documented.
//
//   MOTIONFORK_JSON_MEMBERS(j, figures, windows, apd, ade);  // j["windows"] = figures.windows ...
#pragma once

#include <nlohmann/json.hpp>

#define MOTIONFORK_JSON_MEMBER(member) motionfork_json_out[#member] = motionfork_json_in.member;
#define MOTIONFORK_JSON_MEMBERS(json_object, object, ...)                          \
  do {                                                                             \
    auto& motionfork_json_out = (json_object);                                     \
    const auto& motionfork_json_in = (object);                                     \
    NLOHMANN_JSON_EXPAND(NLOHMANN_JSON_PASTE(MOTIONFORK_JSON_MEMBER, __VA_ARGS__)) \
  } while (false)
