#include "generator/model/bundle.h"

#include <filesystem>
#include <optional>
#include <sstream>

#include "bodyparts/part_plan.h"
#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

void SaveGeneratorBundle(const std::string& dir, const ModelConfig& config, GeneratorNet& net) {
  fs::create_directories(dir);
  std::ostringstream weights;
  torch::save(net, weights);
  WriteFileAtomically((fs::path(dir) / "generator.pt").string(), weights.str());
  WriteFileAtomically((fs::path(dir) / "model.yaml").string(), ModelConfigToYaml(config));
}

GeneratorNet LoadGeneratorBundle(const std::string& dir, ModelConfig* config) {
  const fs::path yaml = fs::path(dir) / "model.yaml", weights = fs::path(dir) / "generator.pt";
  if (!fs::is_directory(dir))
    throw FormatError(FormatMessage(dir, "", "model bundle folder not found"));
  for (const fs::path& f : {yaml, weights}) {
    if (!fs::is_regular_file(f)) {
      throw FormatError(FormatMessage(f.string(), "",
                                      "missing from the model bundle (expected " +
                                          std::string("model.yaml and generator.pt)")));
    }
  }
  *config = LoadModelConfig(yaml.string());
  std::optional<Skeleton> built;
  try {
    built = Skeleton::Build(config->skeleton);
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(yaml.string(), "", e.what()));
  }
  const Skeleton& skeleton = *built;
  if (skeleton.num_joints() - 1 != config->generator.num_nodes) {
    throw FormatError(
        FormatMessage(yaml.string(), "",
                      "generator.num_nodes = " + std::to_string(config->generator.num_nodes) +
                          " does not match the skeleton's " +
                          std::to_string(skeleton.num_joints() - 1) + " non-root joints"));
  }
  const PartPlan plan = MakePartPlan(skeleton, config->generator.partition);
  GeneratorNet net(config->generator, plan.nodes);
  try {
    const std::string bytes = ReadFileBytes(weights.string());
    std::istringstream in(bytes);
    torch::load(net, in);
  } catch (const c10::Error& e) {
    throw FormatError(FormatMessage(weights.string(), "",
                                    "cannot load the weights (corrupt, or from a model with other "
                                    "sizes than model.yaml says): " +
                                        std::string(e.what_without_backtrace())));
  }
  net->eval();
  return net;
}

}  // namespace motionfork
