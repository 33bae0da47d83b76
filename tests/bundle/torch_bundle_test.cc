#include "bundle/torch_bundle.h"

#include <torch/torch.h>

#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "core/error.h"

namespace motionfork {
namespace {

using Catch::Contains;

const TorchBundleNames kNames{"test", "m.yaml", "w.pt"};

// Weights as a bundle written before verification had them: no manifest copy.
std::string LegacyBytes(torch::nn::Module& net) {
  std::ostringstream out;
  torch::serialize::OutputArchive archive;
  net.save(archive);
  archive.save_to(out);
  return out.str();
}

}  // namespace

TEST_CASE("verified weights load into the network their manifest describes") {
  torch::nn::Linear saved(4, 3);
  torch::nn::Linear loaded(4, 3);
  LoadVerifiedWeights(*loaded, WeightBytes(*saved, "sizes: 4 3\n"), "dir", kNames, "sizes: 4 3\n",
                      BundleCheck::kStrict);
  CHECK(torch::equal(saved->weight, loaded->weight));
  CHECK(torch::equal(saved->bias, loaded->bias));
}

TEST_CASE("an edited manifest is refused, naming the line that no longer fits") {
  torch::nn::Linear saved(4, 3);
  torch::nn::Linear loaded(4, 3);
  CHECK_THROWS_AS(LoadVerifiedWeights(*loaded, WeightBytes(*saved, "a: 1\nsizes: 4 3\n"), "dir",
                                      kNames, "a: 1\nsizes: 4 5\n", BundleCheck::kStrict),
                  FormatError);
  CHECK_THROWS_WITH(LoadVerifiedWeights(*loaded, WeightBytes(*saved, "a: 1\nsizes: 4 3\n"), "dir",
                                        kNames, "a: 1\nsizes: 4 5\n", BundleCheck::kStrict),
                    Contains("m.yaml") && Contains("'sizes: 4 5'") && Contains("'sizes: 4 3'"));
}

TEST_CASE("weights without a manifest copy: refused strictly, shape-checked when upgrading") {
  torch::nn::Linear saved(4, 3);
  const std::string legacy = LegacyBytes(*saved);
  torch::nn::Linear same(4, 3);
  CHECK_THROWS_WITH(LoadVerifiedWeights(*same, legacy, "dir", kNames, "s", BundleCheck::kStrict),
                    Contains("w.pt") && Contains("bundle upgrade"));
  LoadVerifiedWeights(*same, legacy, "dir", kNames, "s", BundleCheck::kLegacy);
  CHECK(torch::equal(saved->weight, same->weight));

  torch::nn::Linear wider(4, 5);  // the manifest says 5 outputs, the file holds 3
  CHECK_THROWS_WITH(
      LoadVerifiedWeights(*wider, legacy, "dir", kNames, "s", BundleCheck::kLegacy),
      Contains("tensor 'bias'") && Contains("expected shape [5]") && Contains("found [3]"));

  torch::nn::Linear no_bias(torch::nn::LinearOptions(4, 3).bias(false));  // fewer tensors
  CHECK_THROWS_WITH(LoadVerifiedWeights(*no_bias, legacy, "dir", kNames, "s", BundleCheck::kLegacy),
                    Contains("'bias'") && Contains("does not describe"));
}

TEST_CASE("bytes that are not a LibTorch file are refused with the file's name, no stack trace") {
  torch::nn::Linear net(4, 3);
  try {
    LoadVerifiedWeights(*net, "not a zip archive", "dir", kNames, "s", BundleCheck::kStrict);
    FAIL("loaded");
  } catch (const FormatError& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Contains("w.pt") && Contains("cannot read the weights"));
    CHECK(what.find("frame #") == std::string::npos);
  }
}

}  // namespace motionfork
