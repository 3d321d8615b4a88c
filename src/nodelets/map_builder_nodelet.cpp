// Map-building nodelet (thesis ch. 6.1.1.2): the keyframes (metric models: robust features
// with their 3D points) of the registration nodelet's front end, placed with the fused odometry
// (tf odom -> camera at their stamps, odometry_wait.h), go to the hybrid map as in
// icgm_slam_offline; loop closure corrects the map (eq. 6.2, 6.4) and the correction is
// published as tf map -> odom (map_odom_tf.h). The graph, map cloud and keyframe path are
// built only while someone listens (map_view_publisher.h); services save / load (merge) the
// SQLite map and switch mapping/localization (after the keyframes made before the switch,
// keyframe_intake.h). Keyframe intake: keyframe_intake.h. Mode, loading and the save policy are the
// core's (live_map.h). /initialpose (rviz "2D Pose Estimate") gives the localization a pose;
// without one the robot relocalizes globally by place recognition. The people-free occupancy grid
// and static cloud (~publish_map_products, options from ~map_export_config) are built on load, on
// request and, while someone listens, on save (map_products_publisher.h).
// Its callbacks (keyframes, timer, services) run in turn on a thread of its own, not on the
// manager's workers: `~set_mode` waits for the registration's flush service and for the fused
// odometry, and those need a worker even when the manager has only one.
#include <memory>
#include <string>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nodelet/nodelet.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <pluginlib/class_list_macros.hpp>

#include <icgm_slam/Keyframe.h>

#include "core/common/option_reader.h"
#include "core/slam/live_map.h"
#include "nodelets/keyframe_intake.h"
#include "nodelets/map_odom_tf.h"
#include "nodelets/map_products_publisher.h"
#include "nodelets/map_services.h"
#include "nodelets/map_view_publisher.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam {

namespace nodelets = icgm::nodelets;

class MapBuilderNodelet : public nodelet::Nodelet {
 public:
  ~MapBuilderNodelet() override {
    if (spinner_) spinner_->stop();  // no callback runs from here on
    std::string written;
    if (!map_) return;
    if (const icgm::Status s = map_->SaveAtShutdown(&written); !s.ok()) {
      NODELET_ERROR("map builder: save failed (shutdown): %s", s.reason().c_str());
    }
  }

 private:
  void onInit() override {
    nh_ = getNodeHandle();
    pnh_ = getPrivateNodeHandle();
    nh_.setCallbackQueue(&queue_);
    pnh_.setCallbackQueue(&queue_);
    ros::NodeHandle& nh = nh_;
    ros::NodeHandle& pnh = pnh_;
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
    std::string map_features_source;  // map.yaml's: the keyframes must follow it
    nodelets::LoadConfiguration("map builder", [&] {
      if (const icgm::Status s = icgm::ParseMapMode(nodelets::Param(pnh, "mode", "mapping"),
                                                    &live.mode);
          !s.ok()) {
        throw icgm::LoadError("~mode: " + s.reason());
      }
      const icgm::SlamOptions slam = icgm::LoadSlamOptions(config_dir);
      map_features_source = icgm::NameOf(slam.map_features.source);
      map_ = std::make_unique<icgm::LiveMap>(slam, live);
      if (publish_products) {
        export_options = icgm::LoadMapExportOptions(
            nodelets::Param(pnh, "map_export_config", config_dir + "/map_export.yaml"));
      }
    });
    // camera_only: hand-held, the odometry's child is the camera frame.
    tf_ = std::make_unique<nodelets::MapOdomTf>(nodelets::ReadFrameNames(pnh),
                                                nodelets::Param(pnh, "camera_only", false));
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
    intake_ = std::make_unique<nodelets::KeyframeIntake>(
        nh, pnh, map_.get(), camera_.get(), tf_->buffer(), tf_->frames().odom,
        map_features_source,
        nodelets::KeyframeIntake::Callbacks{
            [this] {
              if (products_) products_->OnLoad();
            },
            [this](const icgm::LiveMapUpdate& update) { added(update); }});
    keyframe_sub_ = nh.subscribe<icgm_slam::Keyframe>(
        "keyframes", 20, [this](const icgm_slam::Keyframe::ConstPtr& msg) { intake_->Add(*msg); });
    services_ = std::make_unique<nodelets::MapServices>(
        pnh, map_.get(),
        [this](nodelets::MapServices::Done done) {
          if (done == nodelets::MapServices::Done::kBeforeModeSwitch) intake_->FlushBeforeModeSwitch();
          if (!products_) return;
          if (done == nodelets::MapServices::Done::kLoaded) products_->OnLoad();
          if (done == nodelets::MapServices::Done::kSaved) products_->OnSave();
        });
    initial_pose_sub_ = nh.subscribe("initialpose", 5, &MapBuilderNodelet::initialPoseCb, this);
    tf_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
      intake_->Drain();
      publishTf();
    });
    spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
    spinner_->start();
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "map builder");
  }

  void added(const icgm::LiveMapUpdate& update) {
    last_stamp_ = icgm::ros_bridge::ToRos(update.result.frontend.stamp);
    if (!update.result.map_status.ok()) return;
    if (update.autosave.ok() && !update.saved_to.empty() && products_) products_->OnSave();
    publishTf();
    view_->Publish(map_->system()->map(), last_stamp_);
  }

  // rviz's "2D Pose Estimate": the base's pose in the map; the camera's follows through tf.
  void initialPoseCb(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
    if (const icgm::Status s = tf_->SetInitialPose(*msg, intake_->camera_frame(), map_->system()); !s.ok()) {
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

  // The callbacks' own queue and thread (declared first: the queue outlives what uses it).
  ros::CallbackQueue queue_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  ros::NodeHandle nh_, pnh_;  // on queue_
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
  std::unique_ptr<nodelets::KeyframeIntake> intake_;  // keyframes waiting for their odometry
  ros::Time last_stamp_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::MapBuilderNodelet, nodelet::Nodelet)
