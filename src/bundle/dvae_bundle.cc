#include "bundle/dvae_bundle.h"

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
#include "core/motion_noise.h"
#include "denoise/refiner_blend.h"
#include "io/file_util.h"

namespace motionfork {

namespace {

using yaml_util::CheckKeys;
using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;
using yaml_util::Section;
using yaml_util::WithFormatErrors;

void ParseModel(const std::string& file, const YAML::Node& n, DvaeOptions* o) {
  CheckKeys(file, n, "model", {"window", "hidden", "latent", "mlp_hidden", "groups"});
  o->window = GetOr<int>(file, n, "window", o->window);
  o->hidden = GetOr<int>(file, n, "hidden", o->hidden);
  o->latent = GetOr<int>(file, n, "latent", o->latent);
  o->mlp_hidden = GetOr<int>(file, n, "mlp_hidden", o->mlp_hidden);
  o->groups = GetOr<int>(file, n, "groups", o->groups);
  ValidateDvaeOptions(*o);
}

void EmitModel(YAML::Emitter& out, const DvaeOptions& o) {
  yaml_util::EmitMap(out, "model", "window", o.window, "hidden", o.hidden, "latent", o.latent,
                     "mlp_hidden", o.mlp_hidden, "groups", o.groups);
}

void ParseNoisePrior(const std::string& file, const YAML::Node& n, DvaeNoisePrior* o) {
  CheckKeys(file, n, "noise_prior", {"dof", "scale"});
  o->dof = GetOr<double>(file, n, "dof", o->dof);
  o->scale = GetOr<double>(file, n, "scale", o->scale);
  if (!(o->dof > 0) || !(o->scale > 0))
    Fail(file, n, "noise_prior: expected dof > 0 and scale > 0 (metres)");
}

void EmitNoisePrior(YAML::Emitter& out, const DvaeNoisePrior& o) {
  yaml_util::EmitMap(out, "noise_prior", "dof", o.dof, "scale", o.scale);
}

void ParseDenoise(const std::string& file, const YAML::Node& n, DenoiseOptions* o) {
  CheckKeys(
      file, n, "denoise",
      {"mode", "iterations", "learning_rate", "bone_weight", "fuse", "samples", "stride", "seed"});
  if (n["mode"]) {
    try {
      o->mode = ParseDenoiseMode(Get<std::string>(file, n, "mode"));
    } catch (const std::invalid_argument& e) {
      Fail(file, n["mode"], e.what());
    }
  }
  o->iterations = GetOr<int>(file, n, "iterations", o->iterations);
  o->learning_rate = GetOr<double>(file, n, "learning_rate", o->learning_rate);
  o->bone_weight = GetOr<double>(file, n, "bone_weight", o->bone_weight);
  o->fuse = GetOr<bool>(file, n, "fuse", o->fuse);
  o->samples = GetOr<int>(file, n, "samples", o->samples);
  o->stride = GetOr<int>(file, n, "stride", o->stride);
  o->seed = GetOr<uint64_t>(file, n, "seed", o->seed);
  if (o->iterations < 0 || !(o->learning_rate > 0) || o->samples < 0 || o->stride < 1 ||
      o->bone_weight < 0) {
    Fail(file, n,
         "denoise: expected iterations >= 0, learning_rate > 0, bone_weight >= 0, samples >= 0, "
         "stride >= 1");
  }
}

void EmitDenoise(YAML::Emitter& out, const DenoiseOptions& o) {
  yaml_util::EmitMap(out, "denoise", "mode", ToString(o.mode), "iterations", o.iterations,
                     "learning_rate", o.learning_rate, "bone_weight", o.bone_weight, "fuse", o.fuse,
                     "samples", o.samples, "stride", o.stride, "seed", o.seed);
}

std::vector<std::string> ParseNoiseList(const std::string& file, const YAML::Node& n) {
  std::vector<std::string> out = yaml_util::StringList(file, n, "noise");
  for (const std::string& s : out) {
    try {
      ParseNoiseSpec(s);
    } catch (const std::invalid_argument& e) {
      Fail(file, n, e.what());
    }
  }
  return out;
}

void ParseRefinerConfig(const std::string& file, const YAML::Node& n, DvaeRefinerConfig* c) {
  std::set<std::string> keys = RefinerModelKeys();
  keys.insert(RefinerTrainKeys().begin(), RefinerTrainKeys().end());
  keys.insert({"noise", "clean_share", "accel_weight"});
  CheckKeys(file, n, "refiner", keys);
  ParseRefinerModel(file, n, &c->model);
  ParseRefinerTraining(file, n, &c->training);
  if (n["noise"]) c->noise = ParseNoiseList(file, n["noise"]);
  c->clean_share = GetOr<double>(file, n, "clean_share", c->clean_share);
  c->accel_weight = GetOr<double>(file, n, "accel_weight", c->accel_weight);
  if (!c->model.enabled() || c->noise.empty() || !(c->clean_share >= 0 && c->clean_share < 1) ||
      !(c->accel_weight >= 0))
    Fail(file, n,
         "refiner: expected channels >= 1, at least one noise spec, 0 <= clean_share < 1 and "
         "accel_weight >= 0");
}

DvaeTrainConfig ParseTrainRoot(const std::string& file, const YAML::Node& root) {
  return WithFormatErrors(file, [&] {
    CheckKeys(
        file, root, "",
        {"name", "protocol", "model", "training", "finetune", "noise_prior", "denoise", "refiner"});
    DvaeTrainConfig c;
    ReadTrainConfigHeader(file, root, &c);
    ParseModel(file, Section(file, root, "model", false), &c.model);
    const YAML::Node t = Section(file, root, "training", false);
    CheckKeys(file, t, "training",
              WithEpochLoopKeys({"lr_decay", "kl_anneal_epochs", "bone_weight", "held_out_share",
                                 "held_out_windows"}));
    DvaeTrainOptions& o = c.training;
    ReadEpochLoopKeys(file, t, &o);
    o.lr_decay = GetOr<double>(file, t, "lr_decay", o.lr_decay);
    o.kl_anneal_epochs = GetOr<int>(file, t, "kl_anneal_epochs", o.kl_anneal_epochs);
    o.bone_weight = GetOr<double>(file, t, "bone_weight", o.bone_weight);
    o.held_out_share = GetOr<double>(file, t, "held_out_share", o.held_out_share);
    o.held_out_windows = GetOr<int>(file, t, "held_out_windows", o.held_out_windows);
    if (o.epochs < 1 || o.batch_size < 1 || o.windows_per_epoch < o.batch_size ||
        !(o.learning_rate > 0) || !(o.lr_decay > 0 && o.lr_decay <= 1) || o.kl_anneal_epochs < 0 ||
        o.threads < 1 || o.bone_weight < 0 || !(o.held_out_share > 0 && o.held_out_share < 1) ||
        o.held_out_windows < 1) {
      Fail(file, t,
           "training: expected epochs >= 1, batch_size >= 1, windows_per_epoch >= batch_size, "
           "learning_rate > 0, "
           "0 < lr_decay <= 1, kl_anneal_epochs >= 0, bone_weight >= 0, threads >= 1, 0 < "
           "held_out_share < 1");
    }
    const YAML::Node f = Section(file, root, "finetune", false);
    CheckKeys(file, f, "finetune",
              WithEpochLoopKeys({"kl_anneal_epochs", "bone_weight", "noise", "patience"}));
    DvaeFinetuneOptions& u = c.finetune;
    ReadEpochLoopKeys(file, f, &u);
    u.kl_anneal_epochs = GetOr<int>(file, f, "kl_anneal_epochs", u.kl_anneal_epochs);
    u.bone_weight = GetOr<double>(file, f, "bone_weight", u.bone_weight);
    if (f["noise"]) u.noise = ParseNoiseList(file, f["noise"]);
    u.patience = GetOr<int>(file, f, "patience", u.patience);
    if (u.epochs < 1 || u.batch_size < 1 || u.windows_per_epoch < u.batch_size ||
        !(u.learning_rate > 0) || u.kl_anneal_epochs < 0 || u.threads < 1 || u.noise.empty() ||
        u.patience < 1 || u.bone_weight < 0) {
      Fail(file, f,
           "finetune: expected epochs >= 1, batch_size >= 1, windows_per_epoch >= batch_size, "
           "learning_rate > 0, "
           "kl_anneal_epochs >= 0, threads >= 1, patience >= 1, bone_weight >= 0 and at least one "
           "noise spec");
    }
    ParseNoisePrior(file, Section(file, root, "noise_prior", false), &c.noise_prior);
    ParseDenoise(file, Section(file, root, "denoise", false), &c.denoise);
    ParseRefinerConfig(file, Section(file, root, "refiner", false), &c.refiner);
    return c;
  });
}

}  // namespace

DvaeTrainConfig LoadDvaeTrainConfig(const std::string& path) {
  return ParseTrainRoot(path, yaml_util::LoadFile(path));
}

DvaeTrainConfig ParseDvaeTrainConfig(const std::string& yaml_text, const std::string& source_name) {
  return ParseTrainRoot(source_name, yaml_util::LoadText(yaml_text, source_name));
}

DvaeManifest LoadDvaeManifest(const std::string& path, BundleChecksums* checksums) {
  const YAML::Node root = LoadManifestFile(path);
  return WithFormatErrors(path, [&] {
    DvaeManifest m;
    ParseManifestHeaderInto(path, root, kDvaeBundleFormat, &m, checksums);
    ParseModel(path, Section(path, root, "model", true), &m.model);
    const int values = 3 * static_cast<int>(m.skeleton.joint_names.size());
    ParseManifestNormalisation(path, root, values, "3 per joint", &m.mean, &m.std);
    ParseNoisePrior(path, Section(path, root, "noise_prior", true), &m.noise_prior);
    m.finetuned = GetOr<bool>(path, root, "finetuned", false);
    if (root["finetune_noise"]) m.finetune_noise = ParseNoiseList(path, root["finetune_noise"]);
    ParseDenoise(path, Section(path, root, "denoise", false), &m.denoise);
    ParseManifestRefiner(path, root, &m.refiner);
    if (m.denoise.mode == DenoiseMode::kRefiner && !m.refiner.enabled())
      Fail(path, root, "denoise.mode is refiner, but the bundle has no refiner");
    if (const YAML::Node b = root["refiner_blend"]) {
      if (!b.IsMap()) Fail(path, b, "refiner_blend: expected a mapping {sigma, weights, smooth}");
      CheckKeys(path, b, "refiner_blend",
                {"sigma", "weights", "smooth", "accel_bound", "outliers", "roughness"});
      RefinerBlend& blend = m.refiner_blend;
      blend.sigma = Get<double>(path, b, "sigma");
      blend.weights = Get<std::vector<double>>(path, b, "weights");
      blend.smooth = GetOr<double>(path, b, "smooth", 0.0);
      blend.accel_bound = GetOr<double>(path, b, "accel_bound", 0.0);
      if (b["roughness"]) {
        try {
          blend.roughness = RoughnessNamed(Get<std::string>(path, b, "roughness"));
        } catch (const std::invalid_argument& e) {
          Fail(path, b["roughness"], std::string("refiner_blend.roughness: ") + e.what());
        }
      }
      if (const YAML::Node o = b["outliers"]) {
        if (!o.IsMap())
          Fail(path, o,
               "refiner_blend.outliers: expected a mapping {half_window, deviations, trend}");
        CheckKeys(path, o, "refiner_blend.outliers", {"half_window", "deviations", "trend"});
        OutlierRepair& r = blend.outliers;
        r.half_window = Get<int>(path, o, "half_window");
        r.deviations = Get<double>(path, o, "deviations");
        r.trend = GetOr<bool>(path, o, "trend", false);
        if (r.half_window < 1 || r.half_window > 1000 || !std::isfinite(r.deviations) ||
            r.deviations < 0) {
          Fail(path, o,
               "refiner_blend.outliers: expected half_window in [1, 1000] frames, deviations >= 0, "
               "found " +
                   std::to_string(r.half_window) + " and " + std::to_string(r.deviations));
        }
      }
      bool valid = m.refiner.enabled() && blend.weights.size() == size_t{kRefinerBlendBins} &&
                   std::isfinite(blend.sigma) && blend.sigma >= 0 && blend.sigma <= 100 &&
                   std::isfinite(blend.smooth) && blend.smooth >= 0 && blend.smooth <= 100 &&
                   std::isfinite(blend.accel_bound) && blend.accel_bound >= 0 &&
                   blend.accel_bound <= 100;
      for (double w : blend.weights) valid = valid && std::isfinite(w) && w >= 0 && w <= 1;
      if (!valid) {
        Fail(path, b,
             "refiner_blend: expected sigma and smooth in [0, 100] frames, accel_bound in [0, "
             "100], " +
                 std::to_string(kRefinerBlendBins) + " weights in [0, 1] and a refiner, found " +
                 std::to_string(blend.weights.size()) + " weights" +
                 (m.refiner.enabled() ? "" : " and no refiner"));
      }
    }
    m.info = ParseManifestInfo(root);
    return m;
  });
}

std::string FormatDvaeManifest(const DvaeManifest& m, const BundleChecksums& checksums) {
  return FormatManifest(
      {m.format, m.protocol, m.fps, m.skeleton, checksums}, m.info, [&m](YAML::Emitter& out) {
        EmitModel(out, m.model);
        EmitManifestNormalisation(out, m.mean, m.std);
        EmitNoisePrior(out, m.noise_prior);
        out << YAML::Key << "finetuned" << YAML::Value << m.finetuned;
        out << YAML::Key << "finetune_noise" << YAML::Value << YAML::Flow << m.finetune_noise;
        EmitDenoise(out, m.denoise);
        EmitManifestRefiner(out, m.refiner);
        if (!m.refiner_blend.weights.empty()) {
          out << YAML::Key << "refiner_blend" << YAML::Value << YAML::BeginMap << YAML::Key
              << "sigma" << YAML::Value << m.refiner_blend.sigma << YAML::Key << "weights"
              << YAML::Value << YAML::Flow << m.refiner_blend.weights;
          // Only when set: bundles from before it re-emit as written.
          if (m.refiner_blend.smooth > 0)
            out << YAML::Key << "smooth" << YAML::Value << m.refiner_blend.smooth;
          if (m.refiner_blend.accel_bound > 0)
            out << YAML::Key << "accel_bound" << YAML::Value << m.refiner_blend.accel_bound;
          if (m.refiner_blend.roughness != Roughness::kGaussian) {
            out << YAML::Key << "roughness" << YAML::Value
                << RoughnessName(m.refiner_blend.roughness);
          }
          if (const OutlierRepair& r = m.refiner_blend.outliers; r.enabled()) {
            out << YAML::Key << "outliers" << YAML::Value << YAML::Flow << YAML::BeginMap
                << YAML::Key << "half_window" << YAML::Value << r.half_window << YAML::Key
                << "deviations" << YAML::Value << r.deviations;
            if (r.trend) out << YAML::Key << "trend" << YAML::Value << true;
            out << YAML::EndMap;
          }
          out << YAML::EndMap;
        }
      });
}

constexpr TorchBundleNames kDvaeFiles{"Motion-DVAE", "dvae.yaml", "dvae.pt"};

// What dvae.pt must have been saved with: the manifest but its denoising defaults and provenance.
std::string DvaeSignature(const DvaeManifest& m) {
  DvaeManifest s = m;
  s.denoise = DenoiseOptions{};
  s.refiner_blend = {};
  s.info.clear();
  return FormatDvaeManifest(s);
}

void SaveDvaeBundle(const std::string& dir, const DvaeManifest& m, DvaeNet& net) {
  SaveTorchBundle(dir, kDvaeFiles, m, net, FormatDvaeManifest, DvaeSignature);
}

DvaeNet LoadDvaeBundle(const std::string& dir, DvaeManifest* m, BundleCheck check) {
  return LoadTorchBundle(dir, kDvaeFiles, m, LoadDvaeManifest, BuildDvaeNet, DvaeSignature, check);
}

DvaeModel LoadDvaeModel(const std::string& dir) {
  DvaeManifest m;
  DvaeNet net = LoadDvaeBundle(dir, &m);
  return DvaeModel::FromNet(std::move(m), std::move(net));
}

DvaeManifest DvaeTrainingManifest(const DvaeTrainConfig& config, const ProtocolOptions& protocol,
                                  const Skeleton& skeleton) {
  DvaeManifest m = ProtocolManifest<DvaeManifest>(config, protocol, skeleton);
  m.noise_prior = config.noise_prior;
  m.denoise = config.denoise;
  if (m.denoise.mode == DenoiseMode::kRefiner)
    m.denoise.mode = DenoiseMode::kRegression;  // none yet
  return m;
}

}  // namespace motionfork
