#pragma once
// Which object a current instance-mask label belongs to. When the segmenter tracks (its ids stay with
// an object over frames) the label is the object id. Otherwise labels are matched to the previous
// frame's objects by flow-propagated overlap: each previous object's tracked points, moved by the
// flow, vote for the label they land in; a label takes the object that sent it the most votes if at
// least `min_overlap` of that object's tracked points landed there, one label per object; other labels
// start new objects.

#include <map>

namespace dslam {

struct AssociationParams {
  bool mask_ids_tracked = true;
  double min_overlap = 0.3;
  void validate() const;
};

class ObjectAssociator {
 public:
  explicit ObjectAssociator(const AssociationParams& params);

  // votes[label][previous object id] = points of that object that landed in the label;
  // tracked[previous object id] = its points that the flow carried into this frame.
  // Returns label -> object id for every label of `labels`.
  std::map<int, int> associate(const std::map<int, int>& label_areas, const std::map<int, std::map<int, int>>& votes,
                               const std::map<int, int>& tracked);

 private:
  AssociationParams params_;
  int next_object_id_ = 1;
};

}  // namespace dslam
