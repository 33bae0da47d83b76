#include "bundle/hgvae_bundle.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bundle/manifest.h"
#include "bundle/protocol_manifest.h"
#include "bundle/refiner_yaml.h"
#include "bundle/torch_bundle.h"
#include "bundle/train_config_keys.h"
#include "config/skeleton_yaml.h"
#include "config/yaml_util.h"
#include "core/error.h"
#include "imputation/refiner_fills.h"
#include "io/file_util.h"

namespace motionfork {

namespace {

using yaml_util::CheckKeys;
using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;
using yaml_util::Section;
using yaml_util::WithFormatErrors;

std::vector<HgvaeLevel> ParseLevels(const std::string& file, const YAML::Node& n) {
  if (!n.IsSequence()) Fail(file, n, "key 'levels' must be a list of [nodes, features] pairs");
  std::vector<HgvaeLevel> out;
  for (const YAML::Node& e : n) {
    if (!e.IsSequence() || e.size() != 2) Fail(file, e, "each level must be [nodes, features]");
    try {
      out.push_back({e[0].as<int>(), e[1].as<int>()});
    } catch (const YAML::Exception&) {
      Fail(file, e, "each level must be two integers [nodes, features]");
    }
  }
  return out;
}

void ParseModel(const std::string& file, const YAML::Node& n, HgvaeOptions* o) {
  CheckKeys(file, n, "model",
            {"levels", "width", "encoder_blocks", "decoder_blocks", "stochastic_levels", "window",
             "label_dropout", "predicted_variance"});
  if (n["levels"]) o->levels = ParseLevels(file, n["levels"]);
  o->width = GetOr<int>(file, n, "width", o->width);
  o->encoder_blocks = GetOr<int>(file, n, "encoder_blocks", o->encoder_blocks);
  o->decoder_blocks = GetOr<int>(file, n, "decoder_blocks", o->decoder_blocks);
  o->stochastic_levels = GetOr<int>(file, n, "stochastic_levels", o->stochastic_levels);
  o->window = GetOr<int>(file, n, "window", o->window);
  o->label_dropout = GetOr<double>(file, n, "label_dropout", o->label_dropout);
  o->predicted_variance = GetOr<bool>(file, n, "predicted_variance", o->predicted_variance);
}

void ParseImpute(const std::string& file, const YAML::Node& n, ImputeOptions* o) {
  CheckKeys(file, n, "impute", {"steps", "learning_rate", "objective", "start"});
  o->steps = GetOr<int>(file, n, "steps", o->steps);
  o->learning_rate = GetOr<double>(file, n, "learning_rate", o->learning_rate);
  if (n["objective"]) {
    try {
      o->objective = ParseImputeObjective(Get<std::string>(file, n, "objective"));
    } catch (const std::invalid_argument& e) {
      Fail(file, n["objective"], e.what());
    }
  }
  if (n["start"]) {
    try {
      o->start = ParseImputeStart(Get<std::string>(file, n, "start"));
    } catch (const std::invalid_argument& e) {
      Fail(file, n["start"], e.what());
    }
  }
  if (o->steps < 0 || !(o->learning_rate > 0))
    Fail(file, n, "impute: expected steps >= 0 and learning_rate > 0");
}

// refiner_weights and refiner_local_weights: [kRefinerGapBuckets finite numbers] (absent: none;
// the first >= 0), refiner_keep_bones: a bool (absent: false), refiner_adapt_values: a finite
// number >= 0 or kRefinerGapLengths of them (absent: 0); only with a refiner.
void ParseRefinerCalibration(const std::string& file, const YAML::Node& root, HgvaeManifest* m) {
  for (const char* key : {"refiner_weights", "refiner_local_weights", "refiner_keep_bones",
                          "refiner_adapt_values", "refiner_smooth", "refiner_gaussian"}) {
    if (root[key] && !m->refiner.enabled())
      Fail(file, root[key], std::string(key) + ": expected a refiner, found none");
  }
  auto weights = [&](const char* key, bool nonnegative, std::vector<double>* out) {
    const YAML::Node n = root[key];
    if (!n) return;
    *out = Get<std::vector<double>>(file, root, key);
    bool valid = out->size() == size_t{kRefinerGapBuckets};
    for (double w : *out) valid = valid && std::isfinite(w) && (!nonnegative || w >= 0);
    if (!valid) {
      Fail(file, n,
           std::string(key) + ": expected " + std::to_string(kRefinerGapBuckets) +
               " finite numbers" + (nonnegative ? " >= 0" : "") + ", found " +
               std::to_string(out->size()) + " numbers");
    }
  };
  weights("refiner_weights", true, &m->refiner_weights);
  weights("refiner_local_weights", false, &m->refiner_local_weights);
  if (root["refiner_keep_bones"])
    m->refiner_keep_bones = Get<bool>(file, root, "refiner_keep_bones");
  if (const YAML::Node n = root["refiner_adapt_values"]) {
    m->refiner_adapt_values =
        n.IsSequence() ? Get<std::vector<double>>(file, root, "refiner_adapt_values")
                       : std::vector<double>{Get<double>(file, root, "refiner_adapt_values")};
    const std::vector<double>& v = m->refiner_adapt_values;
    if (!(v.size() == 1 || v.size() == size_t{kRefinerGapLengths}) ||
        !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x) && x >= 0; })) {
      Fail(file, n,
           "refiner_adapt_values: expected a finite number >= 0 or " +
               std::to_string(kRefinerGapLengths) + " of them (one per gap length), found " +
               (v.size() == 1 ? std::to_string(v[0]) : std::to_string(v.size()) + " numbers"));
    }
  }
  if (const YAML::Node n = root["refiner_smooth"]) {
    if (!n.IsMap()) Fail(file, n, "refiner_smooth: expected a map {bracketed, one_sided}");
    for (const auto& kv : n) {
      const std::string key = kv.first.as<std::string>();
      if (key != "bracketed" && key != "one_sided")
        Fail(file, kv.first,
             "refiner_smooth: unknown key '" + key + "'; expected bracketed, one_sided");
    }
    FillSmoothing& s = m->refiner_smoothing;
    s.bracketed = n["bracketed"] ? Get<double>(file, n, "bracketed") : 0.0;
    s.one_sided = n["one_sided"] ? Get<double>(file, n, "one_sided") : 0.0;
    for (const double x : {s.bracketed, s.one_sided}) {
      if (!std::isfinite(x) || x < 0)
        Fail(file, n, "refiner_smooth: expected finite numbers >= 0, found " + std::to_string(x));
    }
  }
  if (const YAML::Node n = root["refiner_gaussian"]) {
    CheckKeys(file, n, "refiner_gaussian", {"file", "frames", "coords", "windows", "scope"});
    HgvaeManifest::GaussianStage& o = m->refiner_gaussian;
    o.file = Get<std::string>(file, n, "file");
    o.frames = Get<int>(file, n, "frames");
    o.coords = Get<int>(file, n, "coords");
    o.windows = Get<long long>(file, n, "windows");
    try {
      o.scope = ParseGaussianScope(GetOr<std::string>(file, n, "scope", "one_sided"));
    } catch (const std::invalid_argument& e) {
      Fail(file, n["scope"], e.what());
    }
    if (o.file.empty() || o.file.find('/') != std::string::npos || o.frames <= 0 ||
        o.frames > 256 || o.coords <= 0 || o.coords > 3 * 256 || o.windows < 2) {
      Fail(file, n,
           "refiner_gaussian: expected a file name inside the bundle, frames 1-256, coords "
           "1-768 and windows >= 2, found '" +
               o.file + "', " + std::to_string(o.frames) + ", " + std::to_string(o.coords) + ", " +
               std::to_string(o.windows));
    }
  }
}

