#include "bundle/prior_bundle.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <set>
#include <utility>

#include "bundle/bundle_files.h"
#include "bundle/manifest.h"
#include "config/yaml_util.h"
#include "core/error.h"
#include "flow/flow_module.h"
#include "io/file_util.h"
#include "io/npy.h"

namespace motionfork {
namespace {

using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;

using yaml_util::CheckKeys;
using yaml_util::LoadText;
using yaml_util::Section;

void ParseModel(const std::string& file, const YAML::Node& n, FlowOptions* o) {
  CheckKeys(file, n, "model", {"layers", "reflections", "prelu_init"});
  o->num_layers = GetOr<int>(file, n, "layers", o->num_layers);
  o->num_reflections = GetOr<int>(file, n, "reflections", o->num_reflections);
  o->prelu_init = GetOr<double>(file, n, "prelu_init", o->prelu_init);
}

void ParseTraining(const std::string& file, const YAML::Node& n, PriorTrainOptions* o) {
  CheckKeys(
      file, n, "training",
      {"epochs", "constant_epochs", "batch_size", "learning_rate", "weight_decay", "adam_beta1",
       "adam_beta2", "adam_eps", "seed", "held_out_share", "frame_stride", "min_steps"});
  o->epochs = GetOr<int>(file, n, "epochs", o->epochs);
  o->constant_epochs = GetOr<int>(file, n, "constant_epochs", o->constant_epochs);
  o->batch_size = GetOr<int>(file, n, "batch_size", o->batch_size);
  o->learning_rate = GetOr<double>(file, n, "learning_rate", o->learning_rate);
  o->weight_decay = GetOr<double>(file, n, "weight_decay", o->weight_decay);
  o->adam_beta1 = GetOr<double>(file, n, "adam_beta1", o->adam_beta1);
  o->adam_beta2 = GetOr<double>(file, n, "adam_beta2", o->adam_beta2);
  o->adam_eps = GetOr<double>(file, n, "adam_eps", o->adam_eps);
  o->seed = GetOr<uint64_t>(file, n, "seed", o->seed);
  o->held_out_share = GetOr<double>(file, n, "held_out_share", o->held_out_share);
  o->frame_stride = GetOr<int>(file, n, "frame_stride", o->frame_stride);
  o->min_steps = GetOr<int>(file, n, "min_steps", o->min_steps);
}

PriorConfig ParseConfigSections(const std::string& file, const YAML::Node& root) {
  PriorConfig c;
  ParseModel(file, Section(file, root, "model", false), &c.model);
  ParseTraining(file, Section(file, root, "training", false), &c.training);
  try {
    ValidatePriorConfig(c);
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(file, "", e.what()));
  }
  return c;
}

std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The lines `  key: value` of a mapping one level in, in the order given.
std::string Entries(std::initializer_list<std::pair<const char*, std::string>> entries) {
  std::string s;
  for (const auto& [key, value] : entries) s += std::string("  ") + key + ": " + value + "\n";
  return s;
}

std::string NumList(const std::vector<double>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + FlowNumberText(v[i]);
  return s + "]";
}

std::vector<double> DoubleList(const std::string& file, const YAML::Node& map,
                               const std::string& key) {
  const YAML::Node n = map[key];
  if (!n) Fail(file, map, "missing key '" + key + "'");
  if (!n.IsSequence()) Fail(file, n, "key '" + key + "' must be a list of numbers");
  std::vector<double> out;
  for (const YAML::Node& e : n) {
    try {
      out.push_back(e.as<double>());
    } catch (const YAML::Exception&) {
      Fail(file, e, "key '" + key + "' must be a list of numbers (found " + YAML::Dump(e) + ")");
    }
  }
  return out;
}

}  // namespace

PriorConfig ParseFlowConfig(const std::string& yaml_text, const std::string& source_name) {
  const YAML::Node root = LoadText(yaml_text, source_name);
  CheckKeys(source_name, root, "", {"model", "training"});
  return ParseConfigSections(source_name, root);
}

