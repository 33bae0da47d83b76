#include "core/motion_noise.h"

#include <stdexcept>
#include <vector>

namespace motionfork {

namespace {

std::vector<double> Numbers(const std::string& text, const std::string& list) {
  std::vector<double> out;
  size_t pos = 0;
  while (pos <= list.size()) {
    const size_t comma = list.find(',', pos);
    const std::string item =
        list.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size()) {
      throw std::invalid_argument("noise '" + text + "': '" + item + "' is not a number");
    }
    out.push_back(v);
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return out;
}

}  // namespace

NoiseSpec ParseNoiseSpec(const std::string& text) {
  const std::string forms =
      " (expected gaussian:S, outliers:P,S or jitter:S; S in metres, P in [0, 1])";
  const size_t colon = text.find(':');
  if (colon == std::string::npos)
    throw std::invalid_argument("noise '" + text + "': no ':'" + forms);
  const std::string kind = text.substr(0, colon);
  const std::vector<double> v = Numbers(text, text.substr(colon + 1));
  NoiseSpec s;
  s.text = text;
  if (kind == "gaussian" || kind == "jitter") {
    if (v.size() != 1)
      throw std::invalid_argument("noise '" + text + "': expected one number" + forms);
    s.kind = kind == "gaussian" ? NoiseSpec::Kind::kGaussian : NoiseSpec::Kind::kJitter;
    s.sigma = v[0];
  } else if (kind == "outliers") {
    if (v.size() != 2)
      throw std::invalid_argument("noise '" + text + "': expected two numbers" + forms);
    s.kind = NoiseSpec::Kind::kOutliers;
    s.rate = v[0];
    s.sigma = v[1];
    if (s.rate < 0 || s.rate > 1)
      throw std::invalid_argument("noise '" + text + "': P must be in [0, 1]" + forms);
  } else {
    throw std::invalid_argument("noise '" + text + "': unknown kind '" + kind + "'" + forms);
  }
  if (!(s.sigma >= 0) || s.sigma > 10)
    throw std::invalid_argument("noise '" + text + "': S must be in [0, 10] metres");
  return s;
}

void AddNoise(const NoiseSpec& spec, float* p, int frames, int joints, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, spec.sigma);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int t = 0; t < frames; ++t) {
    float* frame = p + static_cast<size_t>(t) * joints * 3;
    switch (spec.kind) {
      case NoiseSpec::Kind::kGaussian:
        for (int i = 0; i < joints * 3; ++i) frame[i] += static_cast<float>(normal(rng));
        break;
      case NoiseSpec::Kind::kOutliers:
        for (int j = 0; j < joints; ++j) {
          if (uniform(rng) >= spec.rate) continue;
          for (int d = 0; d < 3; ++d) frame[3 * j + d] += static_cast<float>(normal(rng));
        }
        break;
      case NoiseSpec::Kind::kJitter: {
        const double o[3] = {normal(rng), normal(rng), normal(rng)};
        for (int j = 0; j < joints; ++j) {
          for (int d = 0; d < 3; ++d) frame[3 * j + d] += static_cast<float>(o[d]);
        }
        break;
      }
    }
  }
}

Motion AddNoise(const Motion& motion, const NoiseSpec& spec, uint64_t seed) {
  std::vector<float> p = motion.positions();
  std::mt19937_64 rng(seed);
  AddNoise(spec, p.data(), motion.num_frames(), motion.num_joints(), rng);
  return Motion(motion.skeleton_ptr(), motion.fps(), std::move(p));
}

}  // namespace motionfork
