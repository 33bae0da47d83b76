#include "config/protocol_config.h"

#include <regex>

#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;

const char* ToString(SourceFormat format) {
  return format == SourceFormat::kBvh ? "bvh" : "videopose3d";
}

const char* ToString(RootHandling root) {
  switch (root) {
    case RootHandling::kRelativeDrop:
      return "relative_drop";
    case RootHandling::kRelative:
      return "relative";
    case RootHandling::kAbsolute:
      return "absolute";
  }
  return "?";
}

void ValidateProtocol(const ProtocolOptions& o) {
  auto bad = [&](const std::string& field, const std::string& value, const std::string& rule) {
    throw std::invalid_argument("protocol '" + o.name + "': " + field + " = " + value +
                                " breaks the rule: " + rule);
  };
  if (o.name.empty()) bad("name", "''", "must not be empty");
  if (o.skeleton.empty()) bad("skeleton", "''", "must name a skeleton config");
  if (!(o.fps > 0)) bad("fps", std::to_string(o.fps), "must be > 0 Hz");
  if (!(o.unit_scale > 0)) bad("source.unit_scale", std::to_string(o.unit_scale), "must be > 0");
  if (o.t_his < 1) bad("t_his", std::to_string(o.t_his), "must be >= 1 frame");
  if (o.t_pred < 1) bad("t_pred", std::to_string(o.t_pred), "must be >= 1 frame");
  if (o.min_length < 0) bad("min_length", std::to_string(o.min_length), "must be >= 0");
  if (o.test_stride < 1) bad("test_windows.stride", std::to_string(o.test_stride), "must be >= 1");
  if (!(o.multimodal_threshold > 0)) {
    bad("multimodal.threshold", std::to_string(o.multimodal_threshold), "must be > 0 metres");
  }
  if (o.split_file.empty() && o.train_subjects.empty() && o.test_subjects.empty()) {
    bad("split", "(none)", "needs split.file or split.train/split.test subject lists");
  }
  if (!o.label_pattern.empty()) {
    try {
      std::regex re(o.label_pattern);
      const int groups = static_cast<int>(re.mark_count());
      if (o.label_action_group > groups || o.label_subject_group > groups) {
        bad("labels", o.label_pattern,
            "action/subject group numbers must be <= the pattern's " + std::to_string(groups) +
                " groups");
      }
    } catch (const std::regex_error& e) {
      bad("labels.pattern", o.label_pattern,
          std::string("must be a valid regex (") + e.what() + ")");
    }
  }
}

ProtocolOptions LoadProtocolConfig(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  ProtocolOptions o;
  o.path = path;
  try {
    o.name = Get<std::string>(path, root, "name");
    o.skeleton = Get<std::string>(path, root, "skeleton");
    const YAML::Node source = root["source"];
    if (!source || !source.IsMap())
      Fail(path, root, "missing mapping 'source' (format, unit_scale)");
    const std::string fmt = Get<std::string>(path, source, "format");
    if (fmt == "bvh") {
      o.format = SourceFormat::kBvh;
    } else if (fmt == "videopose3d") {
      o.format = SourceFormat::kVideoPose3d;
    } else {
      Fail(path, source["format"],
           "source.format: expected 'bvh' or 'videopose3d', found '" + fmt + "'");
    }
    o.unit_scale = GetOr<double>(path, source, "unit_scale", 1.0);
    o.fps = Get<double>(path, root, "fps");
    o.t_his = Get<int>(path, root, "t_his");
    o.t_pred = Get<int>(path, root, "t_pred");
    o.min_length = GetOr<int>(path, root, "min_length", 0);
    if (o.min_length == 0) o.min_length = o.t_his + o.t_pred;
    const std::string r = GetOr<std::string>(path, root, "root", "relative_drop");
    if (r == "relative_drop") {
      o.root = RootHandling::kRelativeDrop;
    } else if (r == "relative") {
      o.root = RootHandling::kRelative;
    } else if (r == "absolute") {
      o.root = RootHandling::kAbsolute;
    } else {
      Fail(path, root["root"],
           "root: expected relative_drop, relative or absolute, found '" + r + "'");
    }
    if (const YAML::Node split = root["split"]) {
      o.split_file = GetOr<std::string>(path, split, "file", "");
      o.train_subjects = yaml_util::StringList(path, split["train"], "split.train");
      o.test_subjects = yaml_util::StringList(path, split["test"], "split.test");
    }
    if (const YAML::Node drops = root["drop_takes"]) {
      if (!drops.IsSequence())
        Fail(path, drops, "drop_takes: expected a list of [subject, action]");
      for (const YAML::Node& d : drops) {
        if (!d.IsSequence() || d.size() != 2)
          Fail(path, d, "drop_takes: expected [subject, action]");
        o.drop_takes.emplace_back(d[0].as<std::string>(), d[1].as<std::string>());
      }
    }
    if (const YAML::Node labels = root["labels"]) {
      o.label_pattern = Get<std::string>(path, labels, "pattern");
      o.label_action_group = GetOr<int>(path, labels, "action", 0);
      o.label_subject_group = GetOr<int>(path, labels, "subject", 0);
    }
    const YAML::Node tw = root["test_windows"];
    o.test_stride = tw ? GetOr<int>(path, tw, "stride", o.t_his) : o.t_his;
    o.test_include_last = tw ? GetOr<bool>(path, tw, "include_last", false) : false;
    if (const YAML::Node mm = root["multimodal"]) {
      o.multimodal_threshold = GetOr<double>(path, mm, "threshold", 0.5);
      o.keep_singleton_sets = GetOr<bool>(path, mm, "keep_singletons", true);
    }
    ValidateProtocol(o);
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(path, "", e.what()));
  } catch (const YAML::Exception& e) {
    throw FormatError(FormatMessage(path, "line " + std::to_string(e.mark.line + 1), e.msg));
  }
  return o;
}

}  // namespace motionfork
