#include "torch_util/error_text.h"

#include <c10/util/Exception.h>

#include <cstdio>
#include <cstdlib>
#include <new>
#include <nlohmann/json.hpp>

namespace motionfork {
namespace {

// "[enforce fail at alloc_cpu.cpp:75] err == 0. X" -> "X"; "[json.exception.type_error.302] X" ->
// "X": the library's internal location is no help to a user.
std::string WithoutBracketPrefix(std::string text) {
  if (!text.empty() && text[0] == '[') {
    const size_t close = text.find("] ");
    if (close != std::string::npos) text = text.substr(close + 2);
  }
  return text;
}

// The first line only: LibTorch appends "Exception raised from ..." and frames below it.
std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

std::string TorchMessage(const c10::Error& e) {
  const std::string text = FirstLine(e.what_without_backtrace());
  const size_t asked = text.find("you tried to allocate ");
  if (text.find("can't allocate memory") != std::string::npos && asked != std::string::npos) {
    const double bytes = std::atof(text.c_str() + asked + 22);
    char buf[96];
    std::snprintf(buf, sizeof(buf), "out of memory: a tensor of %.2f GB could not be allocated",
                  bytes / 1e9);
    return buf;
  }
  std::string message = WithoutBracketPrefix(text);
  if (message.rfind("err == 0. ", 0) == 0) message = message.substr(10);
  return "LibTorch: " + message;
}

}  // namespace

std::string UserErrorMessage(const std::exception& e, const std::string& doing) {
  if (const auto* torch_error = dynamic_cast<const c10::Error*>(&e)) {
    return TorchMessage(*torch_error);
  }
  if (dynamic_cast<const std::bad_alloc*>(&e)) {
    return "out of memory while " + doing +
           " (the input or the request needs more memory than is available)";
  }
  if (dynamic_cast<const nlohmann::json::exception*>(&e)) {
    return "JSON: " + WithoutBracketPrefix(e.what());
  }
  return e.what();
}

}  // namespace motionfork
