#include "bodyparts/part_plan.h"

#include <stdexcept>

namespace motionfork {

int PartPlan::Index(const std::string& part) const {
  for (int p = 0; p < num_parts(); ++p) {
    if (names[p] == part) return p;
  }
  std::string known;
  for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("no body part '" + part + "' in partition '" + partition +
                              "'; its parts are: " + known);
}

std::vector<bool> PartPlan::FixedMask(const std::vector<std::string>& fixed) const {
  std::vector<bool> mask(names.size(), false);
  for (const std::string& f : fixed) {
    const int p = Index(f);
    if (mask[p]) throw std::invalid_argument("body part '" + f + "' is fixed twice");
    mask[p] = true;
  }
  return mask;
}

PartPlan MakePartPlan(const Skeleton& skeleton, const std::string& partition) {
  const Partition& p = skeleton.GetPartition(partition);
  PartPlan plan;
  plan.partition = p.name;
  for (const BodyPart& part : p.parts) {
    plan.names.push_back(part.name);
    std::vector<int64_t> nodes;
    for (int j : part.joints) nodes.push_back(j - 1);
    plan.nodes.push_back(std::move(nodes));
  }
  return plan;
}

}  // namespace motionfork
