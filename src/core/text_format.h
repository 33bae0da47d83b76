// Text for people: printf-style formatting into a std::string, and the number formats that the
// reports share. The libraries' *_text.h reports are built with these; apps print them.
#pragma once

#include <string>

namespace motionfork {

// std::string of printf(format, ...).
std::string StringPrintf(const char* format, ...) __attribute__((format(printf, 1, 2)));
// Appends printf(format, ...) to *out.
void StringAppendf(std::string* out, const char* format, ...) __attribute__((format(printf, 2, 3)));

// "1,234,567"
std::string WithThousands(long long n);
// "12.3 s", "4 min 05 s", "1 h 02 min"
std::string Duration(double seconds);

}  // namespace motionfork
