#pragma once
// Where a point of an object lands in the next image when all that is known of the object's motion is
// its instance mask's bounding box in both images (a new object, or one back from an occlusion).

#include <opencv2/core.hpp>

namespace dslam {

// Where pixel `px` of an object whose mask box was `before` lands when its box is `now`, by the boxes'
// shift and scale, in an image of `width` x `height`. A box cut by the image border has a wrong extent
// on that side: the scale then comes from the other axis (or is 1) and the box is anchored at its uncut
// edge, so that a car leaving the view is predicted leaving it, not squeezed into it. The result may lie
// outside the image.
cv::Point2f PredictFromMaskBoxes(const cv::Rect& before, const cv::Rect& now, const cv::Point2f& px, int width,
                                 int height);

}  // namespace dslam
