#include "denoise/dvae_bundle.h"

#include <filesystem>
#include <sstream>

#include "config/dvae_config.h"
#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

int DvaeValues(const DvaeManifest& m) {
  return 3 * static_cast<int>(m.skeleton.joint_names.size());
}

DvaeNet BuildDvaeNet(const DvaeManifest& m) { return DvaeNet(m.model, DvaeValues(m)); }

void SaveDvaeBundle(const std::string& dir, const DvaeManifest& m, DvaeNet& net) {
  fs::create_directories(dir);
  std::ostringstream weights;
  torch::save(net, weights);
  WriteFileAtomically((fs::path(dir) / "dvae.pt").string(), weights.str());
  WriteFileAtomically((fs::path(dir) / "dvae.yaml").string(), FormatDvaeManifest(m));
}

DvaeNet LoadDvaeBundle(const std::string& dir, DvaeManifest* m) {
  const fs::path yaml = fs::path(dir) / "dvae.yaml", weights = fs::path(dir) / "dvae.pt";
  if (!fs::is_directory(dir))
    throw FormatError(FormatMessage(dir, "", "Motion-DVAE bundle folder not found"));
  for (const fs::path& f : {yaml, weights}) {
    if (!fs::is_regular_file(f)) {
      throw FormatError(FormatMessage(
          f.string(), "", "missing from the Motion-DVAE bundle (expected dvae.yaml and dvae.pt)"));
    }
  }
  *m = LoadDvaeManifest(yaml.string());
  DvaeNet net{nullptr};
  try {
    net = BuildDvaeNet(*m);
    std::istringstream in(ReadFileBytes(weights.string()));
    torch::load(net, in);
  } catch (const c10::Error& e) {
    throw FormatError(
        FormatMessage(weights.string(), "",
                      "cannot load the weights (corrupt, or from a model with other sizes than "
                      "dvae.yaml says): " +
                          std::string(e.what_without_backtrace())));
  }
  net->eval();
  return net;
}

}  // namespace motionfork
