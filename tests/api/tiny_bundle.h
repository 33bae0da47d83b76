// Fixtures for the public API's tests: a tiny generator bundle with random weights on the Bandai
// protocol skeleton (so the shipped bandai constraint set applies), and a history for it.
#pragma once

#include <cstdint>
#include <string>

#include "core/motion.h"

namespace motionfork::testing {

// Writes DIR/model.yaml + DIR/generator.pt: protocol 'bandai' (30 Hz, 5 history -> 10 future
// frames), the skeleton of config_dir/skeletons/bandai.yaml (17 joints, parts legs and upper), a
// one-block network of width 16, weights drawn from `seed`. Untrained: its futures are not
// motion-like, but its shapes, determinism and part control are those of any bundle.
void WriteTinyBundle(const std::string& dir, const std::string& config_dir, uint64_t seed = 0);

// A walking history on the same 17 joints (the test humanoid; Bandai joint names and order).
Motion TinyBundleHistory(int frames, double fps = 30.0);

}  // namespace motionfork::testing
