#include "io/prediction_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/file_util.h"
#include "io/npy.h"

namespace motionfork {
namespace {

using nlohmann::json;

std::string StripExtension(const std::string& path) {
  for (const char* ext : {".npy", ".json"}) {
    const std::string e(ext);
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0) {
      return path.substr(0, path.size() - e.size());
    }
  }
  return path;
}

// JSON has no NaN: a missing figure is null.
json OptionalNumber(const std::optional<double>& x) {
  return x && std::isfinite(*x) ? json(*x) : json(nullptr);
}

json ValidityJson(const SampleValidity& v) {
  json j = {{"valid", v.valid}, {"failed", v.Failed()}, {"violating_frames", v.violating_frames}};
  j["prior_nll"] = OptionalNumber(v.prior_nll);
  return j;
}

// Typed access with an error naming the file and the key.
template <typename T>
T Get(const json& j, const std::string& key, const std::string& file) {
  if (!j.contains(key)) throw FormatError(FormatMessage(file, "", "missing key '" + key + "'"));
  try {
    return j.at(key).get<T>();
  } catch (const json::exception&) {
    throw FormatError(
        FormatMessage(file, "key '" + key + "'", "unexpected value " + j.at(key).dump()));
  }
}

SampleValidity ValidityFromJson(const json& j, const std::string& file) {
  SampleValidity v;
  v.valid = Get<bool>(j, "valid", file);
  v.violating_frames = Get<int>(j, "violating_frames", file);
  if (j.contains("prior_nll") && !j.at("prior_nll").is_null())
    v.prior_nll = Get<double>(j, "prior_nll", file);
  // Files written before "failed" judged the angle ranges only.
  const auto failed = j.contains("failed") ? Get<std::vector<std::string>>(j, "failed", file)
                                           : std::vector<std::string>{};
  const auto fails = [&](const char* judge) {
    return std::find(failed.begin(), failed.end(), judge) != failed.end();
  };
  v.prior_ok = !fails("prior_nll");
  v.history_ok = !fails("history");
  return v;
}

std::optional<double> OptionalNumberFromJson(const json& j, const std::string& key,
                                             const std::string& file) {
  if (!j.contains(key) || j.at(key).is_null()) return std::nullopt;
  return Get<double>(j, key, file);
}

}  // namespace

std::vector<std::string> SampleValidity::Failed() const {
  std::vector<std::string> failed;
  if (violating_frames > 0) failed.push_back("angle_ranges");
  if (!prior_ok) failed.push_back("prior_nll");
  if (!history_ok) failed.push_back("history");
  return failed;
}

