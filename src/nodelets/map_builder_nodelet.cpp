// Map-building nodelet (thesis ch. 6.1.1.2): the keyframes (metric models: robust features
// with their 3D points) of the registration nodelet's front end, placed with the fused odometry
// (tf odom -> camera at their stamps, odometry_wait.h), go to the hybrid map as in
// icgm_slam_offline; loop closure corrects the map (eq. 6.2, 6.4) and the correction is
// published as tf map -> odom (REP-105). Publishes the graph (MarkerArray), the map cloud
// (PointCloud2) and the keyframe path, each built only while someone listens; services save /
// load (merge) the SQLite map and switch mapping/localization. Mode, loading and the save
// policy are the core's (live_map.h). /initialpose (rviz "2D Pose Estimate") gives the
// localization a pose; without one the robot relocalizes globally by place recognition.
// The map's people-free occupancy grid and static cloud (latched, MapProductsPublisher) follow
// every load and every save of the map (~publish_map_products, options from ~map_export_config).
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <icgm_slam/Keyframe.h>
#include <icgm_slam/LoadMap.h>
#include <icgm_slam/SaveMap.h>
#include <icgm_slam/SetMapMode.h>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "core/slam/live_map.h"
#include "nodelets/map_products_publisher.h"
#include "nodelets/odometry_wait.h"
#include "nodelets/sensor_calibration.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/keyframe_msgs.h"
#include "ros_bridge/map_msgs.h"

