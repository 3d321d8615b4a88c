// Map-building nodelet (thesis ch. 6.1.1.2): the keyframes (metric models: robust features
// with their 3D points) of the registration nodelet's front end, placed with the fused odometry
// (tf odom -> camera at their stamps, odometry_wait.h), go to the hybrid map as in
// icgm_slam_offline; loop closure corrects the map (eq. 6.2, 6.4) and the correction is
// published as tf map -> odom (map_odom_tf.h). The graph, map cloud and keyframe path are
// built only while someone listens (map_view_publisher.h); services save / load (merge) the
// SQLite map and switch mapping/localization. Mode, loading and the save policy are the core's
// (live_map.h). /initialpose (rviz "2D Pose Estimate") gives the localization a pose; without
// one the robot relocalizes globally by place recognition. The people-free occupancy grid and
// static cloud (~publish_map_products, options from ~map_export_config) are built on load, on
// request and, while someone listens, on save (map_products_publisher.h).
#include <memory>
#include <string>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include <icgm_slam/Keyframe.h>

#include "core/common/option_reader.h"
#include "core/slam/live_map.h"
#include "nodelets/map_odom_tf.h"
#include "nodelets/map_products_publisher.h"
#include "nodelets/map_services.h"
#include "nodelets/map_view_publisher.h"
#include "nodelets/nodelet_params.h"
#include "nodelets/odometry_wait.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/keyframe_msgs.h"

namespace icgm_slam {

namespace nodelets = icgm::nodelets;

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
    const std::string config_dir = nodelets::Param(pnh, "config_dir", "");
    icgm::LiveMapOptions live;
    live.map_path = nodelets::Param(pnh, "map_path", "");
    live.load_path = nodelets::Param(pnh, "load_map", "");
    live.autosave_every_keyframes = nodelets::Param(pnh, "autosave_every_keyframes", 20);
    live.localization_map_path = nodelets::Param(pnh, "localization_map_path", "");
    camera_ = std::make_unique<nodelets::CameraModelReader>(pnh, "map builder");
    const bool publish_products = nodelets::Param(pnh, "publish_map_products", true);
    icgm::MapExportOptions export_options;
    nodelets::LoadConfiguration("map builder", [&] {
      if (const icgm::Status s = icgm::ParseMapMode(nodelets::Param(pnh, "mode", "mapping"),
                                                    &live.mode);
          !s.ok()) {
        throw icgm::LoadError("~mode: " + s.reason());
      }
      const icgm::SlamOptions slam = icgm::LoadSlamOptions(config_dir);
      map_features_source_ = icgm::NameOf(slam.map_features.source);
      map_ = std::make_unique<icgm::LiveMap>(slam, live);
      if (publish_products) {
        export_options = icgm::LoadMapExportOptions(
            nodelets::Param(pnh, "map_export_config", config_dir + "/map_export.yaml"));
      }
    });
    // camera_only: hand-held, the odometry's child is the camera frame.
    tf_ = std::make_unique<nodelets::MapOdomTf>(nodelets::ReadFrameNames(pnh),
                                                nodelets::Param(pnh, "camera_only", false));
    waiting_ = std::make_unique<nodelets::OdometryWait>(tf_->buffer(), tf_->frames().odom,
                                                        nodelets::Param(pnh, "tf_wait_s", 0.5));
    // Publications
    view_ = std::make_unique<nodelets::MapViewPublisher>(nh, tf_->frames().map);
    if (publish_products) {
      products_ = std::make_unique<nodelets::MapProductsPublisher>(
          nh, pnh, tf_->frames().map, export_options, [this](ros::Time* stamp) {
            *stamp = last_stamp_;
            return map_->system() ? &map_->system()->map() : nullptr;
          });
    }
    // Subscriptions (eager: the map is state), before the services (their presence says the
    // nodelet listens). Timers run on the same callback queue.
    keyframe_sub_ = nh.subscribe("keyframes", 20, &MapBuilderNodelet::keyframeCb, this);
    services_ = std::make_unique<nodelets::MapServices>(
        pnh, map_.get(), [this](nodelets::MapServices::Done done) {
          if (!products_) return;
          if (done == nodelets::MapServices::Done::kLoaded) products_->OnLoad();
          if (done == nodelets::MapServices::Done::kSaved) products_->OnSave();
        });
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
    icgm::Status s = camera_->Read(info, &k);
    std::string loaded;
    try {
      if (s.ok()) s = map_->Start(k, &loaded);
    } catch (const icgm::LoadError& e) {  // a back end this build lacks
      s = icgm::Status::Error(e.what());
    }
    if (!map_->started()) {
      NODELET_ERROR_THROTTLE(5.0, "map builder: cannot start: %s", s.reason().c_str());
      return false;
    }
    if (!s.ok()) NODELET_ERROR("map builder: cannot load map: %s", s.reason().c_str());
    if (!loaded.empty()) NODELET_INFO("map builder: loaded %s", loaded.c_str());
    if (!loaded.empty() && products_) products_->OnLoad();
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
    } else if (!update.saved_to.empty() && products_) {
      products_->OnSave();
    }
    publishTf();
    view_->Publish(system.map(), last_stamp_);
  }

  // rviz's "2D Pose Estimate": the base's pose in the map; the camera's follows through tf.
  void initialPoseCb(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
    if (const icgm::Status s = tf_->SetInitialPose(*msg, camera_frame_, map_->system()); !s.ok()) {
      NODELET_WARN("map builder: initial pose ignored: %s", s.reason().c_str());
      return;
    }
    NODELET_INFO("map builder: initial pose set (%s mode)",
                 icgm::MapModeName(map_->system()->mode()));
    publishTf();
  }

  void publishTf() {
    if (map_->system()) tf_->Publish(*map_->system(), last_stamp_);
  }

  // Subscriptions
  ros::Subscriber keyframe_sub_, initial_pose_sub_;
  // Publications
  std::unique_ptr<nodelets::MapOdomTf> tf_;  // map -> odom; the tf buffer
  std::unique_ptr<nodelets::MapViewPublisher> view_;
  std::unique_ptr<nodelets::MapProductsPublisher> products_;  // null: not published
  std::unique_ptr<nodelets::MapServices> services_;
  ros::WallTimer tf_timer_;  // keyframes whose odometry came late; map -> odom kept fresh
  // Parameters
  std::unique_ptr<nodelets::CameraModelReader> camera_;
  // State
  std::unique_ptr<icgm::LiveMap> map_;
  std::unique_ptr<nodelets::OdometryWait> waiting_;
  std::string camera_frame_;  // of the keyframes, once one arrived
  std::string map_features_source_;  // map.yaml map_features.source
  ros::Time last_stamp_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::MapBuilderNodelet, nodelet::Nodelet)
