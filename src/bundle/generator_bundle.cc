#include "bundle/generator_bundle.h"

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <type_traits>

#include "bodyparts/part_plan.h"
#include "bundle/generator_net_bundle.h"
#include "bundle/manifest.h"
#include "bundle/torch_bundle.h"
#include "bundle/trajectory_bundle.h"
#include "config/constraint_config.h"
#include "config/skeleton_yaml.h"
#include "config/yaml_util.h"
#include "core/error.h"
#include "core/heading.h"
#include "generator/kernels/precision.h"

namespace motionfork {

namespace fs = std::filesystem;

namespace {

using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;
using yaml_util::WithFormatErrors;

template <typename T>
std::vector<T> List(const std::string& path, const YAML::Node& map, const std::string& key,
                    std::vector<T> fallback) {
  const YAML::Node n = map[key];
  if (!n) return fallback;
  if (!n.IsSequence()) Fail(path, n, "'" + key + "' must be a list");
  std::vector<T> out;
  for (const YAML::Node& e : n) out.push_back(e.as<T>());
  return out;
}

// The generator's keys after num_nodes, in file order, as f(key, member): the one list that
// model.yaml's `generator:` is read and written by, and a training config's is read by.
template <typename Options, typename F>
void ForEachGeneratorKey(Options& g, F f) {
  f("n_pre", g.n_pre);
  f("hidden", g.hidden);
  f("blocks", g.blocks);
  f("nz", g.nz);
  f("batch_norm", g.batch_norm);
  f("dropout", g.dropout);
  f("partition", g.partition);
}

// A bundle must hold each key (but dropout, which bundles written before it existed lack: 0); a
// training config may leave any out (the default stays).
void ReadGeneratorKeys(const std::string& path, const YAML::Node& n, bool required,
                       GeneratorOptions* g) {
  ForEachGeneratorKey(*g, [&](const std::string& key, auto& value) {
    using T = std::decay_t<decltype(value)>;
    value = required && key != "dropout" ? Get<T>(path, n, key) : GetOr<T>(path, n, key, value);
  });
}

// model.yaml's body_frame: an up axis, absent for a network in the data's axes (bundles written
// before it existed).
void ReadBodyFrame(const std::string& path, const YAML::Node& n, GeneratorOptions* g) {
  g->body_frame = GetOr<std::string>(path, n, "body_frame", "");
  if (!g->body_frame.empty()) {
    try {
      ParseUp(g->body_frame);
    } catch (const std::invalid_argument& e) {
      Fail(path, n["body_frame"], std::string("generator.body_frame: ") + e.what());
    }
  }
}

void CheckTrainConfig(const GeneratorTrainConfig& c) {
  const TrainingOptions& t = c.training;
  const size_t parts = t.samples_per_part.size();
  auto rule = [&](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  rule(parts >= 1, "training.samples_per_part needs one count per body part");
  for (int64_t n : t.samples_per_part)
    rule(n >= 1, "training.samples_per_part entries must be >= 1");
  rule(c.losses.diversity.size() == parts && c.losses.diversity_scale.size() == parts,
       "losses.diversity and losses.diversity_scale need one value per body part (" +
           std::to_string(parts) + ", as training.samples_per_part)");
  rule(t.batch_histories >= 1, "training.batch_histories must be >= 1");
  rule(t.epochs >= 1, "training.epochs must be >= 1");
  rule(t.windows_per_epoch >= t.batch_histories,
       "training.windows_per_epoch must be >= batch_histories");
  rule(t.lr_constant_epochs >= 0 && t.lr_constant_epochs <= t.epochs,
       "training.lr_constant_epochs must be in 0..epochs");
  rule(t.learning_rate > 0, "training.learning_rate must be > 0");
  rule(t.grad_clip > 0, "training.grad_clip must be > 0");
  if (const auto& r = c.trajectory) {
    rule(c.body_frame,
         "trajectory needs generator.body_frame: true (it works in the body's frame)");
    rule(r->n_in >= 0 && r->n_out >= 1 && r->hidden >= 1 && r->layers >= 1,
         "trajectory.n_in must be >= 0, n_out, hidden and layers >= 1");
    rule(r->epochs >= 1 && r->lr_constant_epochs >= 0 && r->lr_constant_epochs <= r->epochs,
         "trajectory.epochs must be >= 1 and lr_constant_epochs in 0..epochs");
    rule(r->batch >= 1 && r->window_stride >= 1 && r->validation_every >= 0,
         "trajectory.batch and window_stride must be >= 1, validation_every >= 0");
    rule(r->learning_rate > 0 && r->contact_height > 0 && r->final_weight >= 0 &&
             r->skating_weight >= 0,
         "trajectory.learning_rate and contact_height must be > 0, the weights >= 0");
  }
  const AugmentationOptions& a = c.augmentation;
  rule(a.mirror >= 0 && a.mirror <= 1, "augmentation.mirror must be a share in 0..1");
  rule(a.scale >= 1 && a.scale <= 2, "augmentation.scale must be in 1..2 (1: off)");
  rule(a.speed >= 1 && a.speed <= 4, "augmentation.speed must be in 1..4 (1: off)");
  rule(a.history_noise >= 0 && a.history_noise <= 1,
       "augmentation.history_noise must be in 0..1 metres (0: off)");
  rule(t.window_stride >= 1, "training.window_stride must be >= 1");
  rule(t.prior_frame_step >= 1, "training.prior_frame_step must be >= 1");
  rule(t.threads >= 1, "training.threads must be >= 1");
  rule(c.multimodal.max_per_window >= 0, "multimodal.max_per_window must be >= 0");
  rule(!c.multimodal.body_frame || c.body_frame,
       "multimodal.body_frame needs generator.body_frame: true");
}

}  // namespace

GeneratorTrainConfig LoadGeneratorTrainConfig(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  return WithFormatErrors(path, [&] {
    GeneratorTrainConfig c;
    c.path = path;
    c.name = Get<std::string>(path, root, "name");
    c.protocol = Get<std::string>(path, root, "protocol");
    c.prior = GetOr<std::string>(path, root, "prior", "");
    c.constraints = GetOr<std::string>(path, root, "constraints", "");
    if (const YAML::Node g = root["generator"]) {
      ReadGeneratorKeys(path, g, /*required=*/false, &c.generator);
      c.body_frame = GetOr<bool>(path, g, "body_frame", false);
    }
    if (const YAML::Node l = root["losses"]) {
      LossWeights& w = c.losses;
      w.past_reconstruction = GetOr<double>(path, l, "past_reconstruction", w.past_reconstruction);
      w.limb_length = GetOr<double>(path, l, "limb_length", w.limb_length);
      w.diversity = List<double>(path, l, "diversity", {8, 25});
      w.diversity_scale = List<double>(path, l, "diversity_scale", {100, 300});
      w.best_of_many = GetOr<double>(path, l, "best_of_many", w.best_of_many);
      w.multimodal = GetOr<double>(path, l, "multimodal", w.multimodal);
      w.prior_nll = GetOr<double>(path, l, "prior_nll", w.prior_nll);
      w.angle = GetOr<double>(path, l, "angle", w.angle);
    } else {
      c.losses.diversity = {8, 25};
      c.losses.diversity_scale = {100, 300};
    }
    if (const YAML::Node m = root["multimodal"]) {
      MultimodalOptions& o = c.multimodal;
      o.last_pose_threshold = GetOr<double>(path, m, "last_pose_threshold", o.last_pose_threshold);
      o.future_min_distance = GetOr<double>(path, m, "future_min_distance", o.future_min_distance);
      o.max_per_window = GetOr<int>(path, m, "max_per_window", o.max_per_window);
      o.body_frame = GetOr<bool>(path, m, "body_frame", o.body_frame);
    }
    TrainingOptions& t = c.training;
    t.samples_per_part = {10, 10};
    if (const YAML::Node n = root["training"]) {
      t.samples_per_part = List<int64_t>(path, n, "samples_per_part", t.samples_per_part);
      t.batch_histories = GetOr<int>(path, n, "batch_histories", t.batch_histories);
      t.epochs = GetOr<int>(path, n, "epochs", t.epochs);
      t.windows_per_epoch = GetOr<int>(path, n, "windows_per_epoch", t.windows_per_epoch);
      t.lr_constant_epochs = GetOr<int>(path, n, "lr_constant_epochs", t.lr_constant_epochs);
      t.learning_rate = GetOr<double>(path, n, "learning_rate", t.learning_rate);
      t.grad_clip = GetOr<double>(path, n, "grad_clip", t.grad_clip);
      t.window_stride = GetOr<int>(path, n, "window_stride", t.window_stride);
      t.prior_frame_step = GetOr<int>(path, n, "prior_frame_step", t.prior_frame_step);
      t.seed = GetOr<uint64_t>(path, n, "seed", t.seed);
      t.threads = GetOr<int>(path, n, "threads", t.threads);
      t.sync_batch_norm = GetOr<bool>(path, n, "sync_batch_norm", t.sync_batch_norm);
      if (n["precision"]) {
        try {
          t.precision = ParsePrecision(Get<std::string>(path, n, "precision"));
        } catch (const std::invalid_argument& e) {
          Fail(path, n["precision"], std::string("training.") + e.what());
        }
      }
    }
    if (const YAML::Node n = root["augmentation"]) {
      AugmentationOptions& a = c.augmentation;
      a.mirror = GetOr<double>(path, n, "mirror", a.mirror);
      a.scale = GetOr<double>(path, n, "scale", a.scale);
      a.speed = GetOr<double>(path, n, "speed", a.speed);
      a.history_noise = GetOr<double>(path, n, "history_noise", a.history_noise);
    }
    if (const YAML::Node n = root["trajectory"]) {
      TrajectoryTrainOptions o;
      o.n_in = GetOr<int>(path, n, "n_in", o.n_in);
      o.n_out = GetOr<int>(path, n, "n_out", o.n_out);
      o.hidden = GetOr<int>(path, n, "hidden", o.hidden);
      o.layers = GetOr<int>(path, n, "layers", o.layers);
      o.epochs = GetOr<int>(path, n, "epochs", o.epochs);
      o.lr_constant_epochs = GetOr<int>(path, n, "lr_constant_epochs", o.lr_constant_epochs);
      o.batch = GetOr<int>(path, n, "batch", o.batch);
      o.window_stride = GetOr<int>(path, n, "window_stride", o.window_stride);
      o.learning_rate = GetOr<double>(path, n, "learning_rate", o.learning_rate);
      o.validation_every = GetOr<int>(path, n, "validation_every", o.validation_every);
      o.final_weight = GetOr<double>(path, n, "final_weight", o.final_weight);
      o.skating_weight = GetOr<double>(path, n, "skating_weight", o.skating_weight);
      o.contact_height = GetOr<double>(path, n, "contact_height", o.contact_height);
      o.seed = GetOr<uint64_t>(path, n, "seed", o.seed);
      c.trajectory = o;
    }
    CheckTrainConfig(c);
    return c;
  });
}

ModelConfig LoadGeneratorManifest(const std::string& path, BundleChecksums* checksums) {
  const YAML::Node root = LoadManifestFile(path);
  return WithFormatErrors(path, [&] {
    ModelConfig c;
    ManifestHeader h = ParseManifestHeader(path, root, kGeneratorBundleFormat,
                                           {/*protocol=*/true,
                                            /*skeleton=*/false});
    c.format = h.format;
    c.protocol = h.protocol;
    c.fps = h.fps;
    if (checksums) *checksums = std::move(h.checksums);
    const YAML::Node p = root["protocol"];
    GeneratorOptions& g = c.generator;
    g.t_his = Get<int>(path, p, "t_his");
    g.t_pred = Get<int>(path, p, "t_pred");
    const YAML::Node n = root["generator"];
    if (!n) Fail(path, root, "missing mapping 'generator'");
    g.num_nodes = Get<int>(path, n, "num_nodes");
    ReadGeneratorKeys(path, n, /*required=*/true, &g);
    ReadBodyFrame(path, n, &g);
    ValidateGeneratorOptions(g);
    c.skeleton = ParseSkeletonSpec(path, root);
    for (auto& [k, v] : ParseManifestInfo(root)) c.info[k] = std::move(v);
    return c;
  });
}

std::string FormatGeneratorManifest(const ModelConfig& c, const BundleChecksums& checksums) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  EmitManifestFormat(out, {c.format, c.protocol, c.fps, {}, {}}, /*open_protocol=*/true);
  out << YAML::Key << "t_his" << YAML::Value << c.generator.t_his;
  out << YAML::Key << "t_pred" << YAML::Value << c.generator.t_pred;
  out << YAML::EndMap;
  const GeneratorOptions& g = c.generator;
  out << YAML::Key << "generator" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "num_nodes" << YAML::Value << g.num_nodes;
  ForEachGeneratorKey(g, [&out](const char* key, const auto& value) {
    out << YAML::Key << key << YAML::Value << value;
  });
  if (!g.body_frame.empty()) out << YAML::Key << "body_frame" << YAML::Value << g.body_frame;
  out << YAML::EndMap;
  EmitSkeletonSpec(out, c.skeleton);
  EmitManifestChecksums(out, checksums);
  EmitManifestInfo(out, {c.info.begin(), c.info.end()});
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

namespace {

constexpr TorchBundleNames kGeneratorFiles{"model", "model.yaml", "generator.pt"};

// What generator.pt must have been saved with: the manifest but its provenance.
std::string GeneratorSignature(const ModelConfig& c) {
  ModelConfig s = c;
  s.info.clear();
  return FormatGeneratorManifest(s);
}

GeneratorNet BuildGeneratorNet(const std::string& yaml, const ModelConfig& m) {
  std::optional<Skeleton> built;
  try {
    built = Skeleton::Build(m.skeleton);
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(yaml, "", e.what()));
  }
  const Skeleton& skeleton = *built;
  if (skeleton.num_joints() - 1 != m.generator.num_nodes) {
    throw FormatError(
        FormatMessage(yaml, "",
                      "generator.num_nodes = " + std::to_string(m.generator.num_nodes) +
                          " does not match the skeleton's " +
                          std::to_string(skeleton.num_joints() - 1) + " non-root joints"));
  }
  const PartPlan plan = MakePartPlan(skeleton, m.generator.partition);
  return GeneratorNet(m.generator, plan.nodes);
}

}  // namespace

void SaveGeneratorBundle(const std::string& dir, const ModelConfig& config, GeneratorNet& net) {
  SaveTorchBundle(dir, kGeneratorFiles, config, net, FormatGeneratorManifest, GeneratorSignature);
}

GeneratorNet LoadGeneratorBundle(const std::string& dir, ModelConfig* config, BundleCheck check) {
  const std::string yaml = (fs::path(dir) / kGeneratorFiles.manifest).string();
  return LoadTorchBundle(
      dir, kGeneratorFiles, config, LoadGeneratorManifest,
      [&yaml](const ModelConfig& m) { return BuildGeneratorNet(yaml, m); }, GeneratorSignature,
      check);
}

Forecaster LoadForecaster(const std::string& dir) {
  ModelConfig config;
  GeneratorNet net = LoadGeneratorBundle(dir, &config);
  std::optional<ConstraintSetSpec> constraints;
  const fs::path file = fs::path(dir) / "constraints.yaml";
  if (fs::is_regular_file(file)) constraints = LoadConstraintConfig(file.string());
  Forecaster forecaster(std::move(config), net.ptr(), std::move(constraints));
  const fs::path trajectory = fs::path(dir) / kTrajectoryFolder;
  if (fs::is_directory(trajectory)) {
    TrajectoryManifest m;
    TrajectoryNet t = LoadTrajectoryBundle(trajectory.string(), &m);
    try {
      forecaster.AttachTrajectory(t.ptr());
    } catch (const std::invalid_argument& e) {
      throw FormatError(FormatMessage((trajectory / "trajectory.yaml").string(), "", e.what()));
    }
  }
  return forecaster;
}

}  // namespace motionfork
