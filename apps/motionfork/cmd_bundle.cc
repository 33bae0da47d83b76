// motionfork bundle upgrade DIR: rewrites bundles written before motionfork verified its bundles.
#include <cstdio>

#include "bundle/bundle_upgrade.h"
#include "commands.h"
#include "flags.h"

namespace motionfork::app {
namespace {

struct UpgradeOptions {
  std::string dir;
};

void RunUpgrade(const UpgradeOptions& o, const GlobalOptions&) {
  for (const std::string& line : UpgradeBundles(o.dir)) std::printf("rewrote %s\n", line.c_str());
}

}  // namespace

void AddBundleCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* bundle = app.add_subcommand("bundle", "Model bundles on disk");
  bundle->require_subcommand(1);
  const auto [cmd, o] = AddSubcommand<UpgradeOptions>(
      bundle, global, RunUpgrade, "upgrade",
      R"(Rewrite the generator, HG-VAE and Motion-DVAE bundles in DIR and its subfolders that were
written before motionfork verified bundles: the same weights and settings, now with the weights'
checksum in the manifest and the manifest's sizes in the weights, so that a damaged or edited
bundle is refused on load. Each bundle's tensors are checked against its manifest first.)");
  cmd->add_option("DIR", o->dir, "Bundle folder (e.g. a model folder with hgvae/ and dvae/)")
      ->required()
      ->check(CLI::ExistingDirectory);
}

}  // namespace motionfork::app
