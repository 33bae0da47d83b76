#include "bundle/torch_bundle.h"

#include <torch/script.h>

#include <map>
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

Shapes NetShapes(const torch::nn::Module& net) {
  Shapes shapes;
  for (const auto& p : net.named_parameters(/*recurse=*/true))
    shapes[p.key()] = p.value().sizes().vec();
  for (const auto& b : net.named_buffers(/*recurse=*/true))
    shapes[b.key()] = b.value().sizes().vec();
  return shapes;
}

Shapes FileShapes(const torch::jit::Module& file) {
  Shapes shapes;
  for (const auto& p : file.named_parameters(/*recurse=*/true))
    shapes[p.name] = p.value.sizes().vec();
  for (const auto& b : file.named_buffers(/*recurse=*/true)) shapes[b.name] = b.value.sizes().vec();
  return shapes;
}

// The first line where the manifest's signature and the one the weights were saved with differ.
std::string FirstDifference(const std::string& manifest, const std::string& saved) {
  std::istringstream a(manifest), b(saved);
  std::string la, lb;
  int line = 0;
  while (true) {
    const bool more_a = static_cast<bool>(std::getline(a, la));
    const bool more_b = static_cast<bool>(std::getline(b, lb));
    ++line;
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
  std::string bytes;
  std::string weights;   // the file's path
  std::string manifest;  // the manifest's name
  std::shared_ptr<torch::jit::Module> file;
};

VerifiedWeights::VerifiedWeights(const std::string& bytes, const std::string& dir,
                                 const TorchBundleNames& names, const std::string& signature,
                                 BundleCheck check)
    : impl_(std::make_unique<Impl>()) {
  impl_->bytes = bytes;
  impl_->weights = (std::filesystem::path(dir) / names.weights).string();
  impl_->manifest = names.manifest;
  try {
    std::istringstream in(bytes);
    impl_->file = std::make_shared<torch::jit::Module>(torch::jit::load(in, torch::kCPU));
  } catch (const c10::Error& e) {
    Fail(impl_->weights,
         std::string("cannot read the weights (damaged, or not a LibTorch file): ") +
             e.what_without_backtrace());
  }
  CheckSignature(*impl_->file, dir, names, signature, check);
}

VerifiedWeights::~VerifiedWeights() = default;

void VerifiedWeights::LoadInto(torch::nn::Module& net) const {
  CheckShapes(NetShapes(net), FileShapes(*impl_->file), impl_->weights, impl_->manifest);
  try {
    std::istringstream in(impl_->bytes);
    torch::serialize::InputArchive archive;
    archive.load_from(in, torch::kCPU);
    net.load(archive);
  } catch (const c10::Error& e) {
    Fail(impl_->weights, std::string("cannot load the weights: ") + e.what_without_backtrace());
  }
}

void LoadVerifiedWeights(torch::nn::Module& net, const std::string& bytes, const std::string& dir,
                         const TorchBundleNames& names, const std::string& signature,
                         BundleCheck check) {
  VerifiedWeights(bytes, dir, names, signature, check).LoadInto(net);
}

}  // namespace motionfork