void EmitImpute(YAML::Emitter& out, const ImputeOptions& o) {
  // The start only when it is not the mean: bundles from before it existed re-emit as written
  // (their weights hold a copy of the manifest, which a load compares).
  out << YAML::Key << "impute" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "steps" << YAML::Value << o.steps << YAML::Key << "learning_rate"
      << YAML::Value << o.learning_rate << YAML::Key << "objective" << YAML::Value
      << ToString(o.objective);
  if (o.start != ImputeStart::kMean)
    out << YAML::Key << "start" << YAML::Value << ToString(o.start);
  out << YAML::EndMap;
}

void EmitModel(YAML::Emitter& out, const HgvaeOptions& o) {
  out << YAML::Key << "model" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "levels" << YAML::Value << YAML::BeginSeq;
  for (const HgvaeLevel& l : o.levels)
    out << YAML::Flow << YAML::BeginSeq << l.nodes << l.features << YAML::EndSeq;
  out << YAML::EndSeq;
  yaml_util::EmitPairs(out, "width", o.width, "encoder_blocks", o.encoder_blocks, "decoder_blocks",
                       o.decoder_blocks, "stochastic_levels", o.stochastic_levels, "window",
                       o.window, "label_dropout", o.label_dropout, "predicted_variance",
                       o.predicted_variance);
  out << YAML::EndMap;
}

