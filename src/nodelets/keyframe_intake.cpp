#include "nodelets/keyframe_intake.h"

#include <string>
#include <utility>

#include <icgm_slam/FlushKeyframe.h>

#include "nodelets/keyframe_outlet.h"
#include "ros_bridge/image_size.h"
#include "ros_bridge/keyframe_msgs.h"

namespace icgm::nodelets {

KeyframeIntake::KeyframeIntake(ros::NodeHandle& nh, const ros::NodeHandle& pnh, LiveMap* map,
                               const CameraModelReader* camera, const tf2_ros::Buffer& tf,
                               const std::string& odom_frame, std::string map_features_source,
                               Callbacks callbacks)
    : map_(map),
      camera_(camera),
      map_features_source_(std::move(map_features_source)),
      callbacks_(std::move(callbacks)),
      tf_wait_s_(Param(pnh, "tf_wait_s", 0.5)),
      waiting_(std::make_unique<OdometryWait>(tf, odom_frame, tf_wait_s_)),
      flush_(nh.serviceClient<icgm_slam::FlushKeyframe>(KeyframeFlushService(nh))),
      keyframes_topic_(nh.resolveName("keyframes")) {}

void KeyframeIntake::Add(const icgm_slam::Keyframe& msg) {
  // Features chosen as this map's map.yaml says, or none (never a silent difference).
  if (msg.map_features_source != map_features_source_) {
    ROS_ERROR_THROTTLE(10.0,
                       "map builder: keyframe refused: its features follow "
                       "map_features.source '%s', this map's map.yaml says '%s' (give the "
                       "registration nodelet ~map_config_file = this map.yaml)",
                       msg.map_features_source.c_str(), map_features_source_.c_str());
    return;
  }
  if (!map_->started() && !Start(msg.camera_info)) return;
  if (!Fits(msg)) return;
  FrontendKeyframe keyframe;
  if (const Status s = ros_bridge::FromKeyframeMsg(msg, &keyframe); !s.ok()) {
    ROS_WARN_THROTTLE(5.0, "map builder: bad keyframe: %s", s.reason().c_str());
    return;
  }
  camera_frame_ = msg.header.frame_id;
  waiting_->Push(std::move(keyframe), msg.header.frame_id, msg.header.stamp);
  Drain();
}

// The system needs intrinsics: it starts with the first keyframe's camera.
bool KeyframeIntake::Start(const sensor_msgs::CameraInfo& info) {
  CameraIntrinsics k;
  Status s = camera_->Read(info, &k);
  std::string loaded;
  try {
    if (s.ok()) s = map_->Start(k, &loaded);
  } catch (const LoadError& e) {  // a back end this build lacks
    s = Status::Error(e.what());
  }
  if (!map_->started()) {
    ROS_ERROR_THROTTLE(5.0, "map builder: cannot start: %s", s.reason().c_str());
    return false;
  }
  camera_info_ = info;
  if (!s.ok()) ROS_ERROR("map builder: cannot load map: %s", s.reason().c_str());
  if (!loaded.empty()) ROS_INFO("map builder: loaded %s", loaded.c_str());
  if (!loaded.empty() && callbacks_.loaded) callbacks_.loaded();
  if (map_->LocalizingWithoutMap()) {
    ROS_WARN(
        "map builder: localization without a map: nothing to localize against "
        "(give ~load_map or call load_map)");
  }
  return true;
}

bool KeyframeIntake::Fits(const icgm_slam::Keyframe& msg) {
  const std::string camera = keyframes_topic_ + " (the map's camera_info)";
  Status fits = ros_bridge::CheckImageSize(msg.depth, keyframes_topic_ + " depth", camera_info_,
                                           camera);
  if (fits.ok() && !msg.image.data.empty()) {
    fits = ros_bridge::CheckImageSize(msg.image, keyframes_topic_ + " image", camera_info_, camera);
  }
  if (fits.ok()) return true;
  ROS_ERROR_THROTTLE(5.0, "map builder: keyframe refused (%zu so far): %s", ++refused_,
                     fits.reason().c_str());
  return false;
}

void KeyframeIntake::Drain() {
  std::string error;
  const int dropped = waiting_->Drain(
      [this](FrontendKeyframe& keyframe, const Pose3& odom_camera) {
        keyframe.odom_camera = odom_camera;  // the fused odometry, the frame tf publishes
        Process(keyframe);
      },
      &error);
  if (dropped > 0) {
    ROS_WARN_THROTTLE(5.0, "map builder: no odometry for a keyframe (%s); skipped", error.c_str());
  }
}

void KeyframeIntake::Process(const FrontendKeyframe& keyframe) {
  const LiveMapUpdate update = map_->AddKeyframe(keyframe);
  const SlamFrameResult& result = update.result;
  if (!result.map_status.ok()) {
    ROS_WARN("map builder: %s", result.map_status.reason().c_str());
  } else {
    const SlamSystem& system = *map_->system();
    const bool localizing = system.mode() == MapMode::kLocalization;
    if (result.update.loop_closed && localizing) {
      ROS_INFO_THROTTLE(5.0, "map builder: localized (%zu fixes)", system.relocalizations());
    } else if (result.update.loop_closed) {
      ROS_INFO("map builder: loop closed at keyframe %d (%d keyframes)", result.keyframe_id,
               system.map().size());
    } else if (localizing && !system.localized()) {
      ROS_INFO_THROTTLE(5.0, "map builder: not localized yet (%s)",
                        result.update.loop.status.reason().c_str());
    }
    if (!update.autosave.ok()) {
      ROS_ERROR("map builder: autosave failed: %s", update.autosave.reason().c_str());
    }
  }
  if (callbacks_.added) callbacks_.added(update);
}

void KeyframeIntake::FlushBeforeModeSwitch() {
  if (flush_.exists()) {  // a registration nodelet runs
    icgm_slam::FlushKeyframe flush;
    if (!flush_.call(flush)) {
      ROS_WARN("map builder: %s failed: a held keyframe enters after the mode switch",
               flush_.getService().c_str());
    } else if (flush.response.held) {
      Add(flush.response.keyframe);
    }
  }
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(tf_wait_s_);
  while (waiting_->size() > 0 && ros::WallTime::now() < until) {
    ros::WallDuration(0.01).sleep();
    Drain();
  }
  if (waiting_->size() > 0) {
    ROS_WARN(
        "map builder: %zu keyframes still wait for their odometry: they enter the map after "
        "the mode switch",
        waiting_->size());
  }
}

}  // namespace icgm::nodelets
