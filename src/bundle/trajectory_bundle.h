// Trajectory bundles (issue 27): a generator bundle's trajectory/ folder, trajectory.yaml (the
// network's options, the protocol it was trained for, checksums, provenance) and trajectory.pt,
// saved and loaded through the one verified LibTorch path (torch_bundle.h). LoadForecaster
// (generator_bundle.h) attaches one when the generator bundle has it.
#pragma once

#include <map>
#include <string>

#include "bundle/bundle_files.h"
#include "generator/trajectory/trajectory_net.h"

namespace motionfork {

struct TrajectoryManifest {
  std::string format = kTrajectoryBundleFormat;
  std::string protocol;
  double fps = 0;
  TrajectoryOptions options;
  std::map<std::string, std::string> info;  // provenance (config, epochs, validation figures)
};

constexpr const char* kTrajectoryFolder = "trajectory";

TrajectoryManifest LoadTrajectoryManifest(const std::string& path,
                                          BundleChecksums* checksums = nullptr);
std::string FormatTrajectoryManifest(const TrajectoryManifest& m,
                                     const BundleChecksums& checksums = {});

// DIR/trajectory.yaml and DIR/trajectory.pt, all-or-nothing.
void SaveTrajectoryBundle(const std::string& dir, const TrajectoryManifest& m, TrajectoryNet& net);
// Throws FormatError naming the file and what is wrong.
TrajectoryNet LoadTrajectoryBundle(const std::string& dir, TrajectoryManifest* m);

}  // namespace motionfork
