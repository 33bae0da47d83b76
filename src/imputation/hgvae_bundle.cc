#include "imputation/hgvae_bundle.h"

#include <filesystem>
#include <sstream>

#include "config/hgvae_config.h"
#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

int HgvaeCoords(const HgvaeManifest& m) {
  return 3 * (static_cast<int>(m.skeleton.joint_names.size()) - 1);
}

HgvaeNet BuildHgvaeNet(const HgvaeManifest& m) {
  return HgvaeNet(m.model, HgvaeCoords(m), m.model.window, static_cast<int64_t>(m.classes.size()));
}

void SaveHgvaeBundle(const std::string& dir, const HgvaeManifest& m, HgvaeNet& net) {
  fs::create_directories(dir);
  std::ostringstream weights;
  torch::save(net, weights);
  WriteFileAtomically((fs::path(dir) / "hgvae.pt").string(), weights.str());
  WriteFileAtomically((fs::path(dir) / "hgvae.yaml").string(), FormatHgvaeManifest(m));
}

HgvaeNet LoadHgvaeBundle(const std::string& dir, HgvaeManifest* m) {
  const fs::path yaml = fs::path(dir) / "hgvae.yaml", weights = fs::path(dir) / "hgvae.pt";
  if (!fs::is_directory(dir))
    throw FormatError(FormatMessage(dir, "", "HG-VAE bundle folder not found"));
  for (const fs::path& f : {yaml, weights}) {
    if (!fs::is_regular_file(f)) {
      throw FormatError(FormatMessage(
          f.string(), "", "missing from the HG-VAE bundle (expected hgvae.yaml and hgvae.pt)"));
    }
  }
  *m = LoadHgvaeManifest(yaml.string());
  HgvaeNet net{nullptr};
  try {
    net = BuildHgvaeNet(*m);
    std::istringstream in(ReadFileBytes(weights.string()));
    torch::load(net, in);
  } catch (const c10::Error& e) {
    throw FormatError(
        FormatMessage(weights.string(), "",
                      "cannot load the weights (corrupt, or from a model with other sizes than "
                      "hgvae.yaml says): " +
                          std::string(e.what_without_backtrace())));
  }
  net->eval();
  return net;
}

}  // namespace motionfork
