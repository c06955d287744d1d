#include "frontend/object_association.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace dslam {

void AssociationParams::validate() const {
  if (!(min_overlap > 0.0 && min_overlap <= 1.0)) throw std::invalid_argument("association min_overlap must be in (0, 1]");
}

ObjectAssociator::ObjectAssociator(const AssociationParams& params) : params_(params) { params_.validate(); }

std::map<int, int> ObjectAssociator::associate(const std::map<int, int>& label_areas,
                                               const std::map<int, std::map<int, int>>& votes,
                                               const std::map<int, int>& tracked) {
  std::map<int, int> object_of_label;
  if (params_.mask_ids_tracked) {
    for (const auto& [label, area] : label_areas) object_of_label[label] = label;
    return object_of_label;
  }
  // Candidate (votes, label, object) pairs, best first; greedy one-to-one.
  std::vector<std::tuple<int, int, int>> candidates;
  for (const auto& [label, by_object] : votes) {
    if (!label_areas.count(label)) continue;
    for (const auto& [object_id, n] : by_object) {
      const auto t = tracked.find(object_id);
      if (t == tracked.end() || t->second <= 0) continue;
      if (n >= params_.min_overlap * t->second) candidates.emplace_back(n, label, object_id);
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a > b; });
  std::set<int> taken_objects;
  for (const auto& [n, label, object_id] : candidates) {
    if (object_of_label.count(label) || taken_objects.count(object_id)) continue;
    object_of_label[label] = object_id;
    taken_objects.insert(object_id);
  }
  for (const auto& [label, area] : label_areas)
    if (!object_of_label.count(label)) object_of_label[label] = next_object_id_++;
  return object_of_label;
}

}  // namespace dslam