std::string WritePrediction(const std::string& out, const Prediction& p) {
  if (!p.skeleton) throw std::invalid_argument("WritePrediction: the prediction has no skeleton");
  const int T = p.frames(), J = p.joints();
  const size_t expected = static_cast<size_t>(p.k) * T * J * 3;
  if (p.positions.size() != expected) {
    throw std::invalid_argument("WritePrediction: expected " + std::to_string(expected) +
                                " positions ([" + std::to_string(p.k) + ", " + std::to_string(T) +
                                ", " + std::to_string(J) + ", 3]), got " +
                                std::to_string(p.positions.size()));
  }
  if (!p.samples.empty() && static_cast<int>(p.samples.size()) != p.k) {
    throw std::invalid_argument("WritePrediction: expected " + std::to_string(p.k) +
                                " sample entries, got " + std::to_string(p.samples.size()));
  }
  const std::string base = StripExtension(out);
  const Skeleton& s = *p.skeleton;
  json j;
  j["model"] = p.model;
  j["protocol"] = p.protocol;
  j["history"] = p.history;
  j["start_frame"] = p.start_frame;
  j["k"] = p.k;
  j["seed"] = p.seed;
  j["fps"] = p.fps;
  j["t_his"] = p.t_his;
  j["t_pred"] = p.t_pred;
  j["skeleton"] = s.name();
  j["joints"] = s.joint_names();
  j["parents"] = s.parents();
  json pairs = json::array();
  for (const auto& [l, r] : s.left_right_pairs()) pairs.push_back({l, r});
  j["left_right"] = pairs;
  json parts = json::array();
  if (!s.partitions().empty()) {
    for (const BodyPart& part : s.GetPartition().parts)
      parts.push_back({{"name", part.name}, {"joints", part.joints}});
  }
  j["parts"] = parts;
  j["fixed_parts"] = p.fixed_parts;
  j["root_moves"] = p.root_moves;
  j["array"] = std::filesystem::path(base + ".npy").filename().string();
  j["shape"] = {p.k, T, J, 3};
  if (p.prior_bound) j["prior_nll_bound"] = OptionalNumber(p.prior_bound);
  if (p.history_validity) j["history_validity"] = ValidityJson(*p.history_validity);
  if (const auto& c = p.history_check) {
    j["history_check"] = {{"window_score", OptionalNumber(c->window_score)},
                          {"window_bound", OptionalNumber(c->window_bound)},
                          {"doubts", c->doubts}};
  }
  if (const auto& r = p.reading) {
    j["reading"] = {{"path", r->path},
                    {"skeleton", r->skeleton},
                    {"joint_map", r->joint_map},
                    {"unit", r->unit},
                    {"up", r->up},
                    {"left_right", r->left_right},
                    {"bvh_scale", r->bvh_scale},
                    {"fps", r->fps}};
  }
  if (p.denoising) {
    j["denoising"] = {{"model", p.denoising->model},
                      {"mode", p.denoising->mode},
                      {"frames", p.denoising->frames},
                      {"mean_change", p.denoising->mean_change}};
  }
  if (p.imputation) {
    j["imputation"] = {{"model", p.imputation->model},
                       {"missing_values", p.imputation->missing_values},
                       {"score_before", p.imputation->score_before},
                       {"score_after", p.imputation->score_after}};
  }
  json samples = json::array();
  for (const SampleValidity& v : p.samples) samples.push_back(ValidityJson(v));
  j["samples"] = samples;

  NpyArray arr;
  arr.shape = {p.k, T, J, 3};
  arr.data = p.positions;
  // Both files or neither: a reader never finds a new array beside an old description.
  const std::filesystem::path b(base);
  WriteFileSet(b.parent_path().string(),
               {{b.filename().string() + ".npy", SerializeNpy(arr)},
                {b.filename().string() + ".json",
                 j.dump(2, ' ', false, json::error_handler_t::replace) + "\n"}});
  return base;
}

namespace {

Prediction ParsePrediction(const json& j, const std::string& base, const std::string& json_path);

}  // namespace

Prediction ReadPrediction(const std::string& path) {
  const std::string base = StripExtension(path);
  const std::string json_path = base + ".json";
  if (!std::filesystem::exists(json_path)) {
    throw FormatError(FormatMessage(
        json_path, "",
        "prediction description not found (written by 'motionfork predict' beside the .npy)"));
  }
  json j;
  try {
    j = json::parse(ReadFileBytes(json_path));
  } catch (const json::parse_error& e) {
    throw FormatError(FormatMessage(json_path, "byte " + std::to_string(e.byte), "invalid JSON"));
  }
  if (!j.is_object()) throw FormatError(FormatMessage(json_path, "", "expected a JSON object"));
  try {
    return ParsePrediction(j, base, json_path);
  } catch (const json::exception& e) {
    // A value of the wrong type where the reader does not check it key by key.
    std::string what = e.what();  // "[json.exception.type_error.302] type must be ..."
    if (const size_t close = what.find("] "); !what.empty() && what[0] == '[' && close != what.npos)
      what = what.substr(close + 2);
    throw FormatError(FormatMessage(json_path, "", "unexpected content: " + what));
  }
}

