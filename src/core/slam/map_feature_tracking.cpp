#include "core/slam/map_feature_tracking.h"

#include <utility>

#include "core/common/option_reader.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/odometry/rgbd_frontend.h"

namespace icgm {

MapFeatureOptions LoadMapFeatureOptions(const std::string& map_config_file,
                                        const std::string& icgm_config_file) {
  SlamOptions options;
  ReadOptions(OptionReader::FromFile(icgm_config_file), &options.map_features.tracker);
  ReadMapSlamOptions(OptionReader::FromFile(map_config_file), &options);
  return options.map_features;
}

MapFeatureTracking::MapFeatureTracking(const MapFeatureOptions& options) {
  if (options.source == MapFeatureSource::kTracker) {
    tracker_ = std::make_unique<RobustFeatureTracker>(options.tracker);
  }
}

MapFeatureTracking::~MapFeatureTracking() = default;

std::optional<FrontendKeyframe> MapFeatureTracking::AfterFrame(const RgbdFrontend& frontend,
                                                               KeyframePtr new_keyframe) {
  Time stamp;
  const FeatureSet* features = frontend.last_frame_features(&stamp);
  return AfterFrame(stamp, features, std::move(new_keyframe));
}

std::optional<FrontendKeyframe> MapFeatureTracking::AfterFrame(Time stamp,
                                                               const FeatureSet* features,
                                                               KeyframePtr new_keyframe) {
  if (!tracker_) {
    if (!new_keyframe) return std::nullopt;
    return *new_keyframe;
  }
  std::optional<TrackedFrame> tracked;
  if (features && (!tracked_stamp_ || stamp > *tracked_stamp_)) {
    tracked_stamp_ = stamp;
    tracked = tracker_->AddFeatures(stamp, *features);
  }
  std::optional<FrontendKeyframe> released;
  // The held keyframe's frame is the one the tracker completes now (its successor arrived).
  if (held_ && tracked) released = Release(tracked);
  if (new_keyframe) held_ = std::move(new_keyframe);
  return released;
}

std::optional<FrontendKeyframe> MapFeatureTracking::Flush() {
  if (!tracker_) return std::nullopt;
  const std::optional<TrackedFrame> last = tracker_->Flush();
  tracked_stamp_.reset();
  if (!held_) return std::nullopt;
  return Release(last);
}

std::optional<FrontendKeyframe> MapFeatureTracking::ReleaseHeld() {
  if (!tracker_ || !held_) return std::nullopt;
  return Release(tracker_->PeekLast());
}

std::optional<FrontendKeyframe> MapFeatureTracking::Release(
    const std::optional<TrackedFrame>& tracked) {
  FrontendKeyframe keyframe = *held_;
  held_.reset();
  if (tracked && tracked->stamp == keyframe.stamp &&
      tracked->robust.size() == keyframe.features.size()) {
    keyframe.robust = tracked->robust;
  }
  return keyframe;
}

}  // namespace icgm
