// Map-building nodelet (thesis ch. 6.1.1.2): robust features + registered depth + the fused
// odometry (tf odom -> camera) become metric models of the hybrid map; loop closure corrects the
// map (eq. 6.2, 6.4) and the correction is published as tf map -> odom (REP-105). Publishes the
// graph (MarkerArray), the map cloud (PointCloud2) and the keyframe path, each built only while
// someone listens; services save / load (merge) the SQLite map and switch mapping/localization.
// The map's people-free occupancy grid and static cloud (latched, MapProductsPublisher) follow
// every load and every save of the map (~publish_map_products, options from ~map_export_config).
// Mode and save policy are the core's (SlamSystem::SetMode, SavePolicy): while mapping the map
// is saved atomically to ~map_path on every loop closure, every `autosave_every_keyframes`
// keyframes and at shutdown; while localizing the learned map is never written (autosave goes
// to ~localization_map_path). /initialpose (rviz "2D Pose Estimate") gives the localization a
// pose; without one the robot relocalizes globally by place recognition.
#include <algorithm>
#include <deque>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <boost/bind/bind.hpp>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
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
#include "core/features/lens_undistortion.h"
#include "core/odometry/odometry_fusion.h"
#include "core/odometry/wheel_odometry_buffer.h"
#include "core/slam/observation_keyframer.h"
#include "core/slam/slam_system.h"
#include "nodelets/map_products_publisher.h"
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
    pnh.param<std::string>("localization_map_path", localization_map_path_, "");
    if (localization_map_path_.empty() && !map_path_.empty()) {
      const size_t dot = map_path_.rfind(".db");
      localization_map_path_ =
          (dot == std::string::npos ? map_path_ : map_path_.substr(0, dot)) + "_localization.db";
    }
    pnh.param("queue_size", queue_size_, 10);
    pnh.param("depth_scale", depth_scale_, 1000.0);
    // Depth scale and timing, rolling shutter: ~camera_config_file and single parameters.
    std::string calibration_error;
    sensor_calibration_ = icgm::nodelets::ReadSensorCalibration(pnh, &calibration_error);
    if (!calibration_error.empty()) {
      NODELET_ERROR("map builder: %s (ignored)", calibration_error.c_str());
    }
    pnh.param("tf_wait_s", tf_wait_s_, 0.5);
    // Hand-held camera: the odometry's child frame is the camera frame, no wheels.
    pnh.param("camera_only", camera_only_, false);
    icgm::KeyframerOptions keyframer_options;
    icgm::MapExportOptions export_options;
    bool publish_products = true;
    pnh.param("publish_map_products", publish_products, true);
    std::string export_config;
    pnh.param<std::string>("map_export_config", export_config, config_dir + "/map_export.yaml");
    try {
      options_ = icgm::LoadSlamOptions(config_dir);
      const auto map_yaml = icgm::OptionReader::FromFile(config_dir + "/map.yaml");
      icgm::ReadOptions(map_yaml.Section("keyframer"), &keyframer_options);
      if (publish_products) {
        export_options = icgm::LoadMapExportOptions(export_config);
      }
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("map builder: bad configuration: %s", e.what());
      throw;
    }
    keyframer_ = std::make_unique<icgm::ObservationKeyframer>(keyframer_options);
    if (!load_path.empty()) pending_load_ = load_path;
    if (const icgm::Status s = icgm::ParseMapMode(mode, &pending_mode_); !s.ok()) {
      NODELET_FATAL("map builder: ~mode: %s", s.reason().c_str());
      throw std::invalid_argument("map builder: ~mode: " + s.reason());
    }
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);

    // Publications
    graph_pub_ = nh.advertise<visualization_msgs::MarkerArray>("map/graph", 1, true);
    cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("map/cloud", 1, true);
    path_pub_ = nh.advertise<nav_msgs::Path>("map/path", 1, true);
    if (publish_products) {
      products_ =
          std::make_unique<icgm::nodelets::MapProductsPublisher>(nh, map_frame_, export_options);
    }
    save_srv_ = pnh.advertiseService("save_map", &MapBuilderNodelet::saveCb, this);
    load_srv_ = pnh.advertiseService("load_map", &MapBuilderNodelet::loadCb, this);
    mode_srv_ = pnh.advertiseService("set_mode", &MapBuilderNodelet::modeCb, this);
    initial_pose_sub_ = nh.subscribe("initialpose", 5, &MapBuilderNodelet::initialPoseCb, this);
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
    if (options_.map.map.wheel_links && !camera_only_) {
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
    undistortion_ = icgm::LensUndistortion(k);
    system_ = std::make_unique<icgm::SlamSystem>(options_, k);
    system_->SetSavePolicy({map_path_, localization_map_path_, autosave_every_keyframes_});
    if (pending_load_) {
      const icgm::Status s = system_->Load(*pending_load_, false);
      if (s.ok()) {
        NODELET_INFO("map builder: loaded %d keyframes from %s", system_->map().size(),
                     pending_load_->c_str());
        PublishProducts(info.header.stamp);
      } else {
        NODELET_ERROR("map builder: cannot load map: %s", s.reason().c_str());
      }
      pending_load_.reset();
    }
    system_->SetMode(pending_mode_);
    if (pending_mode_ == icgm::MapMode::kLocalization && system_->map().empty()) {
      NODELET_WARN("map builder: localization without a map: nothing to localize against "
                   "(give ~load_map or call load_map)");
    }
    return true;
  }

  // rviz's "2D Pose Estimate": the base's pose in the map; the camera's follows through tf.
  void initialPoseCb(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
    if (!system_ || camera_frame_.empty()) {
      NODELET_WARN("map builder: initial pose ignored: no frame received yet");
      return;
    }
    if (msg->header.frame_id != map_frame_) {
      NODELET_WARN("map builder: initial pose ignored: it is in '%s', not '%s'",
                   msg->header.frame_id.c_str(), map_frame_.c_str());
      return;
    }
    icgm::Pose3 base_to_camera = icgm::Pose3::Identity(), odom_camera;
    try {
      if (!camera_only_) {
        base_to_camera = icgm::ros_bridge::FromTransformMsg(
            tf_buffer_.lookupTransform(base_frame_, camera_frame_, ros::Time(0)).transform);
      }
      odom_camera = icgm::ros_bridge::FromTransformMsg(
          tf_buffer_.lookupTransform(odom_frame_, camera_frame_, ros::Time(0)).transform);
    } catch (const tf2::TransformException& e) {
      NODELET_WARN("map builder: initial pose ignored: %s", e.what());
      return;
    }
    const icgm::Pose3 map_camera = icgm::ros_bridge::FromPoseMsg(msg->pose.pose) * base_to_camera;
    system_->SetInitialPose(map_camera, odom_camera);
    NODELET_INFO("map builder: initial pose set (%s mode)", icgm::MapModeName(system_->mode()));
    publishTf();
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
    // The pinhole model of the keyframes, as the front end's: depth resampled, keypoints found
    // on the raw image moved.
    depth_m = undistortion_.Depth(depth_m);
    if (!o.features->keypoints_undistorted) undistortion_.MoveKeypoints(&frame.features.keypoints);
    last_stamp_ = o.features->header.stamp;
    camera_frame_ = o.features->header.frame_id;
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
    const bool localizing = system_->mode() == icgm::MapMode::kLocalization;
    if (result.update.loop_closed && localizing) {
      NODELET_INFO_THROTTLE(5.0, "map builder: localized (%zu fixes)", system_->relocalizations());
    } else if (result.update.loop_closed) {
      NODELET_INFO("map builder: loop closed at keyframe %d (%d keyframes)", result.keyframe_id,
                   system_->map().size());
    } else if (localizing && !system_->localized()) {
      NODELET_INFO_THROTTLE(5.0, "map builder: not localized yet (%s)",
                            result.update.loop.status.reason().c_str());
    }
    std::string written;
    if (const icgm::Status s = system_->Autosave(result, &written); !s.ok()) {
      NODELET_ERROR("map builder: autosave failed: %s", s.reason().c_str());
    } else if (!written.empty()) {
      NODELET_DEBUG("map builder: saved to %s", written.c_str());
      PublishProducts(last_stamp_);
    }
    publishTf();
    publishMap();
  }

  void publishTf() {
    if (!system_ || last_stamp_.isZero()) return;
    // Localizing without a fix, map -> odom is unknown: none is published rather than a guess.
    if (system_->mode() == icgm::MapMode::kLocalization && !system_->localized()) return;
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

  // The map's occupancy grid and static cloud, built off the callback thread.
  void PublishProducts(const ros::Time& stamp) {
    if (products_ && system_ && !system_->map().empty()) products_->Request(system_->map(), stamp);
  }

  // At shutdown: the mode's file (SavePolicy); localization without kept keyframes changed
  // nothing.
  void SaveIfConfigured(const char* why) {
    if (!system_ || system_->map().empty()) return;
    const bool localizing = system_->mode() == icgm::MapMode::kLocalization;
    if (localizing &&
        system_->options().localization.keyframes == icgm::LocalizationKeyframes::kNone)
      return;
    const icgm::SavePolicy& policy = system_->save_policy();
    if ((localizing ? policy.localization_path : policy.map_path).empty()) return;
    std::string detail;
    const icgm::Status s = system_->SaveMap("", false, &detail);
    if (s.ok()) {
      NODELET_DEBUG("map builder: %s (%s)", detail.c_str(), why);
    } else {
      NODELET_ERROR("map builder: save failed (%s): %s", why, s.reason().c_str());
    }
  }

  bool saveCb(icgm_slam::SaveMap::Request& req, icgm_slam::SaveMap::Response& res) {
    if (!system_) {
      res.success = false;
      res.message = "no map yet (no camera_info received)";
      return true;
    }
    // Save, bundle-adjust (map_refinement.enabled, mapping only), save again: the core's policy.
    std::string detail;
    const icgm::Status s =
        system_->SaveMap(req.path, system_->options().map_refinement.enabled, &detail);
    res.success = s.ok();
    res.message = s.ok() ? detail : s.reason();
    if (s.ok()) PublishProducts(last_stamp_);
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
      PublishProducts(last_stamp_);
    }
    return true;
  }

  bool modeCb(icgm_slam::SetMapMode::Request& req, icgm_slam::SetMapMode::Response& res) {
    icgm::MapMode mode;
    const icgm::Status s = icgm::ParseMapMode(req.mode, &mode);
    res.success = s.ok();
    res.message = s.ok() ? "mode " + req.mode : s.reason();
    if (!s.ok()) return true;
    pending_mode_ = mode;
    if (system_) system_->SetMode(mode);
    return true;
  }

  // Subscriptions
  message_filters::Subscriber<Features> features_sub_;
  message_filters::Subscriber<Image> depth_sub_;
  message_filters::Subscriber<Info> info_sub_;
  std::unique_ptr<message_filters::Synchronizer<Policy>> sync_;
  ros::Subscriber wheel_sub_;
  ros::Subscriber initial_pose_sub_;
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  // Publications
  ros::Publisher graph_pub_, cloud_pub_, path_pub_;
  std::unique_ptr<icgm::nodelets::MapProductsPublisher> products_;  // null: not published
  ros::ServiceServer save_srv_, load_srv_, mode_srv_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  ros::Timer tf_timer_;
  // Parameters
  std::string map_frame_, odom_frame_, base_frame_, map_path_, localization_map_path_;
  icgm::MapMode pending_mode_ = icgm::MapMode::kMapping;
  int autosave_every_keyframes_ = 20;
  int queue_size_ = 10;
  double depth_scale_ = 1000.0;
  icgm::CameraIntrinsics sensor_calibration_;  // camera_info lacks these fields
  double tf_wait_s_ = 0.5;
  bool camera_only_ = false;
  icgm::SlamOptions options_;
  // State
  icgm::CameraIntrinsics intrinsics_;
  icgm::LensUndistortion undistortion_;  // from camera_info's distortion
  std::unique_ptr<icgm::SlamSystem> system_;
  std::unique_ptr<icgm::ObservationKeyframer> keyframer_;
  std::unique_ptr<icgm::WheelOdometryBuffer> wheel_;
  std::optional<icgm::Time> last_keyframe_stamp_;  // the keyframer's previous keyframe
  std::optional<std::string> pending_load_;
  std::deque<Observation> queue_;
  std::string camera_frame_;  // of the features, once one frame arrived
  ros::Time last_stamp_;
  ros::Time last_tf_stamp_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::MapBuilderNodelet, nodelet::Nodelet)
