// Residual trend of a reference keyframe's matches (frontend.residual_trend_*).
//
// While several frames register to the same keyframe, each reference keypoint's match is
// reprojected with the frame's final motion, frame after frame. A static point's residual stays
// at noise level; a slowly moving walker's point drifts steadily in one direction, growing with
// the frames since the keyframe, and its neighbours on the same body drift alike. Such points
// are voted out of the reference (their matches no longer reach ICGM and RANSAC) before they
// have pulled the motion along: a walker moving a few millimetres per frame stays inside the
// registration's tolerance for several frames and joins every consistent set there.
//
// Vote (Observe): a keypoint whose residual (pixels over the keypoint's sigma) over its last
// `frames` observations follows a line (least squares, both image axes) whose slope is at least
// `min_slope_sigmas` standard errors (from the scatter about the line, at least `noise_px`),
// growing by at least `min_growth_px` over them, the newest residual at least `min_drift_px`
// (observations beyond `max_residual_px` are not tracked: wrong matches); and
// with at least `min_neighbours` other such keypoints within `neighbour_radius_px` in the
// reference image drifting within `neighbour_max_angle_deg` of its direction. When more than
// `max_share` of the keypoints observed in the frame would be voted, none is: the motion then
// followed the walkers and the room is what drifts against it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace icgm {

struct ResidualTrendOptions {
  int frames = 0;  // observations a trend spans (0: off; at least 2 when on)
  double min_drift_px = 2.0;
  double min_growth_px = 2.0;
  double noise_px = 0.5;  // least scatter about the trend line assumed
  // The line's slope at least this many standard errors (the scatter about the line).
  double min_slope_sigmas = 3.0;
  // Matches further off are left out (wrong matches, outliers of every motion); a walker that
  // drifts a few pixels per frame is voted out before it gets this far.
  double max_residual_px = 12.0;
  int min_neighbours = 2;
  double neighbour_radius_px = 60.0;
  double neighbour_max_angle_deg = 45.0;
  double max_share = 0.5;
  // Residuals against the constant-velocity prediction instead of the frame's final motion.
  bool against_prediction = false;
  // Each frame's median residual is removed first (a common error of the motion, e.g. a pan
  // mistaken for a slide, shifts every point alike; a walker's own motion does not).
  bool remove_median = false;
  bool on() const { return frames >= 2; }
};

// One match of the frame to the reference: the reference keypoint, its pixel in the reference,
// and the current keypoint's offset from the reference point reprojected with the motion
// (pixels, divided by the keypoint's sigma).
struct TrendObservation {
  int reference_keypoint = -1;
  cv::Point2f reference_px;
  Eigen::Vector2d residual_px = Eigen::Vector2d::Zero();
};

class ResidualTrend {
 public:
  explicit ResidualTrend(const ResidualTrendOptions& options) : options_(options) {}

  // Starts over for the reference frame `reference_index` with `num_keypoints` keypoints.
  void Reset(size_t reference_index, size_t num_keypoints);
  bool tracking(size_t reference_index) const {
    return started_ && reference_index == reference_index_;
  }
  // One more frame registered to the reference; returns the reference keypoints voted out by it
  // (each at most once per reference).
  std::vector<int> Observe(const std::vector<TrendObservation>& observations);
  // Voted out of the current reference so far.
  bool voted(int reference_keypoint) const {
    return reference_keypoint >= 0 && static_cast<size_t>(reference_keypoint) < voted_.size() &&
           voted_[reference_keypoint];
  }
  size_t frames_observed() const { return frame_; }
  // Appends the current keypoint (trainIdx) of every match whose reference keypoint (queryIdx)
  // was voted out.
  void AppendMatchedToVoted(const std::vector<cv::DMatch>& matches,
                            std::vector<int>* current_keypoints) const {
    for (const cv::DMatch& m : matches) {
      if (voted(m.queryIdx)) current_keypoints->push_back(m.trainIdx);
    }
  }

 private:
  struct Sample {
    size_t frame = 0;
    Eigen::Vector2d residual_px;
  };
  // The keypoint's last `frames` samples show a steady drift; its direction in *direction.
  bool Drifting(const std::deque<Sample>& track, Eigen::Vector2d* direction) const;

  ResidualTrendOptions options_;
  bool started_ = false;
  size_t reference_index_ = 0;
  size_t frame_ = 0;
  std::vector<std::deque<Sample>> tracks_;
  std::vector<uint8_t> voted_;
};

}  // namespace icgm
