// Binary clip cache: a parsed dataset saved once so later runs skip parsing.
//
// Layout (little-endian): "MFCLIPS\0", u32 version, u64 key, u32 #skeletons, skeletons
// (name, u32 J, J x (name, i32 parent)), u32 #clips, clips (name, group, subject, action,
// u32 skeleton index, f64 fps, u32 frames, frames*J*3 f32 metres). Strings are u32 length + bytes.
// The key (a hash of the source files' names, sizes and modification times plus the reading
// options) tells a stale cache from a fresh one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/motion.h"

namespace motionfork {

struct CachedClip {
  std::string name;     // clip name (file name without extension, or subject/action)
  std::string group;    // where it came from (archive or folder)
  std::string subject;  // may be empty
  std::string action;   // may be empty
  Motion motion;
};

// All-or-nothing write. Clips sharing a skeleton structure store it once.
void WriteClipCache(const std::string& path, uint64_t key, const std::vector<CachedClip>& clips);

// Returns false (and leaves clips empty) when the file is missing or its key or version differ;
// throws FormatError when the file is corrupt.
bool ReadClipCache(const std::string& path, uint64_t key, std::vector<CachedClip>* clips);

// 64-bit FNV-1a, for cache keys.
uint64_t Fnv1a64(const std::string& text, uint64_t seed = 1469598103934665603ull);

}  // namespace motionfork