namespace icgm_slam {

class MapBuilderNodelet : public nodelet::Nodelet {
 public:
  ~MapBuilderNodelet() override {
    std::string written;
    if (!map_) return;
    if (const icgm::Status s = map_->SaveAtShutdown(&written); !s.ok()) {
      NODELET_ERROR("map builder: save failed (shutdown): %s", s.reason().c_str());
    }
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_dir, mode;
    icgm::LiveMapOptions live;
    pnh.param<std::string>("config_dir", config_dir, "");
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("odom_frame", odom_frame_, "odom");
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param<std::string>("map_path", live.map_path, "");
    pnh.param<std::string>("load_map", live.load_path, "");
    pnh.param<std::string>("mode", mode, "mapping");
    pnh.param("autosave_every_keyframes", live.autosave_every_keyframes, 20);
    pnh.param<std::string>("localization_map_path", live.localization_map_path, "");
    pnh.param("depth_scale", depth_scale_, 1000.0);
    double tf_wait_s = 0.5;
    pnh.param("tf_wait_s", tf_wait_s, tf_wait_s);
    pnh.param("camera_only", camera_only_, false);  // hand-held: odometry child = camera frame
    // Depth scale and timing, rolling shutter: ~camera_config_file and single parameters.
    std::string calibration_error;
    sensor_calibration_ = icgm::nodelets::ReadSensorCalibration(pnh, &calibration_error);
    if (!calibration_error.empty()) {
      NODELET_ERROR("map builder: %s (ignored)", calibration_error.c_str());
    }
    bool publish_products = true;
    pnh.param("publish_map_products", publish_products, true);
    std::string export_config;
    pnh.param<std::string>("map_export_config", export_config, config_dir + "/map_export.yaml");
    icgm::MapExportOptions export_options;
    try {
      if (const icgm::Status s = icgm::ParseMapMode(mode, &live.mode); !s.ok()) {
        throw icgm::LoadError("~mode: " + s.reason());
      }
      const icgm::SlamOptions slam = icgm::LoadSlamOptions(config_dir);
      map_features_source_ = icgm::NameOf(slam.map_features.source);
      map_ = std::make_unique<icgm::LiveMap>(slam, live);
      if (publish_products) export_options = icgm::LoadMapExportOptions(export_config);
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("map builder: bad configuration: %s", e.what());
      throw;
    }
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);
    waiting_ = std::make_unique<icgm::nodelets::OdometryWait>(tf_buffer_, odom_frame_, tf_wait_s);
    // Publications
    graph_pub_ = nh.advertise<visualization_msgs::MarkerArray>("map/graph", 1, true);
    cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("map/cloud", 1, true);
    path_pub_ = nh.advertise<nav_msgs::Path>("map/path", 1, true);
    if (publish_products) {
      products_ =
          std::make_unique<icgm::nodelets::MapProductsPublisher>(nh, map_frame_, export_options);
    }
    // Subscriptions (eager: the map is state), before the services (their presence says the
    // nodelet listens). Timers run on the same callback queue.
    keyframe_sub_ = nh.subscribe("keyframes", 20, &MapBuilderNodelet::keyframeCb, this);
    save_srv_ = pnh.advertiseService("save_map", &MapBuilderNodelet::saveCb, this);
    load_srv_ = pnh.advertiseService("load_map", &MapBuilderNodelet::loadCb, this);
    mode_srv_ = pnh.advertiseService("set_mode", &MapBuilderNodelet::modeCb, this);
    initial_pose_sub_ = nh.subscribe("initialpose", 5, &MapBuilderNodelet::initialPoseCb, this);
    tf_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
      drain();
      publishTf();
    });
  }

  void keyframeCb(const icgm_slam::Keyframe::ConstPtr& msg) {
    // Features chosen as this map's map.yaml says, or none (never a silent difference).
    if (msg->map_features_source != map_features_source_) {
      NODELET_ERROR_THROTTLE(10.0, "map builder: keyframe refused: its features follow "
                             "map_features.source '%s', this map's map.yaml says '%s' (give the "
                             "registration nodelet ~map_config_file = this map.yaml)",
                             msg->map_features_source.c_str(), map_features_source_.c_str());
      return;
    }
    if (!map_->started() && !Start(msg->camera_info)) return;
    icgm::FrontendKeyframe keyframe;
    if (const icgm::Status s = icgm::ros_bridge::FromKeyframeMsg(*msg, &keyframe); !s.ok()) {
      NODELET_WARN_THROTTLE(5.0, "map builder: bad keyframe: %s", s.reason().c_str());
      return;
    }
    camera_frame_ = msg->header.frame_id;
    waiting_->Push(std::move(keyframe), msg->header.frame_id, msg->header.stamp);
    drain();
  }

  // The system needs intrinsics: it starts with the first keyframe's camera.
  bool Start(const sensor_msgs::CameraInfo& info) {
    icgm::CameraIntrinsics k;
    if (icgm::Status s = icgm::ros_bridge::FromCameraInfo(info, depth_scale_, &k); !s) {
      NODELET_WARN_THROTTLE(5.0, "map builder: bad camera_info: %s", s.reason().c_str());
      return false;
    }
    icgm::CopySensorCalibration(sensor_calibration_, &k);
    std::string loaded;
    icgm::Status s = icgm::Status::Ok();
    try {
      s = map_->Start(k, &loaded);
    } catch (const icgm::LoadError& e) {  // a back end this build lacks
      NODELET_ERROR_THROTTLE(5.0, "map builder: %s", e.what());
      return false;
    }
    if (!s.ok()) {
      NODELET_ERROR("map builder: cannot load map: %s", s.reason().c_str());
    } else if (!loaded.empty()) {
      NODELET_INFO("map builder: loaded %s", loaded.c_str());
      PublishProducts(info.header.stamp);
    }
    if (map_->LocalizingWithoutMap()) {
      NODELET_WARN("map builder: localization without a map: nothing to localize against "
                   "(give ~load_map or call load_map)");
    }
    return true;
  }

  void drain() {
    std::string error;
    const int dropped = waiting_->Drain(
        [this](icgm::FrontendKeyframe& keyframe, const icgm::Pose3& odom_camera) {
          keyframe.odom_camera = odom_camera;  // the fused odometry, the frame tf publishes
          process(keyframe);
        },
        &error);
    if (dropped > 0) {
      NODELET_WARN_THROTTLE(5.0, "map builder: no odometry for a keyframe (%s); skipped",
                            error.c_str());
    }
  }

  void process(const icgm::FrontendKeyframe& keyframe) {
    const icgm::LiveMapUpdate update = map_->AddKeyframe(keyframe);
    const icgm::SlamFrameResult& result = update.result;
    last_stamp_ = icgm::ros_bridge::ToRos(keyframe.stamp);
    if (!result.map_status.ok()) {
      NODELET_WARN("map builder: %s", result.map_status.reason().c_str());
      return;
    }
    const icgm::SlamSystem& system = *map_->system();
    const bool localizing = system.mode() == icgm::MapMode::kLocalization;
    if (result.update.loop_closed && localizing) {
      NODELET_INFO_THROTTLE(5.0, "map builder: localized (%zu fixes)", system.relocalizations());
    } else if (result.update.loop_closed) {
      NODELET_INFO("map builder: loop closed at keyframe %d (%d keyframes)", result.keyframe_id,
                   system.map().size());
    } else if (localizing && !system.localized()) {
      NODELET_INFO_THROTTLE(5.0, "map builder: not localized yet (%s)",
                            result.update.loop.status.reason().c_str());
    }
    if (!update.autosave.ok()) {
      NODELET_ERROR("map builder: autosave failed: %s", update.autosave.reason().c_str());
    } else if (!update.saved_to.empty()) {
      PublishProducts(last_stamp_);
    }
    publishTf();
    publishMap(system.map());
  }

  // rviz's "2D Pose Estimate": the base's pose in the map; the camera's follows through tf.
  void initialPoseCb(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
    if (!map_->started() || camera_frame_.empty()) {
      NODELET_WARN("map builder: initial pose ignored: no keyframe received yet");
      return;
    }
    if (msg->header.frame_id != map_frame_) {
      NODELET_WARN("map builder: initial pose ignored: it is in '%s', not '%s'",
                   msg->header.frame_id.c_str(), map_frame_.c_str());
      return;
    }
    icgm::Pose3 base_to_camera = icgm::Pose3::Identity(), odom_camera;
    try {
      if (!camera_only_) base_to_camera = Lookup(base_frame_, camera_frame_);
      odom_camera = Lookup(odom_frame_, camera_frame_);
    } catch (const tf2::TransformException& e) {
      NODELET_WARN("map builder: initial pose ignored: %s", e.what());
      return;
    }
    map_->system()->SetInitialPose(icgm::ros_bridge::FromPoseMsg(msg->pose.pose) * base_to_camera,
                                   odom_camera);
    NODELET_INFO("map builder: initial pose set (%s mode)",
                 icgm::MapModeName(map_->system()->mode()));
    publishTf();
  }

  icgm::Pose3 Lookup(const std::string& target, const std::string& source) const {
    return icgm::ros_bridge::FromTransformMsg(
        tf_buffer_.lookupTransform(target, source, ros::Time(0)).transform);
  }

  void publishTf() {
    const icgm::SlamSystem* system = map_->system();
    if (!system || last_stamp_.isZero()) return;
    // Localizing without a fix, map -> odom is unknown: none is published rather than a guess.
    if (system->mode() == icgm::MapMode::kLocalization && !system->localized()) return;
    geometry_msgs::TransformStamped t;
    // Stamped slightly ahead so consumers can look up map -> base_link at the latest odometry;
    // never twice with one stamp (tf2 rejects repeated data).
    t.header.stamp = std::max(last_stamp_ + ros::Duration(0.1), ros::Time::now());
    if (t.header.stamp <= last_tf_stamp_) return;
    last_tf_stamp_ = t.header.stamp;
    t.header.frame_id = map_frame_;
    t.child_frame_id = odom_frame_;
    t.transform = icgm::ros_bridge::ToTransformMsg(system->MapFromOdom());
    tf_broadcaster_.sendTransform(t);
  }

  void publishMap(const icgm::HybridMap& map) {
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
    const icgm::SlamSystem* system = map_->system();
    if (products_ && system && !system->map().empty()) products_->Request(system->map(), stamp);
  }

  bool saveCb(icgm_slam::SaveMap::Request& req, icgm_slam::SaveMap::Response& res) {
    const icgm::Status s = map_->Save(req.path, &res.message);
    if (s.ok()) PublishProducts(last_stamp_);
    return Answer(s, &res.success, &res.message);
  }
  bool loadCb(icgm_slam::LoadMap::Request& req, icgm_slam::LoadMap::Response& res) {
    const icgm::Status s = map_->Load(req.path, req.merge, &res.message);
    if (s.ok()) PublishProducts(last_stamp_);
    return Answer(s, &res.success, &res.message);
  }
  bool modeCb(icgm_slam::SetMapMode::Request& req, icgm_slam::SetMapMode::Response& res) {
    const icgm::Status s = map_->SetMode(req.mode, &res.message);
    return Answer(s, &res.success, &res.message);
  }
  static bool Answer(const icgm::Status& s, uint8_t* success, std::string* message) {
    *success = s.ok();
    if (!s.ok()) *message = s.reason();
    return true;
  }

  // Subscriptions
  ros::Subscriber keyframe_sub_;
  ros::Subscriber initial_pose_sub_;
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  // Publications
  ros::Publisher graph_pub_, cloud_pub_, path_pub_;
  std::unique_ptr<icgm::nodelets::MapProductsPublisher> products_;  // null: not published
  ros::ServiceServer save_srv_, load_srv_, mode_srv_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  ros::WallTimer tf_timer_;  // keyframes whose odometry came late; map -> odom kept fresh
  // Parameters
  std::string map_frame_, odom_frame_, base_frame_;
  double depth_scale_ = 1000.0;
  icgm::CameraIntrinsics sensor_calibration_;  // camera_info lacks these fields
  bool camera_only_ = false;
  // State
  std::unique_ptr<icgm::LiveMap> map_;
  std::unique_ptr<icgm::nodelets::OdometryWait> waiting_;
  std::string camera_frame_;  // of the keyframes, once one arrived
  std::string map_features_source_;  // map.yaml map_features.source
  ros::Time last_stamp_;
  ros::Time last_tf_stamp_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::MapBuilderNodelet, nodelet::Nodelet)
