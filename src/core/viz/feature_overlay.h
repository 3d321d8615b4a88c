// Debug overlay of a tracked frame, like thesis Fig. 6.4: robust (ICGM-kept) keypoints as green
// circles sized by keypoint scale, other keypoints as small red dots, and the kept motion of
// each robust keypoint as a short line towards its position in the previous frame.
#pragma once

#include <opencv2/core.hpp>

#include "core/icgm/robust_feature_tracker.h"

namespace icgm {

// `image` is BGR or gray (8-bit); `previous` may be null (no motion lines). Returns a new BGR
// image; `image` is not modified.
cv::Mat DrawFeatureOverlay(const cv::Mat& image, const TrackedFrame& frame,
                           const TrackedFrame* previous);

}  // namespace icgm
