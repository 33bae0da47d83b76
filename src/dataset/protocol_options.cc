#include "dataset/protocol_options.h"

#include <regex>
#include <stdexcept>

namespace motionfork {

const char* ToString(SourceFormat format) { return NameOf(format, kSourceFormatNames); }

const char* ToString(RootHandling root) { return NameOf(root, kRootHandlingNames); }

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

}  // namespace motionfork
