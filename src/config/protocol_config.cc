#include "config/protocol_config.h"

#include <algorithm>
#include <cmath>

#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;

ProtocolOptions LoadProtocolConfig(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  return yaml_util::WithFormatErrors(path, [&] {
    ProtocolOptions o;
    o.path = path;
    o.name = Get<std::string>(path, root, "name");
    o.skeleton = Get<std::string>(path, root, "skeleton");
    const YAML::Node source = root["source"];
    if (!source || !source.IsMap())
      Fail(path, root, "missing mapping 'source' (format, unit_scale)");
    const std::string fmt = Get<std::string>(path, source, "format");
    if (const auto format = ValueNamed(fmt, kSourceFormatNames)) {
      o.format = *format;
    } else {
      Fail(path, source["format"],
           "source.format: expected " + NameChoices(kSourceFormatNames) + ", found '" + fmt + "'");
    }
    o.unit_scale = GetOr<double>(path, source, "unit_scale", 1.0);
    o.up = GetOr<std::string>(path, root, "up", "");
    if (!o.up.empty()) {
      static const std::vector<std::string> axes = {"x", "y", "z", "-x", "-y", "-z"};
      if (std::find(axes.begin(), axes.end(), o.up) == axes.end())
        Fail(path, root["up"], "up: expected x, y, z, -x, -y or -z, found '" + o.up + "'");
    }
    o.fps = Get<double>(path, root, "fps");
    o.t_his = Get<int>(path, root, "t_his");
    o.t_pred = Get<int>(path, root, "t_pred");
    o.min_length = GetOr<int>(path, root, "min_length", 0);
    if (o.min_length == 0) o.min_length = o.t_his + o.t_pred;
    const std::string r = GetOr<std::string>(path, root, "root", "relative_drop");
    if (const auto handling = ValueNamed(r, kRootHandlingNames)) {
      o.root = *handling;
    } else {
      Fail(path, root["root"],
           "root: expected " + NameChoices(kRootHandlingNames, "") + ", found '" + r + "'");
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
    if (const YAML::Node list = root["published"]) {
      if (!list.IsSequence())
        Fail(path, list, "published: expected a list of {method, source, apd, ade, fde, ...}");
      for (const YAML::Node& e : list) {
        if (!e.IsMap()) Fail(path, e, "published: expected {method, source, apd, ade, ...}");
        PublishedFigures f;
        f.method = Get<std::string>(path, e, "method");
        f.source = Get<std::string>(path, e, "source");
        const std::pair<const char*, double*> numbers[] = {{"apd", &f.apd},
                                                           {"ade", &f.ade},
                                                           {"fde", &f.fde},
                                                           {"mmade", &f.mmade},
                                                           {"mmfde", &f.mmfde}};
        for (const auto& [key, value] : numbers) {
          *value = Get<double>(path, e, key);
          if (!(*value >= 0) || !std::isfinite(*value))
            Fail(path, e[key], std::string("published.") + key + ": expected a number >= 0");
        }
        o.published.push_back(f);
      }
    }
    ValidateProtocol(o);
    return o;
  });
}

}  // namespace motionfork
