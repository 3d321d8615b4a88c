#include "core/slam/live_frontend.h"

#include <utility>

#include "core/common/thread_cpu_time.h"

namespace icgm {

LiveFrontend::LiveFrontend(const LiveFrontendOptions& options)
    : options_(options), wheel_(options.wheel_lead_s), queue_(options.pacing, &wheel_) {}

bool LiveFrontend::Push(LiveFrame frame) {
  const Time stamp = frame.stamp;
  return queue_.Push(stamp, std::move(frame));
}

bool LiveFrontend::AddWheelOdometry(Time stamp, const Pose3& odom_base) {
  if (!wheel_.Add(stamp, odom_base)) return false;
  queue_.Note(stamp);
  return true;
}

void LiveFrontend::Start(const FrontendOptions& frontend, const CameraIntrinsics& k) {
  frontend_ = std::make_unique<RgbdFrontend>(frontend, k);
  frontend_->SetKeyframeCallback([this](const KeyframePtr& keyframe) { new_keyframe_ = keyframe; });
}

size_t LiveFrontend::Drain(const Sink& sink, const ColourFn& colour) {
  if (!frontend_) return 0;
  size_t processed = 0;
  while (LiveFrame* frame = queue_.ReadyFront()) {
    LiveFrameOutput out;
    out.frame = frame;
    out.missing_wheels = options_.pacing.wheels && !wheel_.received_any();
    const double cpu0 = ThreadCpuMs();
    wheel_.FeedUpTo(frame->stamp, [&](Time t, const Pose3& odom_base) {
      if (Status s = frontend_->AddWheelOdometry(t, odom_base); !s.ok()) out.wheel_status = s;
    });
    new_keyframe_.reset();
    out.result = frontend_->ProcessFeatures(
        frame->stamp, std::move(frame->features), frame->depth_m, frame->depth_stamp,
        colour ? colour(frame->stamp) : cv::Mat(), frame->keypoints_undistorted);
    out.new_keyframe = std::move(new_keyframe_);
    if (out.result.status.ok()) out.step = steps_.Add(out.result);
    out.thread_cpu_ms = ThreadCpuMs() - cpu0;
    sink(out);
    queue_.PopFront();
    ++processed;
  }
  return processed;
}

}  // namespace icgm
