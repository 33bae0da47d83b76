// Split files: "split<TAB>clip file name" per line, '#' comments (e.g. Bandai's split.tsv).
#pragma once

#include <map>
#include <string>

namespace motionfork {

// Clip name (file name without extension) -> split ("train" or "test"). Throws FormatError
// naming the line for a malformed row, an unknown split name or a clip listed twice.
std::map<std::string, std::string> ReadSplitFile(const std::string& path);

}  // namespace motionfork
