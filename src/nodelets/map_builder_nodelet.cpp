// Map-building nodelet (thesis ch. 6.1.1.2): robust features + registered depth + the fused
// odometry (tf odom -> camera) become metric models of the hybrid map; loop closure corrects the
// map (eq. 6.2, 6.4) and the correction is published as tf map -> odom (REP-105). Publishes the
// graph (MarkerArray), the map cloud (PointCloud2) and the keyframe path, each built only while
// someone listens; services save / load (merge) the SQLite map and switch mapping/localization.
// The map is saved atomically on every loop closure, every `autosave_every_keyframes` keyframes
// and at shutdown, so an abort of the manager loses at most the last few keyframes.
#include <algorithm>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include <boost/bind/bind.hpp>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <icgm_slam/LoadMap.h>
#include <icgm_slam/SaveMap.h>
#include <icgm_slam/SetMapMode.h>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "core/odometry/odometry_fusion.h"
#include "core/odometry/wheel_odometry_buffer.h"
#include "core/slam/observation_keyframer.h"
#include "core/slam/slam_system.h"
#include "nodelets/sensor_calibration.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"
#include "ros_bridge/map_msgs.h"

namespace icgm_slam {

class MapBuilderNodelet : public nodelet::Nodelet {
 public:
  ~MapBuilderNodelet() override { SaveIfConfigured("shutdown"); }

 private:
  using Features = icgm_slam::RobustFeatures;
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using Policy = message_filters::sync_policies::ApproximateTime<Features, Image, Info>;

  struct Observation {
    Features::ConstPtr features;
    Image::ConstPtr depth;
    Info::ConstPtr info;
  };

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_dir, mode, load_path;
    pnh.param<std::string>("config_dir", config_dir, "");
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("odom_frame", odom_frame_, "odom");
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param<std::string>("map_path", map_path_, "");
    pnh.param<std::string>("load_map", load_path, "");
    pnh.param<std::string>("mode", mode, "mapping");
    pnh.param("autosave_every_keyframes", autosave_every_keyframes_, 20);
    pnh.param("queue_size", queue_size_, 10);
    pnh.param("depth_scale", depth_scale_, 1000.0);
    // Depth scale and timing, rolling shutter: ~camera_config_file and single parameters.
    std::string calibration_error;
    sensor_calibration_ = icgm::nodelets::ReadSensorCalibration(pnh, &calibration_error);
    if (!calibration_error.empty()) {
      NODELET_ERROR("map builder: %s (ignored)", calibration_error.c_str());
    }
    pnh.param("tf_wait_s", tf_wait_s_, 0.5);
    icgm::KeyframerOptions keyframer_options;
    try {
      options_ = icgm::LoadSlamOptions(config_dir);
      const auto map_yaml = icgm::OptionReader::FromFile(config_dir + "/map.yaml");
      icgm::ReadOptions(map_yaml.Section("keyframer"), &keyframer_options);
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("map builder: bad configuration: %s", e.what());
      throw;
    }
    keyframer_ = std::make_unique<icgm::ObservationKeyframer>(keyframer_options);
    if (!load_path.empty()) pending_load_ = load_path;
    pending_mode_ = mode;
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);

