#include "imputation/occlusion.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>

#include "io/npy.h"

namespace motionfork {

std::vector<uint8_t> RandomOcclusion(int count, int values, double share, uint64_t seed) {
  if (!(share >= 0 && share <= 1)) {
    throw std::invalid_argument("random occlusion: expected a share in [0, 1], got " +
                                std::to_string(share));
  }
  const int k = std::min(values - 1, static_cast<int>(std::lround(share * values)));
  std::vector<uint8_t> mask(static_cast<size_t>(count) * values, 0);
  std::mt19937_64 rng(seed);
  std::vector<int> idx(values);
  for (int w = 0; w < count; ++w) {
    std::iota(idx.begin(), idx.end(), 0);
    // Partial Fisher-Yates: the first k indices are a uniform random subset.
    for (int i = 0; i < k; ++i) {
      std::uniform_int_distribution<int> pick(i, values - 1);
      std::swap(idx[i], idx[pick(rng)]);
      mask[static_cast<size_t>(w) * values + idx[i]] = 1;
    }
  }
  return mask;
}

std::vector<uint8_t> JointOcclusion(int count, int frames, int num_joints,
                                    const std::vector<int>& joints) {
  const int coords = 3 * (num_joints - 1);
  std::vector<uint8_t> mask(static_cast<size_t>(count) * frames * coords, 0);
  for (int j : joints) {
    if (j < 1 || j >= num_joints) {
      throw std::invalid_argument("joint occlusion: joint index " + std::to_string(j) +
                                  " is not a non-root joint");
    }
  }
  for (size_t f = 0; f < static_cast<size_t>(count) * frames; ++f) {
    for (int j : joints) {
      for (int a = 0; a < 3; ++a) mask[f * coords + 3 * (j - 1) + a] = 1;
    }
  }
  return mask;
}

std::vector<uint8_t> MaskFromSpec(const std::string& spec, const Skeleton& skeleton, int frames,
                                  uint64_t seed) {
  const int J = skeleton.num_joints();
  const size_t per_frame = static_cast<size_t>(J) * 3;
  std::vector<uint8_t> mask(static_cast<size_t>(frames) * per_frame, 0);
  if (spec.size() > 4 && spec.compare(spec.size() - 4, 4, ".npy") == 0) {
    const NpyArray a = ReadNpy(spec);
    const bool per_joint = a.shape.size() == 2, per_value = a.shape.size() == 3 && a.shape[2] == 3;
    if (!(per_joint || per_value) || a.shape[0] != frames || a.shape[1] != J) {
      std::string shape;
      for (int64_t d : a.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(d);
      throw std::invalid_argument("mask file " + spec + ": expected shape [" +
                                  std::to_string(frames) + ", " + std::to_string(J) + "] or [" +
                                  std::to_string(frames) + ", " + std::to_string(J) +
                                  ", 3] (frames x joints of the motion), found [" + shape + "]");
    }
    for (size_t i = 0; i < mask.size(); ++i) {
      const size_t src = per_joint ? i / 3 : i;
      mask[i] = a.data[src] != 0.0f;
    }
    for (int t = 0; t < frames; ++t) {
      if (mask[t * per_frame] || mask[t * per_frame + 1] || mask[t * per_frame + 2]) {
        throw std::invalid_argument("mask file " + spec + ": frame " + std::to_string(t) +
                                    " marks the root '" + skeleton.joint_name(0) +
                                    "' missing; it must be known (poses are root-relative)");
      }
    }
    return mask;
  }
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon),
                    arg = colon == std::string::npos ? "" : spec.substr(colon + 1);
  const std::string usage =
      " (expected random:SHARE, joints:NAME,NAME or joints:NAME,NAME@FIRST-LAST)";
  if (kind == "random") {
    double share = -1;
    try {
      size_t used = 0;
      share = std::stod(arg, &used);
      if (used != arg.size()) share = -1;
    } catch (const std::exception&) {
    }
    if (!(share >= 0 && share <= 1)) {
      throw std::invalid_argument("mask '" + spec +
                                  "': expected a share between 0 and 1 after 'random:'");
    }
    // Root values are never missing (poses are root-relative); the share applies to the others.
    const int values = frames * (J - 1) * 3;
    const std::vector<uint8_t> r = RandomOcclusion(1, values, share, seed);
    for (int t = 0; t < frames; ++t) {
      for (size_t v = 0; v < static_cast<size_t>(J - 1) * 3; ++v) {
        mask[t * per_frame + 3 + v] = r[t * (J - 1) * 3 + v];
      }
    }
    return mask;
  }
  if (kind != "joints" || arg.empty())
    throw std::invalid_argument("mask '" + spec + "': unknown form" + usage);
  const auto at = arg.find('@');
  const std::string names = arg.substr(0, at);
  int first = 0, last = frames - 1;
  if (at != std::string::npos) {
    const std::string range = arg.substr(at + 1);
    const auto dash = range.find('-');
    try {
      size_t u1 = 0, u2 = 0;
      first = std::stoi(range.substr(0, dash), &u1);
      last = dash == std::string::npos ? first : std::stoi(range.substr(dash + 1), &u2);
      if (u1 != range.substr(0, dash).size()) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::invalid_argument("mask '" + spec +
                                  "': expected frames FIRST-LAST after '@', got '" + range + "'");
    }
    if (first < 0 || last >= frames || first > last) {
      throw std::invalid_argument("mask '" + spec + "': frames " + std::to_string(first) + ".." +
                                  std::to_string(last) + " are outside the motion's frames 0.." +
                                  std::to_string(frames - 1));
    }
  }
  std::stringstream ss(names);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const auto j = skeleton.Find(name);
    if (!j) {
      std::string list;
      for (int k = 1; k < J; ++k) list += (k > 1 ? ", " : "") + skeleton.joint_name(k);
      throw std::invalid_argument("mask '" + spec + "': unknown joint '" + name + "' (skeleton '" +
                                  skeleton.name() + "' has " + list + ")");
    }
    if (*j == 0) {
      throw std::invalid_argument("mask '" + spec + "': the root '" + name +
                                  "' cannot be missing (poses are root-relative)");
    }
    for (int t = first; t <= last; ++t) {
      for (int a = 0; a < 3; ++a) mask[t * per_frame + 3 * *j + a] = 1;
    }
  }
  return mask;
}

}  // namespace motionfork
