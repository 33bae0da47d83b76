#include "config/model_config.h"

#include "config/skeleton_yaml.h"
#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;

ModelConfig LoadModelConfig(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  ModelConfig c;
  try {
    c.format = Get<std::string>(path, root, "format");
    if (c.format != kGeneratorBundleFormat) {
      Fail(path, root["format"],
           "format: expected '" + std::string(kGeneratorBundleFormat) + "', found '" + c.format +
               "' (a bundle from another version?)");
    }
    const YAML::Node p = root["protocol"];
    if (!p) Fail(path, root, "missing mapping 'protocol'");
    c.protocol = Get<std::string>(path, p, "name");
    c.fps = Get<double>(path, p, "fps");
    GeneratorOptions& g = c.generator;
    g.t_his = Get<int>(path, p, "t_his");
    g.t_pred = Get<int>(path, p, "t_pred");
    const YAML::Node n = root["generator"];
    if (!n) Fail(path, root, "missing mapping 'generator'");
    g.num_nodes = Get<int>(path, n, "num_nodes");
    g.n_pre = Get<int>(path, n, "n_pre");
    g.hidden = Get<int>(path, n, "hidden");
    g.blocks = Get<int>(path, n, "blocks");
    g.nz = Get<int>(path, n, "nz");
    g.batch_norm = Get<bool>(path, n, "batch_norm");
    g.dropout = GetOr<double>(path, n, "dropout", 0.0);
    g.partition = Get<std::string>(path, n, "partition");
    ValidateGeneratorOptions(g);
    c.skeleton = ParseSkeletonSpec(path, root);
    if (const YAML::Node info = root["info"]) {
      for (const auto& kv : info) c.info[kv.first.as<std::string>()] = kv.second.as<std::string>();
    }
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(path, "", e.what()));
  } catch (const YAML::Exception& e) {
    throw FormatError(FormatMessage(path, "line " + std::to_string(e.mark.line + 1), e.msg));
  }
  return c;
}

std::string ModelConfigToYaml(const ModelConfig& c) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << c.format;
  out << YAML::Key << "protocol" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << c.protocol;
  out << YAML::Key << "fps" << YAML::Value << c.fps;
  out << YAML::Key << "t_his" << YAML::Value << c.generator.t_his;
  out << YAML::Key << "t_pred" << YAML::Value << c.generator.t_pred;
  out << YAML::EndMap;
  const GeneratorOptions& g = c.generator;
  out << YAML::Key << "generator" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "num_nodes" << YAML::Value << g.num_nodes;
  out << YAML::Key << "n_pre" << YAML::Value << g.n_pre;
  out << YAML::Key << "hidden" << YAML::Value << g.hidden;
  out << YAML::Key << "blocks" << YAML::Value << g.blocks;
  out << YAML::Key << "nz" << YAML::Value << g.nz;
  out << YAML::Key << "batch_norm" << YAML::Value << g.batch_norm;
  out << YAML::Key << "dropout" << YAML::Value << g.dropout;
  out << YAML::Key << "partition" << YAML::Value << g.partition;
  out << YAML::EndMap;
  EmitSkeletonSpec(out, c.skeleton);
  out << YAML::Key << "info" << YAML::Value << YAML::BeginMap;
  for (const auto& [k, v] : c.info) out << YAML::Key << k << YAML::Value << v;
  out << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace motionfork
