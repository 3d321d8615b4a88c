#include "core/viz/feature_overlay.h"

#include <string>

#include <opencv2/imgproc.hpp>

namespace icgm {

cv::Mat DrawFeatureOverlay(const cv::Mat& image, const TrackedFrame& frame,
                           const TrackedFrame* previous) {
  cv::Mat out;
  if (image.channels() == 1) {
    cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, out, cv::COLOR_BGRA2BGR);
  } else {
    out = image.clone();
  }
  const cv::Scalar kRobust(60, 220, 60);
  const cv::Scalar kOther(40, 40, 230);
  const cv::Scalar kMotion(255, 200, 0);
  const auto& kps = frame.features.keypoints;
  for (size_t i = 0; i < kps.size(); ++i) {
    const bool robust = i < frame.robust.size() && frame.robust[i];
    if (!robust) cv::circle(out, kps[i].pt, 2, kOther, cv::FILLED, cv::LINE_AA);
  }
  for (size_t i = 0; i < kps.size(); ++i) {
    const bool robust = i < frame.robust.size() && frame.robust[i];
    if (!robust) continue;
    const int radius = std::max(3, static_cast<int>(kps[i].size * 0.25f));
    cv::circle(out, kps[i].pt, radius, kRobust, 1, cv::LINE_AA);
  }
  if (previous) {
    const auto& prev_kps = previous->features.keypoints;
    for (size_t m = 0; m < frame.matches_to_previous.size(); ++m) {
      if (m >= frame.match_kept.size() || !frame.match_kept[m]) continue;
      const cv::DMatch& d = frame.matches_to_previous[m];
      if (d.queryIdx < 0 || d.trainIdx < 0 || static_cast<size_t>(d.queryIdx) >= kps.size() ||
          static_cast<size_t>(d.trainIdx) >= prev_kps.size()) {
        continue;
      }
      cv::line(out, kps[d.queryIdx].pt, prev_kps[d.trainIdx].pt, kMotion, 1, cv::LINE_AA);
    }
  }
  const std::string label = std::to_string(frame.NumRobust()) + " robust / " +
                            std::to_string(kps.size()) + " features";
  cv::rectangle(out, {0, 0}, {std::min(out.cols, 8 + 9 * static_cast<int>(label.size())), 22},
                cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(out, label, {4, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  return out;
}

}  // namespace icgm