PriorConfig LoadFlowConfig(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  CheckKeys(path, root, "", {"model", "training"});
  return ParseConfigSections(path, root);
}

PriorManifest ParsePriorManifest(const std::string& yaml_text, const std::string& file) {
  const YAML::Node root = LoadText(yaml_text, file);
  PriorManifest m;
  m.version = ParseManifestVersion(file, root, PriorManifest::kFormat,
                                   "a motionfork pose-prior bundle", PriorManifest::kVersion);
  const YAML::Node sk = Section(file, root, "skeleton", true);
  m.skeleton_name = Get<std::string>(file, sk, "name");
  m.skeleton_config = GetOr<std::string>(file, sk, "config", "");
  const YAML::Node joints = sk["joints"];
  if (!joints || !joints.IsSequence() || joints.size() < 2) {
    Fail(file, joints ? joints : sk,
         "skeleton.joints must be a list of [name, parent] (>= 2 joints)");
  }
  for (const YAML::Node& j : joints) {
    if (!j.IsSequence() || j.size() != 2 || !j[0].IsScalar()) {
      Fail(file, j, "skeleton.joints: expected [name, parent] with parent ~ for the root");
    }
    m.joint_names.push_back(j[0].as<std::string>());
    if (j[1].IsNull()) {
      m.parents.push_back(-1);
      continue;
    }
    const std::string parent = j[1].as<std::string>();
    int index = -1;
    for (size_t k = 0; k + 1 < m.joint_names.size(); ++k) {
      if (m.joint_names[k] == parent) index = static_cast<int>(k);
    }
    if (index < 0) {
      Fail(file, j,
           "skeleton.joints: parent '" + parent + "' of '" + m.joint_names.back() +
               "' must be listed before it");
    }
    m.parents.push_back(index);
  }
  m.bone_lengths = DoubleList(file, root, "bone_lengths");
  m.dim = Get<int>(file, root, "dim");
  CheckKeys(file, root, "",
            {"format", "version", "skeleton", "bone_lengths", "dim", "model", "training", "summary",
             "weights"});
  m.config = ParseConfigSections(file, root);

  const YAML::Node s = Section(file, root, "summary", false);
  PriorTrainingSummary& y = m.summary;
  y.protocol = GetOr<std::string>(file, s, "protocol", "");
  y.fps = GetOr<double>(file, s, "fps", 0.0);
  y.train_frames = GetOr<int64_t>(file, s, "train_frames", 0);
  y.held_out_frames = GetOr<int64_t>(file, s, "held_out_frames", 0);
  y.test_frames = GetOr<int64_t>(file, s, "test_frames", 0);
  y.epochs_completed = GetOr<int>(file, s, "epochs_completed", 0);
  if (s["train_nll"]) y.train_nll = DoubleList(file, s, "train_nll");
  if (s["held_out_nll"]) y.held_out_nll = DoubleList(file, s, "held_out_nll");
  const double nan = std::nan("");
  y.test_nll = GetOr<double>(file, s, "test_nll", nan);
  y.held_out_nll_q50 = GetOr<double>(file, s, "held_out_nll_q50", nan);
  y.held_out_nll_q90 = GetOr<double>(file, s, "held_out_nll_q90", nan);
  y.held_out_nll_q99 = GetOr<double>(file, s, "held_out_nll_q99", nan);
  y.seconds = GetOr<double>(file, s, "seconds", 0.0);
  y.threads = GetOr<int>(file, s, "threads", 0);

  const YAML::Node w = Section(file, root, "weights", true);
  m.weights_file = Get<std::string>(file, w, "file");
  if (m.weights_file.find('/') != std::string::npos ||
      m.weights_file.find('\\') != std::string::npos) {
    Fail(file, w["file"],
         "weights.file must be a file name inside the bundle folder, found '" + m.weights_file +
             "'");
  }
  m.weights_checksum = Get<std::string>(file, w, "checksum");
  const YAML::Node params = w["parameters"];
  if (!params || !params.IsSequence()) Fail(file, w, "weights.parameters must be a list");
  for (const YAML::Node& p : params) {
    PriorParameterEntry e;
    e.name = Get<std::string>(file, p, "name");
    const YAML::Node shape = p["shape"];
    if (!shape || !shape.IsSequence()) Fail(file, p, "weights.parameters: 'shape' must be a list");
    for (const YAML::Node& d : shape) e.shape.push_back(d.as<int64_t>());
    m.parameters.push_back(std::move(e));
  }
  return m;
}

