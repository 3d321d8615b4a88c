// The feature extraction nodelet's frames: features of each colour image, extracted alone or,
// with ~track, through the robust feature tracker (ICGM between consecutive frames; the
// double-directional mode completes a frame when the next one arrives). The last few images
// are kept (a view of the message's pixels when extraction only reads them) so the completed
// frame's image and frame id are at hand for its message and debug overlay. A stamp not after
// the last restarts the tracks.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <sensor_msgs/Image.h>
#include <opencv2/core.hpp>

#include "core/common/status.h"
#include "core/common/time.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/robust_feature_tracker.h"

namespace icgm::nodelets {

class FeatureFrames {
 public:
  struct Completed {
    TrackedFrame frame;
    const cv::Mat* bgr = nullptr;            // its undistorted image (null: no longer kept)
    std::string frame_id;                    // its camera frame (empty: no longer kept)
    const TrackedFrame* previous = nullptr;  // the frame completed before it
  };
  // `track`: through the tracker (options.mode, window); else extraction with options.features.
  FeatureFrames(bool track, const TrackerOptions& options);

  bool tracking() const { return tracker_ != nullptr; }
  // The image's colour pixels (a view of the message without tracking, a copy with it), for
  // `undistort` to map into the undistorted image.
  Status Read(const sensor_msgs::ImageConstPtr& msg, cv::Mat* bgr) const;
  // Adds the (undistorted) image of `msg`; returns the frame completed now, if any.
  // *restarted: the stamp was not after the last one.
  std::optional<Completed> Add(const sensor_msgs::ImageConstPtr& msg, const cv::Mat& bgr,
                               bool* restarted);
  // After the completed frame was published: it becomes the previous frame.
  void Published(TrackedFrame frame) { previous_ = std::move(frame); }
  const std::optional<Time>& last_stamp() const { return last_stamp_; }

 private:
  struct Stored {
    Time stamp;
    cv::Mat bgr;
    std::string frame_id;
    sensor_msgs::ImageConstPtr source;  // owns bgr's pixels when bgr is a view of it
  };
  std::unique_ptr<RobustFeatureTracker> tracker_;  // track
  std::unique_ptr<FeatureExtractor> extractor_;    // without track
  std::vector<Stored> history_;
  std::optional<TrackedFrame> previous_;
  std::optional<Time> last_stamp_;
};

}  // namespace icgm::nodelets
