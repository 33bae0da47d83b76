#include "eval/multimodal.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "core/error.h"
#include "io/clip_cache.h"
#include "io/file_util.h"

namespace motionfork {
namespace {

constexpr char kMagic[8] = {'M', 'F', 'M', 'M', 'S', 'E', 'T', '\0'};
constexpr uint32_t kVersion = 1;

template <typename T>
void Put(std::string* out, T v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

}  // namespace

MultimodalSets ComputeMultimodalSets(const std::vector<float>& last_poses, int dims,
                                     double threshold) {
  if (dims < 1)
    throw std::invalid_argument("multimodal sets: expected dims >= 1, got " + std::to_string(dims));
  if (last_poses.size() % dims != 0) {
    throw std::invalid_argument("multimodal sets: expected [N, " + std::to_string(dims) +
                                "] last poses, got " + std::to_string(last_poses.size()) +
                                " values (not a multiple of " + std::to_string(dims) + ")");
  }
  if (!(threshold > 0) || !std::isfinite(threshold)) {
    throw std::invalid_argument("multimodal sets: expected a threshold > 0 m, got " +
                                std::to_string(threshold));
  }
  const size_t n = last_poses.size() / dims;
  MultimodalSets sets;
  sets.offsets.reserve(n + 1);
  sets.offsets.push_back(0);
  for (size_t i = 0; i < n; ++i) {
    const float* a = last_poses.data() + i * dims;
    for (size_t j = 0; j < n; ++j) {
      const float* b = last_poses.data() + j * dims;
      double d2 = 0;
      for (int k = 0; k < dims; ++k) {
        const double d = double(a[k]) - double(b[k]);
        d2 += d * d;
      }
      if (std::sqrt(d2) < threshold) sets.members.push_back(static_cast<int32_t>(j));
    }
    sets.offsets.push_back(static_cast<int64_t>(sets.members.size()));
  }
  return sets;
}

uint64_t MultimodalCacheKey(const std::vector<float>& last_poses, int dims, double threshold) {
  std::string head = "multimodal|v" + std::to_string(kVersion) + "|" + std::to_string(dims) + "|";
  head.append(reinterpret_cast<const char*>(&threshold), sizeof(threshold));
  const uint64_t h = Fnv1a64(head);
  return Fnv1a64(std::string(reinterpret_cast<const char*>(last_poses.data()),
                             last_poses.size() * sizeof(float)),
                 h);
}

void WriteMultimodalCache(const std::string& path, uint64_t key, const MultimodalSets& sets) {
  std::string out(kMagic, sizeof(kMagic));
  Put<uint32_t>(&out, kVersion);
  Put<uint64_t>(&out, key);
  Put<uint32_t>(&out, static_cast<uint32_t>(sets.num_windows()));
  out.append(reinterpret_cast<const char*>(sets.offsets.data()),
             sets.offsets.size() * sizeof(int64_t));
  out.append(reinterpret_cast<const char*>(sets.members.data()),
             sets.members.size() * sizeof(int32_t));
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
  }
  WriteFileAtomically(path, out);
}

bool ReadMultimodalCache(const std::string& path, uint64_t key, MultimodalSets* sets) {
  *sets = MultimodalSets();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  const std::string b = ReadFileBytes(path);
  size_t pos = 0;
  auto corrupt = [&](const std::string& what) {
    return FormatError(FormatMessage(path, "byte " + std::to_string(pos),
                                     what + " (delete the file to rebuild it)"));
  };
  auto get = [&](void* dst, size_t n, const char* what) {
    if (n > b.size() - pos) {
      throw corrupt(std::string("multimodal cache is truncated: expected ") + what + " of " +
                    std::to_string(n) + " bytes, found " + std::to_string(b.size() - pos));
    }
    std::memcpy(dst, b.data() + pos, n);
    pos += n;
  };
  char magic[8];
  get(magic, 8, "the magic number");
  if (std::memcmp(magic, kMagic, 8) != 0) throw corrupt("not a multimodal-set cache");
  uint32_t version = 0;
  uint64_t stored_key = 0;
  get(&version, sizeof(version), "the version");
  if (version != kVersion) return false;
  get(&stored_key, sizeof(stored_key), "the key");
  if (stored_key != key) return false;
  uint32_t n = 0;
  get(&n, sizeof(n), "the window count");
  // Sizes are checked against the bytes left before anything is allocated for them.
  auto require = [&](uint64_t bytes, const char* what) {
    if (bytes > b.size() - pos) {
      throw corrupt(std::string("multimodal cache is truncated: expected ") + what + " of " +
                    std::to_string(bytes) + " bytes, found " + std::to_string(b.size() - pos));
    }
  };
  require((static_cast<uint64_t>(n) + 1) * sizeof(int64_t), "the set offsets");
  MultimodalSets out;
  out.offsets.resize(static_cast<size_t>(n) + 1);
  get(out.offsets.data(), out.offsets.size() * sizeof(int64_t), "the set offsets");
  if (out.offsets[0] != 0) throw corrupt("first set offset is not 0");
  for (size_t i = 0; i < n; ++i) {
    if (out.offsets[i + 1] <= out.offsets[i]) throw corrupt("set offsets do not increase");
  }
  require(static_cast<uint64_t>(out.offsets.back()) * sizeof(int32_t), "the set members");
  out.members.resize(static_cast<size_t>(out.offsets.back()));
  get(out.members.data(), out.members.size() * sizeof(int32_t), "the set members");
  if (pos != b.size()) throw corrupt("unexpected bytes after the last set");
  for (int32_t m : out.members) {
    if (m < 0 || static_cast<uint32_t>(m) >= n) throw corrupt("set member out of range");
  }
  *sets = std::move(out);
  return true;
}

}  // namespace motionfork