std::string FormatPriorManifest(const PriorManifest& m) {
  std::string s;
  s += "# motionfork pose prior: a normalizing flow on unit limb directions (GSPS).\n";
  s += "# Load with LoadPosePrior (src/bundle/prior_bundle.h) or 'motionfork prior score/sample\n";
  s += "# --model DIR'. Weights: weights.npy, float32, the parameters below concatenated in "
       "order.\n";
  s += std::string("format: ") + PriorManifest::kFormat + "\n";
  s += "version: " + std::to_string(m.version) + "\n";
  s += "skeleton:\n";
  s += "  name: " + Quote(m.skeleton_name) + "\n";
  s += "  config: " + Quote(m.skeleton_config) + "\n";
  s += "  joints:  # [name, parent]\n";
  for (size_t j = 0; j < m.joint_names.size(); ++j) {
    const int p = j < m.parents.size() ? m.parents[j] : -1;
    s += "    - [" + Quote(m.joint_names[j]) + ", " +
         (p < 0 ? std::string("~") : Quote(m.joint_names[p])) + "]\n";
  }
  s += "bone_lengths: " + NumList(m.bone_lengths) +
       "  # metres, limb k ends at joint k + 1; default for sampling\n";
  s += "dim: " + std::to_string(m.dim) + "  # 3 x (joints - 1) numbers per pose\n";
  s += FormatFlowConfig(m.config);
  const PriorTrainingSummary& y = m.summary;
  s += "summary:  # NLL in nats per pose (48-D density for 17 joints); lower = more likely\n";
  s += Entries({{"protocol", Quote(y.protocol)},
                {"fps", FlowNumberText(y.fps)},
                {"train_frames", std::to_string(y.train_frames)},
                {"held_out_frames", std::to_string(y.held_out_frames)},
                {"test_frames", std::to_string(y.test_frames)},
                {"epochs_completed", std::to_string(y.epochs_completed)},
                {"train_nll", NumList(y.train_nll)},
                {"held_out_nll", NumList(y.held_out_nll)},
                {"test_nll", FlowNumberText(y.test_nll)},
                {"held_out_nll_q50", FlowNumberText(y.held_out_nll_q50)},
                {"held_out_nll_q90", FlowNumberText(y.held_out_nll_q90)},
                {"held_out_nll_q99", FlowNumberText(y.held_out_nll_q99)},
                {"seconds", FlowNumberText(y.seconds)},
                {"threads", std::to_string(y.threads)}});
  s += "weights:\n";
  s += "  file: " + Quote(m.weights_file) + "\n";
  s += "  checksum: " + Quote(m.weights_checksum) + "\n";
  s += "  parameters:\n";
  for (const PriorParameterEntry& p : m.parameters) {
    s += "    - {name: " + Quote(p.name) + ", shape: [";
    for (size_t i = 0; i < p.shape.size(); ++i) s += (i ? ", " : "") + std::to_string(p.shape[i]);
    s += "]}\n";
  }
  return s;
}

namespace {

std::string ShapeText(const std::vector<int64_t>& shape) {
  std::string s = "[";
  for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + "]";
}

}  // namespace