void EmitOod(YAML::Emitter& out, const HgvaeManifest& m) {
  yaml_util::EmitMap(out, "ood", "score", ToString(m.ood_score), "score_mean", m.score_mean,
                     "score_std", m.score_std, "k", m.ood_k);
}

HgvaeTrainConfig ParseTrainRoot(const std::string& file, const YAML::Node& root) {
  return WithFormatErrors(file, [&] {
    CheckKeys(file, root, "",
              {"name", "protocol", "model", "training", "impute", "ood", "refiner"});
    HgvaeTrainConfig c;
    ReadTrainConfigHeader(file, root, &c);
    ParseModel(file, Section(file, root, "model", false), &c.model);
    ValidateHgvaeOptions(c.model, 0);
    const YAML::Node t = Section(file, root, "training", false);
    CheckKeys(
        file, t, "training",
        WithEpochLoopKeys({"kl_warmup_epochs", "condition", "held_out_share", "held_out_windows"}));
    HgvaeTrainOptions& o = c.training;
    ReadEpochLoopKeys(file, t, &o);
    o.kl_warmup_epochs = GetOr<int>(file, t, "kl_warmup_epochs", o.kl_warmup_epochs);
    o.condition = GetOr<std::string>(file, t, "condition", o.condition);
    o.held_out_share = GetOr<double>(file, t, "held_out_share", o.held_out_share);
    o.held_out_windows = GetOr<int>(file, t, "held_out_windows", o.held_out_windows);
    if (o.epochs < 1 || o.batch_size < 1 || o.windows_per_epoch < o.batch_size ||
        !(o.learning_rate > 0) || o.kl_warmup_epochs < 0 || o.threads < 1 ||
        !(o.held_out_share > 0 && o.held_out_share < 1)) {
      Fail(file, t,
           "training: expected epochs >= 1, batch_size >= 1, windows_per_epoch >= batch_size, "
           "learning_rate > 0, "
           "kl_warmup_epochs >= 0, threads >= 1, 0 < held_out_share < 1");
    }
    if (!o.condition.empty() && o.condition != "action") {
      Fail(file, t["condition"],
           "training.condition: expected '' (none) or 'action', got '" + o.condition + "'");
    }
    ParseImpute(file, Section(file, root, "impute", false), &c.impute);
    const YAML::Node ood = Section(file, root, "ood", false);
    CheckKeys(file, ood, "ood", {"k", "score"});
    c.ood_k = GetOr<double>(file, ood, "k", c.ood_k);
    c.ood_score =
        ParseImputeObjective(GetOr<std::string>(file, ood, "score", ToString(c.ood_score)));
    const YAML::Node r = Section(file, root, "refiner", false);
    std::set<std::string> keys = RefinerModelKeys();
    keys.insert(RefinerTrainKeys().begin(), RefinerTrainKeys().end());
    CheckKeys(file, r, "refiner", keys);
    ParseRefinerModel(file, r, &c.refiner.model);
    ParseRefinerTraining(file, r, &c.refiner.training);
    if (!c.refiner.model.enabled()) Fail(file, r, "refiner: expected channels >= 1");
    return c;
  });
}

}  // namespace

HgvaeTrainConfig LoadHgvaeTrainConfig(const std::string& path) {
  return ParseTrainRoot(path, yaml_util::LoadFile(path));
}

HgvaeTrainConfig ParseHgvaeTrainConfig(const std::string& yaml_text,
                                       const std::string& source_name) {
  return ParseTrainRoot(source_name, yaml_util::LoadText(yaml_text, source_name));
}