    // Publications
    graph_pub_ = nh.advertise<visualization_msgs::MarkerArray>("map/graph", 1, true);
    cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("map/cloud", 1, true);
    path_pub_ = nh.advertise<nav_msgs::Path>("map/path", 1, true);
    save_srv_ = pnh.advertiseService("save_map", &MapBuilderNodelet::saveCb, this);
    load_srv_ = pnh.advertiseService("load_map", &MapBuilderNodelet::loadCb, this);
    mode_srv_ = pnh.advertiseService("set_mode", &MapBuilderNodelet::modeCb, this);
    tf_timer_ = nh.createTimer(ros::Duration(0.1), [this](const ros::TimerEvent&) { publishTf(); });
    // Subscriptions (eager: the map is state)
    features_sub_.subscribe(nh, "features", queue_size_);
    depth_sub_.subscribe(nh, "depth", queue_size_);
    info_sub_.subscribe(nh, "camera_info", queue_size_);
    sync_ = std::make_unique<message_filters::Synchronizer<Policy>>(
        Policy(queue_size_), features_sub_, depth_sub_, info_sub_);
    sync_->registerCallback(boost::bind(&MapBuilderNodelet::frameCb, this, boost::placeholders::_1,
                                        boost::placeholders::_2, boost::placeholders::_3));
    // Wheel odometry for the wheel-odometry links beside visual steps (map.wheel_links).
    if (options_.map.map.wheel_links) {
      wheel_ = std::make_unique<icgm::WheelOdometryBuffer>(options_.frontend.wheel);
      wheel_sub_ = nh.subscribe("wheel_odom", 200, &MapBuilderNodelet::wheelCb, this);
    }
  }

  void wheelCb(const nav_msgs::Odometry::ConstPtr& msg) {
    const icgm::Status s = wheel_->Add(icgm::ros_bridge::FromRos(msg->header.stamp),
                                       icgm::ros_bridge::FromPoseMsg(msg->pose.pose));
    if (!s.ok()) NODELET_WARN_THROTTLE(5.0, "map builder: wheel odometry: %s", s.reason().c_str());
  }

  // The wheels' motion since the previous keyframe, moved into the camera frame with the
  // base -> camera extrinsic from tf. Left unset (no wheel link) without wheel data covering
  // the span or without the extrinsic.
  void AttachWheelMotion(const std::string& camera_frame, icgm::FrontendKeyframe* keyframe) {
    const std::optional<icgm::Time> previous = last_keyframe_stamp_;
    last_keyframe_stamp_ = keyframe->stamp;
    if (!wheel_ || !previous) return;
    icgm::Pose3 base_motion;
    if (const icgm::Status s = wheel_->RelativeMotion(*previous, keyframe->stamp, &base_motion);
        !s.ok()) {
      NODELET_DEBUG("map builder: no wheel link: %s", s.reason().c_str());
      return;
    }
    icgm::Pose3 base_to_camera;
    try {
      base_to_camera = icgm::ros_bridge::FromTransformMsg(
          tf_buffer_.lookupTransform(base_frame_, camera_frame, ros::Time(0)).transform);
    } catch (const tf2::TransformException& e) {
      NODELET_WARN_THROTTLE(5.0, "map builder: no wheel link without %s -> %s: %s",
                            base_frame_.c_str(), camera_frame.c_str(), e.what());
      return;
    }
    keyframe->wheel_camera_motion = icgm::CameraMotionFromBase(base_motion, base_to_camera);
  }

  // The system needs intrinsics, so it is created with the first camera_info.
  bool EnsureSystem(const Info& info) {
    if (system_) return true;
    icgm::CameraIntrinsics k;
    if (icgm::Status s = icgm::ros_bridge::FromCameraInfo(info, depth_scale_, &k); !s) {
      NODELET_WARN_THROTTLE(5.0, "map builder: bad camera_info: %s", s.reason().c_str());
      return false;
    }
    icgm::CopySensorCalibration(sensor_calibration_, &k);
    intrinsics_ = k;
    system_ = std::make_unique<icgm::SlamSystem>(options_, k);
    if (pending_load_) {
      const icgm::Status s = system_->Load(*pending_load_, false);
      if (s.ok()) {
        NODELET_INFO("map builder: loaded %d keyframes from %s", system_->map().size(),
                     pending_load_->c_str());
      } else {
        NODELET_ERROR("map builder: cannot load map: %s", s.reason().c_str());
      }
      pending_load_.reset();
    }
    setMode(pending_mode_);
    return true;
  }

  void frameCb(const Features::ConstPtr& f, const Image::ConstPtr& d, const Info::ConstPtr& i) {
    if (!EnsureSystem(*i)) return;
    queue_.push_back({f, d, i});
    // The fused odometry for a frame may arrive after the frame: wait for tf, bounded.
    while (!queue_.empty()) {
      const Observation& o = queue_.front();
      geometry_msgs::TransformStamped odom_camera;
      try {
        odom_camera = tf_buffer_.lookupTransform(odom_frame_, o.features->header.frame_id,
                                                 o.features->header.stamp);
      } catch (const tf2::TransformException& e) {
        const double age = (f->header.stamp - o.features->header.stamp).toSec();
        if (age < tf_wait_s_) return;
        NODELET_WARN_THROTTLE(5.0, "map builder: no odometry for a frame (%s); frame skipped",
                              e.what());
        queue_.pop_front();
        continue;
      }
      process(o, icgm::ros_bridge::FromTransformMsg(odom_camera.transform));
      queue_.pop_front();
    }
  }

  void process(const Observation& o, const icgm::Pose3& odom_camera) {
    icgm::TrackedFrame frame;
    cv::Mat depth_m;
    if (icgm::Status s = icgm::ros_bridge::FromFeaturesMsg(*o.features, &frame); !s) {
      NODELET_WARN_THROTTLE(5.0, "map builder: bad features: %s", s.reason().c_str());
      return;
    }
    if (icgm::Status s = icgm::ros_bridge::DepthFromImageMsg(*o.depth, depth_scale_, &depth_m); !s) {
      NODELET_WARN_THROTTLE(5.0, "map builder: bad depth: %s", s.reason().c_str());
      return;
    }
    last_stamp_ = o.features->header.stamp;
    auto keyframe = keyframer_->Offer(frame, depth_m, intrinsics_, odom_camera,
                                      icgm::MotionSource::kVision,
                                      icgm::ros_bridge::FromRos(o.depth->header.stamp));
    if (!keyframe) return;
    AttachWheelMotion(o.features->header.frame_id, &*keyframe);
    const icgm::SlamFrameResult result = system_->AddKeyframe(*keyframe);
    if (!result.map_status.ok()) {
      NODELET_WARN("map builder: %s", result.map_status.reason().c_str());
      return;
    }
    ++keyframes_since_save_;
    if (result.update.loop_closed) {
      NODELET_INFO("map builder: loop closed at keyframe %d (%d keyframes)", result.keyframe_id,
                   system_->map().size());
      SaveIfConfigured("loop closure");
    } else if (autosave_every_keyframes_ > 0 &&
               keyframes_since_save_ >= autosave_every_keyframes_) {
      SaveIfConfigured("autosave");
    }
    publishTf();
    publishMap();
  }

  void publishTf() {
    if (!system_ || last_stamp_.isZero()) return;
    geometry_msgs::TransformStamped t;
    // Stamped slightly ahead so consumers can look up map -> base_link at the latest odometry;
    // never twice with one stamp (tf2 rejects repeated data).
    t.header.stamp = std::max(last_stamp_ + ros::Duration(0.1), ros::Time::now());
    if (t.header.stamp <= last_tf_stamp_) return;
    last_tf_stamp_ = t.header.stamp;
    t.header.frame_id = map_frame_;
    t.child_frame_id = odom_frame_;
    t.transform = icgm::ros_bridge::ToTransformMsg(system_->MapFromOdom());
    tf_broadcaster_.sendTransform(t);
  }

  void publishMap() {
    const auto& map = system_->map();
    const icgm::Time stamp = icgm::ros_bridge::FromRos(last_stamp_);
    if (graph_pub_.getNumSubscribers() > 0)
      graph_pub_.publish(icgm::ros_bridge::ToGraphMarkers(map, map_frame_, stamp));
    if (cloud_pub_.getNumSubscribers() > 0)
      cloud_pub_.publish(icgm::ros_bridge::ToMapCloud(map, map_frame_, stamp));
    if (path_pub_.getNumSubscribers() > 0)
      path_pub_.publish(icgm::ros_bridge::ToKeyframePath(map, map_frame_, stamp));
  }

  void SaveIfConfigured(const char* why) {
    if (!system_ || map_path_.empty() || system_->map().empty()) return;
    const icgm::Status s = system_->Save(map_path_);
    if (s.ok()) {
      keyframes_since_save_ = 0;
      NODELET_DEBUG("map builder: saved %d keyframes to %s (%s)", system_->map().size(),
                    map_path_.c_str(), why);
    } else {
      NODELET_ERROR("map builder: save failed (%s): %s", why, s.reason().c_str());
    }
  }

  bool setMode(const std::string& mode) {
    if (mode == "mapping") {
      system_->SetMode(icgm::MapMode::kMapping);
    } else if (mode == "localization") {
      system_->SetMode(icgm::MapMode::kLocalization);
    } else {
      return false;
    }
    return true;
  }

  bool saveCb(icgm_slam::SaveMap::Request& req, icgm_slam::SaveMap::Response& res) {
    const std::string path = req.path.empty() ? map_path_ : req.path;
    if (!system_ || path.empty()) {
      res.success = false;
      res.message = !system_ ? "no map yet (no camera_info received)" : "no path given";
      return true;
    }
    // Saved as it is first, so nothing is lost if the refinement fails; then bundle-adjusted
    // (map_refinement.h) and saved again.
    icgm::Status s = system_->Save(path);
    std::string refined;
    if (s.ok() && system_->options().map_refinement.enabled && system_->map().size() > 1) {
      icgm::MapRefinementSummary summary;
      const icgm::Status r = system_->RefineMap(&summary);
      if (r.ok()) {
        s = system_->Save(path);
        refined = " (bundle-adjusted: " + std::to_string(summary.bundle_adjustment.points) +
                  " points)";
      } else {
        NODELET_WARN("map builder: map not refined: %s", r.reason().c_str());
        refined = " (not refined: " + r.reason() + ")";
      }
    }
    res.success = s.ok();
    res.message = s.ok() ? "saved " + std::to_string(system_->map().size()) + " keyframes to " +
                               path + refined
                         : s.reason();
    return true;
  }

  bool loadCb(icgm_slam::LoadMap::Request& req, icgm_slam::LoadMap::Response& res) {
    if (!system_) {
      pending_load_ = req.path;
      res.success = true;
      res.message = "will load when the first camera_info arrives";
      return true;
    }
    const icgm::Status s = system_->Load(req.path, req.merge);
    res.success = s.ok();
    res.message = s.ok() ? "map has " + std::to_string(system_->map().size()) + " keyframes"
                         : s.reason();
    if (s.ok()) {
      keyframer_->Reset();
      last_keyframe_stamp_.reset();
    }
    return true;
  }

  bool modeCb(icgm_slam::SetMapMode::Request& req, icgm_slam::SetMapMode::Response& res) {
    pending_mode_ = req.mode;
    res.success = !system_ || setMode(req.mode);
    res.message = res.success ? "mode " + req.mode : "mode must be mapping or localization";
    return true;
  }

  // Subscriptions
  message_filters::Subscriber<Features> features_sub_;
  message_filters::Subscriber<Image> depth_sub_;
  message_filters::Subscriber<Info> info_sub_;
  std::unique_ptr<message_filters::Synchronizer<Policy>> sync_;
  ros::Subscriber wheel_sub_;
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  // Publications
  ros::Publisher graph_pub_, cloud_pub_, path_pub_;
  ros::ServiceServer save_srv_, load_srv_, mode_srv_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  ros::Timer tf_timer_;
  // Parameters
  std::string map_frame_, odom_frame_, base_frame_, map_path_, pending_mode_;
  int autosave_every_keyframes_ = 20;
  int queue_size_ = 10;
  double depth_scale_ = 1000.0;
  icgm::CameraIntrinsics sensor_calibration_;  // camera_info lacks these fields
  double tf_wait_s_ = 0.5;
  icgm::SlamOptions options_;
  // State
  icgm::CameraIntrinsics intrinsics_;
  std::unique_ptr<icgm::SlamSystem> system_;
  std::unique_ptr<icgm::ObservationKeyframer> keyframer_;
  std::unique_ptr<icgm::WheelOdometryBuffer> wheel_;
  std::optional<icgm::Time> last_keyframe_stamp_;  // the keyframer's previous keyframe
  std::optional<std::string> pending_load_;
  std::deque<Observation> queue_;
  ros::Time last_stamp_;
  ros::Time last_tf_stamp_;
  int keyframes_since_save_ = 0;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::MapBuilderNodelet, nodelet::Nodelet)
