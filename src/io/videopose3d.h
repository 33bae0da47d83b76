// Human3.6M / HumanEva-I as exported by VideoPose3D (data_3d_h36m.npz, data_3d_humaneva15.npz),
// after conversion by tools/videopose3d_to_motionfork.py into a plain layout:
//
//   OUT/manifest.tsv         header "subject<TAB>action<TAB>frames<TAB>joints<TAB>fps<TAB>file",
//                            then one row per take; file is relative to OUT
//   OUT/<subject>/<action>.npy   float32 [T, J, 3], metres, as stored in the npz
//
// Subjects keep their npz names ("S1", "Train/S1"), actions too ("Walking 1 chunk0").
#pragma once

#include <string>
#include <vector>

namespace motionfork {

struct VideoPose3dTake {
  std::string subject;
  std::string action;
  int frames = 0;
  int joints = 0;
  double fps = 0;
  std::string path;  // absolute or relative to the working directory
};

// Reads DIR/manifest.tsv. Throws FormatError naming the manifest line on malformed rows.
std::vector<VideoPose3dTake> ReadVideoPose3dManifest(const std::string& dir);

}  // namespace motionfork
