// Error types shared by every module.
//
// FormatError: the content of a file (or buffer) is not what a reader expected. Its message names
// the source (file name), the place (line, frame, byte offset), what was expected and what was
// found, so a user can fix the file without reading our code.
// std::invalid_argument: a caller passed arguments that break a documented precondition
// (sizes, ranges); the message says "expected N, got M".
#pragma once

#include <stdexcept>
#include <string>

namespace motionfork {

class FormatError : public std::runtime_error {
 public:
  explicit FormatError(const std::string& message) : std::runtime_error(message) {}
};

// "SOURCE:LOCATION: WHAT" with LOCATION omitted when empty, e.g.
// "walk.bvh:line 12: expected a number of channels (1..6), found 'seven'".
inline std::string FormatMessage(const std::string& source, const std::string& location,
                                 const std::string& what) {
  std::string out = source.empty() ? std::string("<input>") : source;
  if (!location.empty()) out += ":" + location;
  out += ": " + what;
  return out;
}

}  // namespace motionfork
