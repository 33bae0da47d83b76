#include "core/text_format.h"

#include <cstdarg>
#include <cstdio>

namespace motionfork {

namespace {

void AppendV(std::string* out, const char* format, va_list args) {
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  if (n <= 0) return;
  const size_t old = out->size();
  out->resize(old + static_cast<size_t>(n) + 1);
  std::vsnprintf(&(*out)[old], static_cast<size_t>(n) + 1, format, args);
  out->resize(old + static_cast<size_t>(n));
}

}  // namespace

std::string StringPrintf(const char* format, ...) {
  std::string out;
  va_list args;
  va_start(args, format);
  AppendV(&out, format, args);
  va_end(args);
  return out;
}

void StringAppendf(std::string* out, const char* format, ...) {
  va_list args;
  va_start(args, format);
  AppendV(out, format, args);
  va_end(args);
}

std::string WithThousands(long long n) {
  std::string digits = std::to_string(n < 0 ? -n : n);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return n < 0 ? "-" + out : out;
}

std::string Duration(double seconds) {
  if (seconds < 60) return StringPrintf("%.1f s", seconds);
  if (seconds < 3600) return StringPrintf("%d min %02d s", int(seconds / 60), int(seconds) % 60);
  return StringPrintf("%d h %02d min", int(seconds / 3600), int(seconds / 60) % 60);
}

}  // namespace motionfork