HgvaeManifest LoadHgvaeManifest(const std::string& path, BundleChecksums* checksums) {
  const YAML::Node root = LoadManifestFile(path);
  return WithFormatErrors(path, [&] {
    HgvaeManifest m;
    ParseManifestHeaderInto(path, root, kHgvaeBundleFormat, &m, checksums);
    ParseModel(path, Section(path, root, "model", true), &m.model);
    m.classes = yaml_util::StringList(path, root["classes"], "classes");
    const int coords = 3 * (static_cast<int>(m.skeleton.joint_names.size()) - 1);
    ParseManifestNormalisation(path, root, coords, "3 per non-root joint", &m.mean, &m.std);
    ValidateHgvaeOptions(m.model, coords);
    const YAML::Node ood = Section(path, root, "ood", true);
    m.score_mean = Get<double>(path, ood, "score_mean");
    m.score_std = Get<double>(path, ood, "score_std");
    m.ood_k = Get<double>(path, ood, "k");
    // Bundles written before the key existed hold the paper's posterior score.
    m.ood_score = ParseImputeObjective(GetOr<std::string>(path, ood, "score", "posterior"));
    ParseImpute(path, Section(path, root, "impute", false), &m.impute);
    ParseManifestRefiner(path, root, &m.refiner);
    if (m.impute.start == ImputeStart::kRefiner && !m.refiner.enabled())
      Fail(path, root, "impute.start is refiner, but the bundle has no refiner");
    ParseRefinerCalibration(path, root, &m);
    m.info = ParseManifestInfo(root);
    return m;
  });
}

std::string FormatHgvaeManifest(const HgvaeManifest& m, const BundleChecksums& checksums) {
  return FormatManifest(
      {m.format, m.protocol, m.fps, m.skeleton, checksums}, m.info, [&m](YAML::Emitter& out) {
        EmitModel(out, m.model);
        out << YAML::Key << "classes" << YAML::Value << YAML::Flow << m.classes;
        EmitManifestNormalisation(out, m.mean, m.std);
        EmitOod(out, m);
        EmitImpute(out, m.impute);
        EmitManifestRefiner(out, m.refiner);
        if (!m.refiner_weights.empty()) {
          out << YAML::Key << "refiner_weights" << YAML::Value << YAML::Flow << m.refiner_weights;
        }
        if (!m.refiner_local_weights.empty()) {
          out << YAML::Key << "refiner_local_weights" << YAML::Value << YAML::Flow
              << m.refiner_local_weights;
        }
        if (m.refiner_keep_bones) out << YAML::Key << "refiner_keep_bones" << YAML::Value << true;
        const std::vector<double>& adapt = m.refiner_adapt_values;
        if (adapt.size() == 1 && adapt[0] > 0) {
          out << YAML::Key << "refiner_adapt_values" << YAML::Value << adapt[0];
        } else if (adapt.size() > 1) {
          out << YAML::Key << "refiner_adapt_values" << YAML::Value << YAML::Flow << adapt;
        }
        if (m.refiner_smoothing.active()) {
          out << YAML::Key << "refiner_smooth" << YAML::Value << YAML::Flow << YAML::BeginMap
              << YAML::Key << "bracketed" << YAML::Value << m.refiner_smoothing.bracketed
              << YAML::Key << "one_sided" << YAML::Value << m.refiner_smoothing.one_sided
              << YAML::EndMap;
        }
        if (const HgvaeManifest::GaussianStage& o = m.refiner_gaussian; o.enabled()) {
          out << YAML::Key << "refiner_gaussian" << YAML::Value << YAML::Flow << YAML::BeginMap
              << YAML::Key << "file" << YAML::Value << o.file << YAML::Key << "frames"
              << YAML::Value << o.frames << YAML::Key << "coords" << YAML::Value << o.coords
              << YAML::Key << "windows" << YAML::Value << o.windows << YAML::Key << "scope"
              << YAML::Value << GaussianScopeName(o.scope) << YAML::EndMap;
        }
      });
}

constexpr TorchBundleNames kHgvaeFiles{"HG-VAE", "hgvae.yaml", "hgvae.pt"};

