// Rig conventions: how a family of skeletons (Mixamo, the Unreal mannequin, SMPL, Human3.6M, ...)
// names the joints of the human body.
//
// Every body joint has a role ("pelvis", "left_knee", ...; BodyRoles()). A convention says which
// of its joints plays each role, or how the position is made from its joints (a blend, e.g. a
// pelvis between the two hips). Conventions are tables, read from configs/rigs/*.yaml
// (config/rig_config.h); a user's joint map (--joint-map FILE) is one more table of the same form.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace motionfork {

// A position made from a rig's joints: one joint (weights {1}) or a weighted mean of several.
struct JointBlend {
  std::vector<std::string> joints;
  std::vector<double> weights;  // one per joint, summing to 1
};

struct RigConvention {
  std::string name;
  std::string path;  // the YAML file it came from ("" when made in code)
  // role -> the ways this rig makes it, most preferred first (spelling variants such as
  // "LeftUpLeg" / "L_Hip"); the first whose joints a rig has is used.
  std::map<std::string, std::vector<JointBlend>> roles;
  // Other joints characteristic of the rig ("HeadTop_End", "LowerBack"): they count only when
  // telling which convention a rig follows.
  std::vector<std::string> also;
};

// The roles, in a fixed order: pelvis, spine, chest, neck, head, head_end, then per side
// clavicle, shoulder, elbow, wrist, hip, knee, ankle, toe (left_..., right_...), then root (the
// ground projection some rigs carry).
const std::vector<std::string>& BodyRoles();
bool IsBodyRole(std::string_view role);

// How a role is made when a rig has no joint for it: the pelvis between the hips, the spine
// between pelvis and chest, the neck between chest and head, the chest between the shoulders.
// Empty for roles that cannot be made.
const std::vector<std::pair<std::string, double>>& DerivedRole(const std::string& role);

// How joint names are compared: lower case, a namespace prefix dropped ("mixamorig:Hips",
// "Character1:Hips" -> "hips"), and '_', '-', '.' and spaces removed ("Left_Up-Leg" ->
// "leftupleg").
std::string NormalizeJointName(std::string_view name);

}  // namespace motionfork
