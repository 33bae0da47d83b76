#include "denoise/dvae_options.h"

#include <stdexcept>

namespace motionfork {

const char* ToString(DenoiseMode mode) { return NameOf(mode, kDenoiseModeNames); }

DenoiseMode ParseDenoiseMode(const std::string& text) {
  if (text == "optimization") return DenoiseMode::kOptimisation;  // the US spelling, not listed
  return ParseEnumName(text, kDenoiseModeNames, "denoise mode");
}

DenoiseOptions DenoiseOverrides::Apply(DenoiseOptions o) const {
  if (!mode.empty()) o.mode = ParseDenoiseMode(mode);
  if (iterations >= 0) o.iterations = iterations;
  if (samples >= 0) o.samples = samples;
  if (seed >= 0) o.seed = static_cast<uint64_t>(seed);
  if (!blend.empty()) o.fuse = blend == "fused";
  return o;
}

void ValidateDvaeOptions(const DvaeOptions& o) {
  auto fail = [](const std::string& m) { throw std::invalid_argument("dvae model: " + m); };
  if (o.window < 3 || o.window > 4096)
    fail("window: expected 3..4096 frames, got " + std::to_string(o.window));
  if (o.hidden < 1 || o.latent < 1 || o.hidden > 4096 || o.latent > 4096)
    fail("hidden and latent: expected 1..4096");
  if (o.mlp_hidden > 65536) fail("mlp_hidden: expected <= 65536");
  if (o.groups < 1 || o.mlp_hidden < o.groups || o.mlp_hidden % o.groups != 0) {
    fail("mlp_hidden (" + std::to_string(o.mlp_hidden) +
         ") must be a positive multiple of groups (" + std::to_string(o.groups) + ")");
  }
}

}  // namespace motionfork
