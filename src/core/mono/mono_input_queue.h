// Images of a live monocular stream held until their inputs are complete, so that the odometry
// gets what an offline run gives it (icgm_mono_vo --bag: every wheel sample up to an image's
// stamp before that image). Without wheels an image is ready at once. With wheels it waits
// until a wheel sample at or after its stamp arrived; once more than max_wait_images images came
// in since the last wheel sample, the wheels count as stopped and images go on without them.
// Images leave in arrival order. Not thread-safe.
#pragma once

#include <deque>

#include <opencv2/core.hpp>

#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/dataset/trajectory.h"

namespace icgm {

// One image ready for MonoOdometry::ProcessFrame, after its wheel samples.
struct MonoInput {
  Time stamp;
  cv::Mat image;
  Trajectory wheel;  // T_odom_base samples up to the stamp not handed out before, in order
};

class MonoInputQueue {
 public:
  // wheels: wait for wheel samples; max_wait_images >= 0.
  MonoInputQueue(bool wheels, int max_wait_images)
      : wheels_(wheels), max_wait_images_(max_wait_images) {}

  void AddImage(Time stamp, cv::Mat image);
  // Ignored without wheels.
  void AddWheel(Time stamp, const Pose3& odom_base);
  // The oldest image when it is ready (false: none held, or it waits for the wheels).
  bool Pop(MonoInput* input);
  // Drops the held images (kept wheel samples stay); returns how many.
  size_t DropImages();
  size_t num_images() const { return images_.size(); }

 private:
  bool wheels_;
  int max_wait_images_;
  std::deque<MonoInput> images_;
  std::deque<StampedPose> wheel_;
  int images_since_wheel_ = 0;  // images received since the last wheel sample
};

}  // namespace icgm
