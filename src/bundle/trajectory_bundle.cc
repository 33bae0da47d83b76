#include "bundle/trajectory_bundle.h"

#include <filesystem>
#include <stdexcept>

#include "bundle/manifest.h"
#include "bundle/torch_bundle.h"
#include "config/yaml_util.h"
#include "core/error.h"
#include "core/heading.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::WithFormatErrors;

namespace {

TrajectoryManifest ParseTrajectoryManifest(const std::string& path, const YAML::Node& root,
                                           BundleChecksums* checksums) {
  TrajectoryManifest m;
  ManifestHeader h = ParseManifestHeader(path, root, kTrajectoryBundleFormat,
                                         {/*protocol=*/true, /*skeleton=*/false});
  m.format = h.format;
  m.protocol = h.protocol;
  m.fps = h.fps;
  if (checksums) *checksums = std::move(h.checksums);
  const YAML::Node n = root["network"];
  if (!n) Fail(path, root, "missing mapping 'network'");
  TrajectoryOptions& o = m.options;
  o.t_his = Get<int>(path, n, "t_his");
  o.t_pred = Get<int>(path, n, "t_pred");
  o.num_nodes = Get<int>(path, n, "num_nodes");
  o.future_nodes = Get<std::vector<int64_t>>(path, n, "future_nodes");
  o.n_in = Get<int>(path, n, "n_in");
  o.n_out = Get<int>(path, n, "n_out");
  o.hidden = Get<int>(path, n, "hidden");
  o.layers = Get<int>(path, n, "layers");
  o.up = Get<std::string>(path, n, "up");
  try {
    ParseUp(o.up);
    ValidateTrajectoryOptions(o);
  } catch (const std::invalid_argument& e) {
    Fail(path, n, e.what());
  }
  for (auto& [k, v] : ParseManifestInfo(root)) m.info[k] = std::move(v);
  return m;
}

}  // namespace

TrajectoryManifest LoadTrajectoryManifest(const std::string& path, BundleChecksums* checksums) {
  const YAML::Node root = LoadManifestFile(path);
  return WithFormatErrors(path, [&] { return ParseTrajectoryManifest(path, root, checksums); });
}

std::string FormatTrajectoryManifest(const TrajectoryManifest& m,
                                     const BundleChecksums& checksums) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  EmitManifestFormat(out, {m.format, m.protocol, m.fps, {}, {}});
  const TrajectoryOptions& o = m.options;
  out << YAML::Key << "network" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "t_his" << YAML::Value << o.t_his;
  out << YAML::Key << "t_pred" << YAML::Value << o.t_pred;
  out << YAML::Key << "num_nodes" << YAML::Value << o.num_nodes;
  out << YAML::Key << "future_nodes" << YAML::Value << YAML::Flow << o.future_nodes;
  out << YAML::Key << "n_in" << YAML::Value << o.n_in;
  out << YAML::Key << "n_out" << YAML::Value << o.n_out;
  out << YAML::Key << "hidden" << YAML::Value << o.hidden;
  out << YAML::Key << "layers" << YAML::Value << o.layers;
  out << YAML::Key << "up" << YAML::Value << o.up;
  out << YAML::EndMap;
  EmitManifestChecksums(out, checksums);
  EmitManifestInfo(out, {m.info.begin(), m.info.end()});
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

namespace {

constexpr TorchBundleNames kTrajectoryFiles{"trajectory", "trajectory.yaml", "trajectory.pt"};

std::string TrajectorySignature(const TrajectoryManifest& m) {
  TrajectoryManifest s = m;
  s.info.clear();
  return FormatTrajectoryManifest(s);
}

}  // namespace

void SaveTrajectoryBundle(const std::string& dir, const TrajectoryManifest& m, TrajectoryNet& net) {
  SaveTorchBundle(dir, kTrajectoryFiles, m, net, FormatTrajectoryManifest, TrajectorySignature);
}

TrajectoryNet LoadTrajectoryBundle(const std::string& dir, TrajectoryManifest* m) {
  return LoadTorchBundle(
      dir, kTrajectoryFiles, m, LoadTrajectoryManifest,
      [](const TrajectoryManifest& t) { return TrajectoryNet(t.options); }, TrajectorySignature);
}

}  // namespace motionfork
