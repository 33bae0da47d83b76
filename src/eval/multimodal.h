// DLow's multimodal ground truth: for every test window, the futures of all test windows whose
// last history pose is close to its own.
//
// Window j joins window i's set when ||p_i - p_j|| < threshold (strictly, as in DLow's code:
// `pd[i] < threshold`), p the last history pose as a root-relative pose vector without the root
// (e.g. 48 numbers), metres, distance over the whole vector in double precision. Every window is
// in its own set.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace motionfork {

struct MultimodalSets {
  std::vector<int64_t> offsets;  // [N + 1]; set i is members[offsets[i], offsets[i + 1])
  std::vector<int32_t> members;  // window indices, ascending within a set

  int num_windows() const { return offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1; }
  int set_size(int i) const { return static_cast<int>(offsets[i + 1] - offsets[i]); }
  const int32_t* set(int i) const { return members.data() + offsets[i]; }
};

// last_poses: [N, D] metres. threshold: metres, > 0. Throws std::invalid_argument for a size that
// is not a multiple of D, D < 1 or a threshold <= 0.
MultimodalSets ComputeMultimodalSets(const std::vector<float>& last_poses, int dims,
                                     double threshold);

// Cache key: a hash of the threshold, D and every last pose's bytes.
uint64_t MultimodalCacheKey(const std::vector<float>& last_poses, int dims, double threshold);

// Binary cache (little-endian): "MFMMSET\0", u32 version, u64 key, u32 N, (N + 1) x i64 offsets,
// members as i32. All-or-nothing write (FormatError when the folder is not writable).
void WriteMultimodalCache(const std::string& path, uint64_t key, const MultimodalSets& sets);
// False when the file is missing or its version or key differ; FormatError when it is corrupt.
bool ReadMultimodalCache(const std::string& path, uint64_t key, MultimodalSets* sets);

}  // namespace motionfork
