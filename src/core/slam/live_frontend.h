// The RGB-D front end of a running robot, fed message by message: frames (features extracted
// elsewhere + metric depth) and wheel odometry arrive in any interleaving, and the front end is
// given the same inputs, in the same order, as icgm_slam_offline gives its RgbdFrontend:
//  - a frame waits until the wheel samples up to wheel_lead_s after its stamp are in
//    (WheelPacedQueue, bounded by pacing.max_wait_s), then exactly the samples up to that instant
//    are handed over before it (WheelFeed, as RunSlam and the offline tool feed them);
//  - frames are processed in arrival order with RgbdFrontend::ProcessFeatures;
//  - each processed frame reports its result, the keyframe made during it and the vision step
//    since the previous processed frame (VisionStepChain: what the odometry fusion is given).
// The front end is created by Start once the camera and the base -> camera extrinsic are known
// (the caller waits for them); frames queue meanwhile. Not thread-safe: one caller at a time.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/odometry/vision_step.h"
#include "core/slam/wheel_feed.h"
#include "core/slam/wheel_paced_queue.h"

namespace icgm {

// One RGB-D frame as it arrives: the features of the colour image and the depth image.
struct LiveFrame {
  Time stamp;                          // the colour image's (the features')
  FeatureSet features;                 // moved into the front end when processed
  bool keypoints_undistorted = false;  // see RgbdFrontend::ProcessFeatures
  cv::Mat depth_m;                     // CV_32FC1 metres, registered to the colour image
  Time depth_stamp;
  std::string camera_frame;  // the camera's frame name, carried through for the outputs
};

struct LiveFrontendOptions {
  WheelPacedQueueOptions pacing;  // pacing.wheels false: a camera without wheels
  double wheel_lead_s = 0.05;     // as icgm_slam_offline (SlamRunOptions::wheel_lead_s)
};

// What one processed frame gives.
struct LiveFrameOutput {
  const LiveFrame* frame = nullptr;  // valid during the callback (its features moved out)
  FrontendFrameResult result;
  KeyframePtr new_keyframe;  // the keyframe the front end made during this frame, or null
  // With result.status ok: the step since the previous processed frame (none for the first).
  std::optional<VisionStepChain::Step> step;
  Status wheel_status =
      Status::Ok();             // the last wheel sample the front end refused before this frame
  bool missing_wheels = false;  // wheels expected but none received yet
  double thread_cpu_ms = 0.0;   // CPU time of the wheel feed + registration of this frame
};

class LiveFrontend {
 public:
  using Sink = std::function<void(const LiveFrameOutput&)>;
  // The colour image of the frame stamped `stamp` (frontend.select_by_evidence), or empty.
  using ColourFn = std::function<cv::Mat(Time stamp)>;

  explicit LiveFrontend(const LiveFrontendOptions& options);

  // Queues a frame; false when the oldest queued frame was dropped to make room.
  bool Push(LiveFrame frame);
  // A T_odom_base sample; false (dropped) when it is not newer than the last one.
  bool AddWheelOdometry(Time stamp, const Pose3& odom_base);

  // The oldest queued frame when its wheel data is in (or waited long enough), else nullptr.
  const LiveFrame* ReadyFront() { return queue_.ReadyFront(); }
  void DropFront() { queue_.PopFront(); }
  void Clear() { queue_.Clear(); }

  // Creates the front end (frontend.fusion.base_to_camera set by the caller) for camera `k`.
  void Start(const FrontendOptions& frontend, const CameraIntrinsics& k);
  bool started() const { return frontend_ != nullptr; }

  // After Start: processes the ready frames in order, `sink` after each. Returns their count.
  size_t Drain(const Sink& sink, const ColourFn& colour = ColourFn());

  const RgbdFrontend* frontend() const { return frontend_.get(); }
  size_t pending() const { return queue_.size(); }

 private:
  LiveFrontendOptions options_;
  WheelFeed wheel_;  // samples not yet given to the front end
  WheelPacedQueue<LiveFrame> queue_;
  std::unique_ptr<RgbdFrontend> frontend_;
  VisionStepChain steps_;
  KeyframePtr new_keyframe_;  // made by the front end during the current frame
};

}  // namespace icgm