namespace {

Prediction ParsePrediction(const json& j, const std::string& base, const std::string& json_path) {
  Prediction p;
  p.model = j.value("model", "");
  p.protocol = j.value("protocol", "");
  p.history = j.value("history", "");
  p.start_frame = j.value("start_frame", 0);
  p.seed = j.value("seed", uint64_t{0});
  p.k = Get<int>(j, "k", json_path);
  p.fps = Get<double>(j, "fps", json_path);
  p.t_his = Get<int>(j, "t_his", json_path);
  p.t_pred = Get<int>(j, "t_pred", json_path);
  if (p.k < 1 || p.t_his < 1 || p.t_pred < 0 || !(p.fps > 0)) {
    throw FormatError(
        FormatMessage(json_path, "", "expected k >= 1, t_his >= 1, t_pred >= 0, fps > 0"));
  }
  const auto names = Get<std::vector<std::string>>(j, "joints", json_path);
  const auto parents = Get<std::vector<int>>(j, "parents", json_path);
  std::vector<std::pair<int, int>> pairs;
  for (const auto& pr : j.value("left_right", json::array())) {
    const auto v = pr.get<std::vector<int>>();
    if (v.size() != 2)
      throw FormatError(
          FormatMessage(json_path, "key 'left_right'", "expected [left, right] pairs"));
    pairs.emplace_back(v[0], v[1]);
  }
  std::vector<Partition> partitions;
  if (j.contains("parts") && !j["parts"].empty()) {
    Partition part{"default", {}};
    for (const auto& pj : j["parts"])
      part.parts.push_back({Get<std::string>(pj, "name", json_path),
                            Get<std::vector<int>>(pj, "joints", json_path)});
    partitions.push_back(part);
  }
  try {
    p.skeleton = std::make_shared<Skeleton>(Skeleton::FromParents(
        j.value("skeleton", std::string("prediction")), names, parents, pairs, partitions));
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(json_path, "skeleton", e.what()));
  }
  p.fixed_parts = j.value("fixed_parts", std::vector<std::string>{});
  p.root_moves = j.value("root_moves", false);
  if (j.contains("history_validity"))
    p.history_validity = ValidityFromJson(j["history_validity"], json_path);
  p.prior_bound = OptionalNumberFromJson(j, "prior_nll_bound", json_path);
  if (j.contains("reading")) {
    const json& r = j["reading"];
    p.reading = HistoryReading{r.value("path", std::string()),
                               Get<std::string>(r, "skeleton", json_path),
                               Get<std::string>(r, "joint_map", json_path),
                               Get<std::string>(r, "unit", json_path),
                               Get<std::string>(r, "up", json_path),
                               Get<std::string>(r, "left_right", json_path),
                               Get<double>(r, "bvh_scale", json_path),
                               Get<double>(r, "fps", json_path)};
  }
  if (j.contains("history_check")) {
    const json& c = j["history_check"];
    p.history_check = HistoryCheck{OptionalNumberFromJson(c, "window_score", json_path),
                                   OptionalNumberFromJson(c, "window_bound", json_path),
                                   Get<std::vector<std::string>>(c, "doubts", json_path)};
  }
  if (j.contains("imputation")) {
    const json& im = j["imputation"];
    p.imputation = HistoryImputation{im.value("model", std::string()),
                                     im.value("missing_values", 0),
                                     im.value("score_before", 0.0),
                                     im.value("score_after", 0.0),
                                     std::string(),
                                     0.0,
                                     0.0};
  }
  if (j.contains("denoising")) {
    const json& dn = j["denoising"];
    p.denoising =
        HistoryDenoising{dn.value("model", std::string()), dn.value("mode", std::string()),
                         dn.value("frames", 0), dn.value("mean_change", 0.0)};
  }
  for (const auto& sj : j.value("samples", json::array()))
    p.samples.push_back(ValidityFromJson(sj, json_path));
  if (!p.samples.empty() && static_cast<int>(p.samples.size()) != p.k) {
    throw FormatError(FormatMessage(
        json_path, "key 'samples'",
        "expected " + std::to_string(p.k) + " entries, found " + std::to_string(p.samples.size())));
  }

  const std::string array_name =
      j.value("array", std::filesystem::path(base + ".npy").filename().string());
  const std::string npy_path =
      (std::filesystem::path(json_path).parent_path() / array_name).string();
  NpyArray arr = ReadNpy(npy_path);
  const std::vector<int64_t> want = {p.k, p.frames(), static_cast<int64_t>(names.size()), 3};
  if (arr.shape != want) {
    std::string found;
    for (size_t i = 0; i < arr.shape.size(); ++i)
      found += (i ? ", " : "") + std::to_string(arr.shape[i]);
    throw FormatError(FormatMessage(npy_path, "",
                                    "expected shape [" + std::to_string(want[0]) + ", " +
                                        std::to_string(want[1]) + ", " + std::to_string(want[2]) +
                                        ", 3] (from " + json_path + "), found [" + found + "]"));
  }
  p.positions = std::move(arr.data);
  return p;
}

}  // namespace

bool IsPredictionPath(const std::string& path) {
  const std::filesystem::path p(path);
  if (p.extension() == ".json") return true;
  return p.extension() == ".npy" &&
         std::filesystem::exists(std::filesystem::path(p).replace_extension(".json"));
}

}  // namespace motionfork
