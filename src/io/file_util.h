// Whole-file reading and all-or-nothing writing.
#pragma once

#include <string>
#include <string_view>

namespace motionfork {

// Reads a whole file into memory. Throws FormatError naming the file when it cannot be opened.
std::string ReadFileBytes(const std::string& path);

// Writes bytes to path through a temporary file in the same folder and a rename, so a reader
// never sees a half-written file and a failed write leaves no file behind. Throws FormatError.
void WriteFileAtomically(const std::string& path, std::string_view bytes);

}  // namespace motionfork
