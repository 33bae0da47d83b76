#include "bundle/bundle_upgrade.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "bundle/dvae_bundle.h"
#include "bundle/generator_net_bundle.h"
#include "bundle/hgvae_bundle.h"

namespace motionfork {

namespace fs = std::filesystem;

namespace {

bool Holds(const fs::path& dir, const char* manifest, const char* weights) {
  return fs::is_regular_file(dir / manifest) && fs::is_regular_file(dir / weights);
}

// Rewrites the bundles of one folder; appends what it rewrote to `done`.
void UpgradeFolder(const fs::path& dir, std::vector<std::string>* done) {
  const std::string d = dir.string();
  if (Holds(dir, "model.yaml", "generator.pt")) {
    ModelConfig c;
    GeneratorNet net = LoadGeneratorBundle(d, &c, BundleCheck::kLegacy);
    SaveGeneratorBundle(d, c, net);
    done->push_back(d + ": generator");
  }
  if (Holds(dir, "hgvae.yaml", "hgvae.pt")) {
    HgvaeManifest m;
    HgvaeNet net = LoadHgvaeBundle(d, &m, BundleCheck::kLegacy);
    SaveHgvaeBundle(d, m, net);
    done->push_back(d + ": HG-VAE");
  }
  if (Holds(dir, "dvae.yaml", "dvae.pt")) {
    DvaeManifest m;
    DvaeNet net = LoadDvaeBundle(d, &m, BundleCheck::kLegacy);
    SaveDvaeBundle(d, m, net);
    done->push_back(d + ": Motion-DVAE");
  }
}

}  // namespace

std::vector<std::string> UpgradeBundles(const std::string& dir) {
  if (!fs::is_directory(dir)) throw std::invalid_argument(dir + ": not a folder");
  std::vector<std::string> done;
  UpgradeFolder(dir, &done);
  std::vector<fs::path> subfolders;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.is_directory()) subfolders.push_back(e.path());
  }
  std::sort(subfolders.begin(), subfolders.end());
  for (const fs::path& sub : subfolders) UpgradeFolder(sub, &done);
  if (done.empty()) {
    throw std::invalid_argument(dir +
                                ": holds no generator, HG-VAE or Motion-DVAE bundle (model.yaml + "
                                "generator.pt, hgvae.yaml + hgvae.pt, dvae.yaml + dvae.pt)");
  }
  return done;
}

}  // namespace motionfork
