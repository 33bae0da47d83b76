#include "bundle/torch_bundle.h"

#include <torch/script.h>

#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace motionfork {

namespace {

// The archive key of the manifest signature inside a weights file.
constexpr const char* kSignatureKey = "motionfork_manifest";

using Shapes = std::map<std::string, std::vector<int64_t>>;

[[noreturn]] void Fail(const std::string& file, const std::string& what) {
  throw FormatError(FormatMessage(file, "", what));
}

std::string ShapeText(const std::vector<int64_t>& shape) {
  std::string s = "[";
  for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + "]";
}

using Tensors = std::map<std::string, torch::Tensor>;

// Every parameter and buffer by its dotted name.
Tensors NetTensors(const torch::nn::Module& net) {
  Tensors tensors;
  for (const auto& p : net.named_parameters(/*recurse=*/true)) tensors[p.key()] = p.value();
  for (const auto& b : net.named_buffers(/*recurse=*/true)) tensors[b.key()] = b.value();
  return tensors;
}

Tensors FileTensors(const torch::jit::Module& file) {
  Tensors tensors;
  for (const auto& p : file.named_parameters(/*recurse=*/true)) tensors[p.name] = p.value;
  for (const auto& b : file.named_buffers(/*recurse=*/true)) tensors[b.name] = b.value;
  return tensors;
}

Shapes ShapesOf(const Tensors& tensors) {
  Shapes shapes;
  for (const auto& [name, t] : tensors) shapes[name] = t.sizes().vec();
  return shapes;
}

// The first line where the manifest's signature and the one the weights were saved with differ.
std::string FirstDifference(const std::string& manifest, const std::string& saved) {
  std::istringstream a(manifest), b(saved);
  std::string la, lb;
  while (true) {
    const bool more_a = static_cast<bool>(std::getline(a, la));
    const bool more_b = static_cast<bool>(std::getline(b, lb));
    if (!more_a && !more_b) return "";
    if (!more_a) la = "(nothing)";
    if (!more_b) lb = "(nothing)";
    if (la != lb) return "'" + la + "' where the weights were saved with '" + lb + "'";
  }
}

void CheckSignature(const torch::jit::Module& file, const std::string& dir,
                    const TorchBundleNames& names, const std::string& signature,
                    BundleCheck check) {
  const std::string weights = (std::filesystem::path(dir) / names.weights).string();
  if (!file.hasattr(kSignatureKey)) {
    if (check == BundleCheck::kLegacy) return;
    Fail(weights,
         "records no copy of its manifest (a bundle written before motionfork verified bundles); "
         "rewrite it with 'motionfork bundle upgrade " +
             dir + "'");
  }
  const c10::IValue saved = file.attr(kSignatureKey);
  if (!saved.isString()) Fail(weights, std::string("'") + kSignatureKey + "' is not text");
  if (saved.toStringRef() == signature) return;
  Fail((std::filesystem::path(dir) / names.manifest).string(),
       "does not describe " + std::string(names.weights) + ": " +
           FirstDifference(signature, saved.toStringRef()) +
           " (the manifest was edited or belongs to another bundle)");
}

void CheckShapes(const Shapes& expected, const Shapes& found, const std::string& weights,
                 const std::string& manifest) {
  for (const auto& [name, shape] : expected) {
    const auto it = found.find(name);
    if (it == found.end()) {
      Fail(weights, "tensor '" + name + "' " + ShapeText(shape) + ", which " + manifest +
                        " describes, is missing");
    }
    if (it->second != shape) {
      Fail(weights, "tensor '" + name + "': expected shape " + ShapeText(shape) + " (from " +
                        manifest + "), found " + ShapeText(it->second));
    }
  }
  for (const auto& [name, shape] : found) {
    if (!expected.count(name)) {
      Fail(weights, "holds tensor '" + name + "' " + ShapeText(shape) + ", which " + manifest +
                        " does not describe (another model's weights, or the manifest was edited)");
    }
  }
}

}  // namespace

std::string WeightBytes(torch::nn::Module& net, const std::string& signature) {
  torch::serialize::OutputArchive archive;
  net.save(archive);
  archive.write(kSignatureKey, c10::IValue(signature));
  std::ostringstream out;
  archive.save_to(out);
  return out.str();
}

struct VerifiedWeights::Impl {
  std::string weights;   // the file's path
  std::string manifest;  // the manifest's name
  Tensors tensors;       // the file's, by name
};

VerifiedWeights::VerifiedWeights(const std::string& bytes, const std::string& dir,
                                 const TorchBundleNames& names, const std::string& signature,
                                 BundleCheck check)
    : impl_(std::make_unique<Impl>()) {
  impl_->weights = (std::filesystem::path(dir) / names.weights).string();
  impl_->manifest = names.manifest;
  std::optional<torch::jit::Module> file;
  try {
    std::istringstream in(bytes);
    file = torch::jit::load(in, torch::kCPU);
  } catch (const c10::Error& e) {
    Fail(impl_->weights,
         std::string("cannot read the weights (damaged, or not a LibTorch file): ") +
             e.what_without_backtrace());
  }
  CheckSignature(*file, dir, names, signature, check);
  impl_->tensors = FileTensors(*file);
}

VerifiedWeights::~VerifiedWeights() = default;

void VerifiedWeights::LoadInto(torch::nn::Module& net) const {
  const Tensors target = NetTensors(net);
  CheckShapes(ShapesOf(target), ShapesOf(impl_->tensors), impl_->weights, impl_->manifest);
  torch::NoGradGuard no_grad;
  for (const auto& [name, t] : target) t.copy_(impl_->tensors.at(name));
}

void LoadVerifiedWeights(torch::nn::Module& net, const std::string& bytes, const std::string& dir,
                         const TorchBundleNames& names, const std::string& signature,
                         BundleCheck check) {
  VerifiedWeights(bytes, dir, names, signature, check).LoadInto(net);
}

}  // namespace motionfork
