// Where the body goes (issue 27): figures of the root's world trajectory and of the feet's contact
// with the ground, beside the protocol's root-relative figures (which they leave as they are).
//
// Frames and units: world positions in metres, [T, J, 3] a motion, root first; `up` names the
// data's up axis (axis 0-2 and its sign, rig/body_frame.h's ParseUpAxis); the ground plane is the
// other two axes.
#pragma once

#include <utility>
#include <vector>

#include "core/heading.h"  // UpAxis, GroundAxes
#include "eval/metrics.h"

namespace motionfork {

// One window's (or a mean over windows') root figures, metres; skating in metres a frame.
struct RootFigures {
  double ade = 0, fde = 0;   // RootMinDisplacement
  double final_spread = 0;   // FinalRootSpread
  double skating = 0;        // FootSkating of the predicted frames, mean over samples
  double truth_skating = 0;  // FootSkating of the ground truth's frames
  RootFigures& operator+=(const RootFigures& o);
  RootFigures operator/(double n) const;
};

// Best of K against the ground truth's root ([T, 3] world): ADE = min over samples of the mean over
// frames of the root's 3D distance, FDE = min over samples of the last frame's (as
// MinDisplacement). samples: [K, T, J, 3]. Throws std::invalid_argument for K < 1, T < 1, J < 1.
Displacement RootMinDisplacement(const float* samples, int K, int T, int J,
                                 const float* truth_root);

// The spread of where the futures end: mean over pairs of samples of the distance between their
// last root positions on the ground plane (metres; 0 when every future ends at one point, as
// zero-velocity's). Throws for K < 2.
double FinalRootSpread(const float* samples, int K, int T, int J, UpAxis up);

// Foot skating: how far feet slide while they touch the ground. A foot touches when its height
// above `ground` is below `contact_height`; each such pair of consecutive frames adds the foot's
// ground-plane displacement weighted by 2 - 2^(h / contact_height) (h the higher of its two
// heights: 1 on the floor, 0 at the contact height), and the figure is the sum over feet and frame
// pairs divided by the frame pairs (metres a frame; a real walk's planted foot scores near 0).
// frames: [T, J, 3]; feet: joint indices. Throws for T < 2, an index out of range or
// contact_height <= 0.
double FootSkating(const float* frames, int T, int J, const std::vector<int>& feet, UpAxis up,
                   double ground, double contact_height);

// The ground's height under a motion: the lowest height any of the feet reach in its frames
// ([T, J, 3]). Throws for T < 1 or no feet.
double GroundHeight(const float* frames, int T, int J, const std::vector<int>& feet, UpAxis up);

}  // namespace motionfork
