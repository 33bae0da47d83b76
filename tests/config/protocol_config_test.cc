#include "config/protocol_config.h"

#include <catch2/catch.hpp>
#include <fstream>

#include "config/config_paths.h"
#include "test_support.h"

using namespace motionfork;

namespace {
ProtocolOptions Shipped(const std::string& name) {
  return LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", name));
}
}  // namespace

TEST_CASE("shipped protocols carry the published settings") {
  const ProtocolOptions h = Shipped("h36m");
  CHECK(h.fps == 50);
  CHECK(h.t_his == 25);
  CHECK(h.t_pred == 100);
  CHECK(h.train_subjects == std::vector<std::string>{"S1", "S5", "S6", "S7", "S8"});
  CHECK(h.test_subjects == std::vector<std::string>{"S9", "S11"});
  CHECK(h.test_stride == 25);
  CHECK_FALSE(h.test_include_last);
  CHECK(h.multimodal_threshold == 0.5);
  CHECK(h.root == RootHandling::kRelativeDrop);
  CHECK(h.format == SourceFormat::kVideoPose3d);

  const ProtocolOptions e = Shipped("humaneva");
  CHECK(e.fps == 60);
  CHECK(e.t_his == 15);
  CHECK(e.t_pred == 60);
  CHECK(e.min_length == 75);
  CHECK(e.train_subjects == std::vector<std::string>{"Train/S1", "Train/S2", "Train/S3"});
  CHECK(e.test_subjects == std::vector<std::string>{"Validate/S1", "Validate/S2", "Validate/S3"});
  CHECK(e.drop_takes ==
        std::vector<std::pair<std::string, std::string>>{{"Train/S3", "Walking 1 chunk0"},
                                                         {"Train/S3", "Walking 1 chunk2"},
                                                         {"Validate/S3", "Walking 1 chunk4"}});

  const ProtocolOptions b = Shipped("bandai");
  CHECK(b.fps == 30);
  CHECK(b.t_his == 15);
  CHECK(b.t_pred == 60);
  CHECK(b.min_length == 75);
  CHECK(b.unit_scale == 0.01);
  CHECK(b.split_file == "split.tsv");
  CHECK(b.format == SourceFormat::kBvh);
  CHECK(b.published.empty());

  // The papers' tables (K = 50), GSPS's and DLow's among them.
  REQUIRE(e.published.size() == 4);
  CHECK(e.published[1].method == "GSPS");
  CHECK(e.published[1].source.find("ICCV 2021") != std::string::npos);
  CHECK(e.published[1].apd == 5.825);
  CHECK(e.published[1].mmfde == 0.331);
  REQUIRE(h.published.size() == 4);
  CHECK(h.published[0].method == "DLow");
  CHECK(h.published[0].ade == 0.425);
}

TEST_CASE("protocol configs name the broken field") {
  testing::TempDir dir;
  const std::string path = dir.file("p.yaml");
  std::ofstream(path) << "name: p\nskeleton: bandai\nsource: {format: bvh}\nfps: 30\nt_his: 0\n"
                         "t_pred: 60\nsplit: {file: s.tsv}\n";
  CHECK_THROWS_WITH(LoadProtocolConfig(path),
                    Catch::Contains("p.yaml") && Catch::Contains("t_his = 0"));
  std::ofstream(path) << "name: p\nskeleton: bandai\nsource: {format: c3d}\nfps: 30\nt_his: 1\n"
                         "t_pred: 60\n";
  CHECK_THROWS_WITH(LoadProtocolConfig(path), Catch::Contains("line 3") && Catch::Contains("c3d"));
  std::ofstream(path) << "name: p\nskeleton: bandai\nsource: {format: bvh}\nfps: fast\n";
  CHECK_THROWS_WITH(LoadProtocolConfig(path),
                    Catch::Contains("'fps'") && Catch::Contains("line 4"));
  const std::string good =
      "name: p\nskeleton: bandai\nsource: {format: bvh}\nfps: 30\nt_his: 1\n"
      "t_pred: 60\n";
  std::ofstream(path) << good << "published:\n  - {method: X, source: Y, apd: 1, ade: 0.2}\n";
  CHECK_THROWS_WITH(LoadProtocolConfig(path), Catch::Contains("line 8") && Catch::Contains("fde"));
  std::ofstream(path) << good
                      << "published:\n  - {method: X, source: Y, apd: -1, ade: 0.2, fde: 0.2, "
                         "mmade: 0.3, mmfde: 0.3}\n";
  CHECK_THROWS_WITH(LoadProtocolConfig(path), Catch::Contains("published.apd"));
}