void SavePosePrior(const PosePrior& prior, const std::string& dir) {
  PriorManifest m;
  const Skeleton& s = prior.skeleton();
  m.skeleton_name = s.name();
  m.skeleton_config = prior.skeleton_config();
  m.joint_names = s.joint_names();
  m.parents = s.parents();
  m.bone_lengths = prior.bone_lengths();
  m.dim = prior.dim();
  m.config = prior.config();
  m.summary = prior.summary();
  NpyArray weights;
  {
    torch::NoGradGuard no_grad;
    for (const auto& [name, t] : prior.module()->OrderedParameters()) {
      m.parameters.push_back({name, t.sizes().vec()});
      const torch::Tensor c = t.detach().to(torch::kFloat32).contiguous();
      weights.data.insert(weights.data.end(), c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
    }
  }
  weights.shape = {static_cast<int64_t>(weights.data.size())};
  WriteBundle(dir, {{m.weights_file, SerializeNpy(weights)}}, "prior.yaml",
              [&m](const BundleChecksums& sums) {
                m.weights_checksum = sums.at(m.weights_file);
                return FormatPriorManifest(m);
              });
}

PosePrior LoadPosePrior(const std::string& dir) {
  namespace fs = std::filesystem;
  const std::string manifest_path = (fs::path(dir) / "prior.yaml").string();
  if (!fs::is_regular_file(manifest_path)) {
    throw FormatError(FormatMessage(dir, "",
                                    "expected a prior bundle folder holding prior.yaml "
                                    "(written by 'motionfork prior train'), found none"));
  }
  const PriorManifest m = ParsePriorManifest(ReadFileBytes(manifest_path), manifest_path);
  auto fail = [&](const std::string& what) {
    throw FormatError(FormatMessage(manifest_path, "", what));
  };
  std::shared_ptr<const Skeleton> skeleton;
  try {
    skeleton = std::make_shared<const Skeleton>(
        Skeleton::FromParents(m.skeleton_name, m.joint_names, m.parents));
  } catch (const std::invalid_argument& e) {
    fail(std::string("skeleton: ") + e.what());
  }
  if (m.dim != 3 * (skeleton->num_joints() - 1)) {
    fail("dim = " + std::to_string(m.dim) +
         ", expected 3 x (joints - 1) = " + std::to_string(3 * (skeleton->num_joints() - 1)));
  }
  std::unique_ptr<PosePrior> made;
  try {
    made = std::make_unique<PosePrior>(skeleton, m.config);
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
  PosePrior prior = std::move(*made);
  prior.set_skeleton_config(m.skeleton_config);
  prior.mutable_summary() = m.summary;
  try {
    prior.set_bone_lengths(m.bone_lengths);
  } catch (const std::invalid_argument& e) {
    fail(std::string("bone_lengths: ") + e.what());
  }
  const auto params = prior.module()->OrderedParameters();
  if (params.size() != m.parameters.size()) {
    fail("lists " + std::to_string(m.parameters.size()) +
         " parameters, the model it describes has " + std::to_string(params.size()));
  }
  int64_t total = 0;
  for (size_t i = 0; i < params.size(); ++i) {
    const auto expected = params[i].second.sizes().vec();
    if (m.parameters[i].name != params[i].first || m.parameters[i].shape != expected) {
      fail("parameter " + std::to_string(i) + ": expected '" + params[i].first + "' of shape " +
           ShapeText(expected) + ", found '" + m.parameters[i].name + "' of shape " +
           ShapeText(m.parameters[i].shape));
    }
    total += params[i].second.numel();
  }
  const std::string weights_path = (fs::path(dir) / m.weights_file).string();
  const std::string bytes =
      ReadBundleFile(dir, m.weights_file, {{m.weights_file, m.weights_checksum}}, "prior.yaml");
  const NpyArray w = ParseNpy(bytes, weights_path);
  if (w.shape != std::vector<int64_t>{total}) {
    throw FormatError(FormatMessage(
        weights_path, "",
        "expected shape [" + std::to_string(total) + "], found " + ShapeText(w.shape)));
  }
  torch::NoGradGuard no_grad;
  int64_t offset = 0;
  for (const auto& [name, t] : params) {
    torch::Tensor dst = t;
    dst.copy_(
        torch::from_blob(const_cast<float*>(w.data.data()) + offset, t.sizes(), torch::kFloat32)
            .to(t.dtype()));
    offset += t.numel();
  }
  return prior;
}

}  // namespace motionfork
