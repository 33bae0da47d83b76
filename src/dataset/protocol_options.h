// Protocol options: which clips, skeleton, frame rate and window lengths an experiment uses.
// Filled from configs/protocols/*.yaml by config/protocol_config.h (keys and defaults are
// documented in configs/protocols/README.md).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/enum_names.h"

namespace motionfork {

enum class SourceFormat { kBvh, kVideoPose3d };
enum class RootHandling { kRelativeDrop, kRelative, kAbsolute };

// Their names in protocol configs (source.format, root).
inline constexpr EnumName<SourceFormat> kSourceFormatNames[] = {
    {SourceFormat::kBvh, "bvh"}, {SourceFormat::kVideoPose3d, "videopose3d"}};
inline constexpr EnumName<RootHandling> kRootHandlingNames[] = {
    {RootHandling::kRelativeDrop, "relative_drop"},
    {RootHandling::kRelative, "relative"},
    {RootHandling::kAbsolute, "absolute"}};

// A method's published figures on the protocol (K = 50, whole pose vectors, metres), as its paper
// reports them: what `motionfork eval` prints beside a model's.
struct PublishedFigures {
  std::string method;  // "GSPS"
  std::string source;  // "Mao et al., ICCV 2021, Table 1"
  double apd = 0, ade = 0, fde = 0, mmade = 0, mmfde = 0;
};

struct ProtocolOptions {
  std::string name;
  std::string path;      // the YAML it came from
  std::string skeleton;  // skeleton config name or path
  SourceFormat format = SourceFormat::kBvh;
  double unit_scale = 1.0;  // file length unit -> metres
  // The data's up axis ("y", "z", "-z", ...): the frame a model trained on it expects; motions of
  // another frame are turned into it (rig/body_frame.h). "" = not declared: kept as they come.
  std::string up;
  double fps = 0;      // Hz
  int t_his = 0;       // frames
  int t_pred = 0;      // frames
  int min_length = 0;  // frames; 0 -> t_his + t_pred
  RootHandling root = RootHandling::kRelativeDrop;
  std::string split_file;  // relative to the data folder unless absolute
  std::vector<std::string> train_subjects;
  std::vector<std::string> test_subjects;
  std::vector<std::pair<std::string, std::string>> drop_takes;  // (subject, action)
  std::string label_pattern;                                    // regex on clip names; empty = none
  int label_action_group = 0;
  int label_subject_group = 0;
  int test_stride = 0;  // frames; 0 -> t_his
  bool test_include_last = false;
  double multimodal_threshold = 0.5;  // metres
  bool keep_singleton_sets = true;
  std::vector<PublishedFigures> published;  // the protocol YAML's `published:` list

  int window_length() const { return t_his + t_pred; }
};

// Checks ranges (t_his >= 1, fps > 0, ...); throws std::invalid_argument naming field and rule.
void ValidateProtocol(const ProtocolOptions& options);

const char* ToString(SourceFormat format);
const char* ToString(RootHandling root);

}  // namespace motionfork
