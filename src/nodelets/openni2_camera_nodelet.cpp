// OpenNI2 RGB-D driver nodelet (Kinect, Xtion, .oni recordings, the project's virtual device):
// colour bgr8 and registered depth 16UC1 mm as openni2_launch names them (rgb/image_color,
// rgb/camera_info, depth_registered/image_raw, depth_registered/camera_info), stamped with the
// device clock mapped to ROS time (core/sensor/device_clock.h). A device that cannot register
// depth to colour in hardware has it registered in software (core/sensor/depth_registration.h)
// when the camera YAML has a depth_camera section (core/sensor/rgbd_calibration.h). Streams run
// only while someone subscribes. Without a device, or after it is unplugged, it logs why and
// retries every ~retry_interval_s; the nodelet stays up. The end of a recording the device plays
// (a fakenect dump, an .oni file played once) is said once and not retried.
#include <atomic>
#include <memory>
#include <mutex>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/sensor/openni_camera.h"
#include "core/sensor/rgbd_calibration.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"

namespace icgm_slam {

namespace nl = icgm::nodelets;

class Openni2CameraNodelet : public nodelet::Nodelet {
 public:
  ~Openni2CameraNodelet() override {
    timer_.stop();
    camera_.Close();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    options_.uri = nl::Param(pnh, "device_uri", "");
    options_.width_px = nl::Param(pnh, "width_px", 640);
    options_.height_px = nl::Param(pnh, "height_px", 480);
    options_.fps = nl::Param(pnh, "fps", 30);
    options_.hardware_registration = nl::Param(pnh, "hardware_registration", true);
    options_.hardware_sync = nl::Param(pnh, "hardware_sync", true);
    options_.max_sync_dt_s = nl::Param(pnh, "max_sync_dt_s", 0.02);
    options_.oni_repeat = nl::Param(pnh, "oni_repeat", true);
    options_.oni_registered = nl::Param(pnh, "oni_registered", true);
    options_.wait_for_recording = nl::Param(pnh, "wait_for_recording", false);
    frame_id_ = nl::Param(pnh, "frame_id", icgm::ros_bridge::topics::kCameraFrame);
    camera_config_ = nl::Param(pnh, "camera_config_file", "");
    retry_interval_s_ = nl::Param(pnh, "retry_interval_s", 2.0);
    frame_timeout_s_ = nl::Param(pnh, "frame_timeout_s", 3.0);
    if (icgm::Status s = options_.Validate(); !s.ok() || !(retry_interval_s_ > 0.0)) {
      NODELET_FATAL("openni2 camera: %s", s.ok() ? "~retry_interval_s must be > 0" : s.reason().c_str());
      throw std::runtime_error("openni2 camera: bad parameters");
    }
    if (!camera_config_.empty()) {
      std::vector<std::string> problems;
      calibration_ = icgm::LoadRgbdCalibration(camera_config_, &problems);
      for (const std::string& p : problems) NODELET_ERROR("openni2 camera: %s", p.c_str());
    }
    // Publications (lazy: the streams run while any of them has a subscriber)
    auto cb = [this](const ros::SingleSubscriberPublisher&) { connectCb(); };
    rgb_pub_ = nh.advertise<sensor_msgs::Image>("rgb/image_color", 5, cb, cb);
    rgb_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 5, cb, cb);
    depth_pub_ = nh.advertise<sensor_msgs::Image>("depth_registered/image_raw", 5, cb, cb);
    depth_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("depth_registered/camera_info", 5, cb, cb);
    timer_ = nh.createWallTimer(ros::WallDuration(retry_interval_s_),
                                [this](const ros::WallTimerEvent&) { watchdogCb(); });
    watchdogCb();
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "openni2 camera");
  }

  bool listened() const {
    return rgb_pub_.getNumSubscribers() + rgb_info_pub_.getNumSubscribers() +
               depth_pub_.getNumSubscribers() + depth_info_pub_.getNumSubscribers() > 0;
  }

  void connectCb() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!camera_.is_open()) return;
    if (listened() && !camera_.is_started()) {
      if (icgm::Status s = camera_.Start(); !s.ok()) NODELET_ERROR("openni2 camera: %s", s.reason().c_str());
    } else if (!listened() && camera_.is_started()) {
      camera_.Stop();
    }
  }

  // Opens the device when it is closed; closes it when it was unplugged or stopped delivering.
  void watchdogCb() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (refused_) return;
      if (camera_.is_open()) {
        if (camera_.end_of_recording()) {  // not a failure: said once, nothing to reopen
          if (!end_reported_) {
            NODELET_WARN(
                "openni2 camera: end of recording: %s: %zu pairs, %zu frames unpaired; "
                "no more frames, not reopening",
                camera_.description().c_str(), camera_.pairs(), camera_.dropped());
          }
          end_reported_ = true;
          return;
        }
        const bool stalled = camera_.seconds_without_frames() > frame_timeout_s_;
        if (!camera_.disconnected() && !stalled) return;
        NODELET_ERROR("openni2 camera: %s; retrying every %.1f s",
                      camera_.disconnected() ? "device unplugged" : "no frames from the device",
                      retry_interval_s_);
        camera_.Close();
      }
      if (ros::Time::now().isZero()) return;  // simulated time not running yet
      const icgm::Status s = camera_.Open(
          options_, [] { return icgm::ros_bridge::FromRos(ros::Time::now()); },
          [this](const icgm::RgbdPair& p) { pairCb(p); });
      if (!s.ok()) {
        NODELET_ERROR_THROTTLE(30.0, "openni2 camera: %s; retrying every %.1f s", s.reason().c_str(),
                               retry_interval_s_);
        return;
      }
      const icgm::CameraIntrinsics streamed = camera_.FieldOfViewIntrinsics();
      if (const icgm::Status fits = icgm::CheckCalibratedSize(calibration_, streamed.width_px,
                                                              streamed.height_px, camera_config_);
          !fits.ok()) {
        // A configuration error, not a device one: said once, the device left closed.
        NODELET_ERROR("openni2 camera: %s; not publishing", fits.reason().c_str());
        camera_.Close();
        refused_ = true;
        return;
      }
      intrinsics_ = calibration_.color.value_or(streamed);
      const auto registration =
          icgm::SoftwareRegistration(calibration_, camera_.hardware_registration(), intrinsics_);
      std::atomic_store(&registration_, registration);
      NODELET_INFO("openni2 camera: %s%s; camera_info from %s", camera_.description().c_str(),
                   registration ? ", registered in software" : "",
                   calibration_.color ? camera_config_.c_str() : "the field of view");
    }
    connectCb();
  }

  // OpenNI's thread: one depth-colour pair.
  void pairCb(const icgm::RgbdPair& p) {
    try {
      cpu_.Start();
      namespace rb = icgm::ros_bridge;
      if (rgb_pub_.getNumSubscribers() > 0) rgb_pub_.publish(rb::ToImageMsg(p.color.image, "bgr8", frame_id_, p.color.stamp));
      if (rgb_info_pub_.getNumSubscribers() > 0) rgb_info_pub_.publish(rb::ToCameraInfo(intrinsics_, frame_id_, p.color.stamp));
      if (depth_pub_.getNumSubscribers() > 0) {
        const auto registration = std::atomic_load(&registration_);
        const cv::Mat depth = registration ? registration->Register(p.depth.image) : p.depth.image;
        if (depth.empty()) throw std::runtime_error("depth image does not match the depth_camera calibration");
        depth_pub_.publish(rb::ToImageMsg(depth, "16UC1", frame_id_, p.depth.stamp));
      }
      if (depth_info_pub_.getNumSubscribers() > 0) depth_info_pub_.publish(rb::ToCameraInfo(intrinsics_, frame_id_, p.depth.stamp));
      if (double ms; cpu_.Stop(&ms)) {
        NODELET_INFO("openni2 camera: %.2f ms CPU per frame (last 100), %zu pairs, %zu frames unpaired",
                     ms, camera_.pairs(), camera_.dropped());
      }
    } catch (const std::exception& e) {
      NODELET_WARN_THROTTLE(5.0, "openni2 camera: frame dropped: %s", e.what());
    }
  }

  // Publications
  ros::Publisher rgb_pub_, rgb_info_pub_, depth_pub_, depth_info_pub_;
  // Parameters
  icgm::OpenniCameraOptions options_;
  std::string frame_id_, camera_config_;
  double retry_interval_s_ = 2.0, frame_timeout_s_ = 3.0;
  // State
  std::mutex mutex_;
  icgm::OpenniCamera camera_;
  bool end_reported_ = false;
  bool refused_ = false;  // the calibration does not fit the streamed size: stays closed
  icgm::RgbdCalibration calibration_;  // from ~camera_config_file
  icgm::CameraIntrinsics intrinsics_;   // camera_info
  std::shared_ptr<const icgm::DepthRegistration> registration_;  // null: depth published as delivered
  ros::WallTimer timer_;
  icgm::nodelets::CpuMeter cpu_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::Openni2CameraNodelet, nodelet::Nodelet)
