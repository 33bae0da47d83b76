// The one translation of exceptions into what a user reads (apps/motionfork's error path): the
// project's own messages as they are; LibTorch errors without their C++ stack frames; running out
// of memory and JSON library errors as sentences.
#pragma once

#include <exception>
#include <string>

namespace motionfork {

// `doing` says what was running (e.g. "running 'motionfork predict'"), for an out-of-memory error
// that does not say it itself.
std::string UserErrorMessage(const std::exception& e, const std::string& doing);

}  // namespace motionfork