// What hgvae.pt must have been saved with: the manifest but its settings (imputation defaults, the
// out-of-distribution rule and statistics, rewritten after evaluation) and provenance.
std::string HgvaeSignature(const HgvaeManifest& m) {
  HgvaeManifest s = m;
  const HgvaeManifest defaults;
  s.impute = defaults.impute;
  s.ood_score = defaults.ood_score;
  s.ood_k = defaults.ood_k;
  s.score_mean = defaults.score_mean;
  s.score_std = defaults.score_std;
  s.refiner_weights.clear();
  s.refiner_local_weights.clear();
  s.refiner_keep_bones = false;
  s.refiner_adapt_values.clear();
  s.refiner_smoothing = {};
  s.refiner_gaussian = {};
  s.info.clear();
  return FormatHgvaeManifest(s);
}

void SaveHgvaeBundle(const std::string& dir, const HgvaeManifest& m, HgvaeNet& net) {
  std::vector<BundleFile> files = {{kHgvaeFiles.weights, WeightBytes(*net, HgvaeSignature(m))}};
  if (const HgvaeManifest::GaussianStage& o = m.refiner_gaussian; o.enabled()) {
    if (!o.model || o.model->frames != o.frames || o.model->coords != o.coords) {
      throw std::invalid_argument("SaveHgvaeBundle: refiner_gaussian names " + o.file +
                                  " but holds no window Gaussian of its size");
    }
    files.push_back({o.file, SerializeWindowGaussian(*o.model)});
  }
  WriteBundle(dir, files, kHgvaeFiles.manifest,
              [&](const BundleChecksums& sums) { return FormatHgvaeManifest(m, sums); });
}

HgvaeNet LoadHgvaeBundle(const std::string& dir, HgvaeManifest* m, BundleCheck check) {
  HgvaeNet net =
      LoadTorchBundle(dir, kHgvaeFiles, m, LoadHgvaeManifest, BuildHgvaeNet, HgvaeSignature, check);
  if (HgvaeManifest::GaussianStage& o = m->refiner_gaussian; o.enabled()) {
    BundleChecksums sums;
    LoadHgvaeManifest((std::filesystem::path(dir) / kHgvaeFiles.manifest).string(), &sums);
    RequireBundleFiles(dir, kHgvaeFiles.kind, {kHgvaeFiles.manifest, o.file});
    RequireChecksum(dir, o.file, sums, kHgvaeFiles.manifest);
    const std::string source = (std::filesystem::path(dir) / o.file).string();
    o.model = std::make_shared<const WindowGaussian>(
        ParseWindowGaussian(ReadBundleFile(dir, o.file, sums, kHgvaeFiles.manifest), o.frames,
                            o.coords, o.windows, source));
    const int expected = 3 * (static_cast<int>(m->skeleton.joint_names.size()) - 1);
    if (o.coords != expected) {
      throw FormatError(source + ": a window Gaussian of " + std::to_string(o.coords) +
                        " coordinates, expected the skeleton's " + std::to_string(expected));
    }
  }
  return net;
}

HgvaeModel LoadHgvaeModel(const std::string& dir) {
  HgvaeManifest m;
  HgvaeNet net = LoadHgvaeBundle(dir, &m);
  return HgvaeModel::FromNet(std::move(m), std::move(net));
}

void RewriteHgvaeManifest(const std::string& dir, const HgvaeManifest& m) {
  const std::string path = (std::filesystem::path(dir) / "hgvae.yaml").string();
  BundleChecksums sums;
  LoadHgvaeManifest(path, &sums);
  WriteFileAtomically(path, FormatHgvaeManifest(m, sums));
}

HgvaeManifest HgvaeTrainingManifest(const HgvaeTrainConfig& config, const ProtocolOptions& protocol,
                                    const Skeleton& skeleton) {
  HgvaeManifest m = ProtocolManifest<HgvaeManifest>(config, protocol, skeleton);
  m.ood_k = config.ood_k;
  m.ood_score = config.ood_score;
  m.impute = config.impute;
  if (m.impute.start == ImputeStart::kRefiner) m.impute.start = ImputeStart::kMean;  // none yet
  return m;
}

}  // namespace motionfork
