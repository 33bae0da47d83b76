// The known name closest to a mistyped one ("predcit" -> "predict"), for "did you mean ...?"
// messages.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace motionfork {

// Optimal-string-alignment distance: insertions, deletions, substitutions and swaps of two
// neighbours ("predcit") each count one.
size_t EditDistance(const std::string& a, const std::string& b);

// The candidate closest to `word` by edit distance when it is close enough to be a typo (at most
// 2 edits, and fewer than half its length), else "".
std::string ClosestName(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace motionfork
