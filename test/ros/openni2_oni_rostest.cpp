// The .oni round trip through the driver nodelet: the test records the virtual OpenNI2 device
// serving a simulated scenario (colour and depth rendered at the same instant) to an .oni file
// with OpenNI's Recorder, then the nodelets of openni2_oni.test play it back through OpenNI's
// file driver. Every recorded frame pair arrives once (a loaded machine may miss one or two:
// OpenNI keeps only a stream's newest frame), 640x480 bgr8 / 16UC1, its colour equal to
// the rendered image and its depth to the rendered depth in mm, stamped on the scenario's frame
// spacing within the device clock mapping's bound. The second nodelet takes the recording as
// unregistered and publishes its depth registered in software with the camera YAML's depth camera.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>

#include <OpenNI.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include "core/dataset/camera_options.h"
#include "camera_images.h"
#include "core/sensor/depth_registration.h"
#include "core/sensor/openni_camera.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam::test {
namespace {

icgm::Time WallNow() {
  return icgm::Time::FromNanoseconds(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                         std::chrono::steady_clock::now().time_since_epoch())
                                         .count());
}

int FindEqual(const cv::Mat& image, const std::vector<cv::Mat>& candidates) {
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (image.size() == candidates[i].size() && image.type() == candidates[i].type() &&
        cv::norm(image, candidates[i], cv::NORM_INF) == 0.0) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

// The message stamped nearest `t`, if within tolerance_s (colour and depth of one instant are
// mapped to ROS time by one clock, one sample apart).
std::multimap<ros::Time, sensor_msgs::ImageConstPtr>::const_iterator Nearest(
    const std::multimap<ros::Time, sensor_msgs::ImageConstPtr>& msgs, ros::Time t, double tolerance_s) {
  auto best = msgs.end();
  for (auto it = msgs.begin(); it != msgs.end(); ++it) {
    if (std::abs((it->first - t).toSec()) <= tolerance_s &&
        (best == msgs.end() || std::abs((it->first - t).toSec()) < std::abs((best->first - t).toSec()))) {
      best = it;
    }
  }
  return best;
}

TEST(Openni2Oni, RecordingRoundTripsThroughTheNodelet) {
  ros::NodeHandle nh, pnh("~");
  std::string oni, scenario, camera_config;
  int frames = 0;
  ASSERT_TRUE(pnh.getParam("oni", oni));
  ASSERT_TRUE(pnh.getParam("scenario", scenario));
  ASSERT_TRUE(pnh.getParam("camera_config", camera_config));
  ASSERT_TRUE(pnh.getParam("frames", frames));
  CameraImages plain(nh, "camera"), software(nh, "camera_sw");
  ros::AsyncSpinner spinner(2);
  spinner.start();

  // Ground truth, rendered before the nodelets play the file so as not to slow them.
  const icgm::sim::Simulator simulator(icgm::sim::LoadSimOptions(scenario));
  std::vector<cv::Mat> truth_bgr, truth_mm, truth_sw_mm;
  icgm::DepthCameraCalibration depth_camera;
  ASSERT_TRUE(icgm::LoadDepthCameraCalibration(camera_config, &depth_camera));
  const icgm::DepthRegistration registration(depth_camera, icgm::LoadCameraIntrinsics(camera_config));
  for (int i = 0; i < frames; ++i) {
    const icgm::sim::SimFrame f = simulator.Render(i);
    truth_bgr.push_back(f.bgr);
    cv::Mat m = f.depth_m.clone();
    cv::patchNaNs(m, 0.0);
    truth_mm.emplace_back();
    m.convertTo(truth_mm.back(), CV_16UC1, 1000.0);
    truth_sw_mm.push_back(registration.Register(truth_mm.back()));
  }
  // Record: written under another name and renamed when complete, so the nodelets open it whole.
  const std::string partial = oni + ".partial";
  std::remove(oni.c_str());
  {
    icgm::OpenniCameraOptions options;
    options.uri = "icgm-virtual://sim?scenario=" + scenario + "&frames=" + std::to_string(frames);
    icgm::OpenniCamera camera;
    std::atomic<int> live{0};
    const icgm::Status opened =
        camera.Open(options, WallNow, [&](const icgm::RgbdPair&) { ++live; });
    ASSERT_TRUE(opened.ok()) << opened.reason();
    ASSERT_TRUE(camera.StartRecording(partial).ok());
    ASSERT_TRUE(camera.Start().ok());
    // The scenario runs at 10 Hz; the device renders each frame as it serves it.
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (live < frames && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the recorder's queue
    camera.Close();
  }
  int recorded = 0;
  {
    openni::Device file;
    ASSERT_EQ(file.open(partial.c_str()), openni::STATUS_OK) << openni::OpenNI::getExtendedError();
    openni::VideoStream color, depth;
    ASSERT_EQ(color.create(file, openni::SENSOR_COLOR), openni::STATUS_OK);
    ASSERT_EQ(depth.create(file, openni::SENSOR_DEPTH), openni::STATUS_OK);
    recorded = std::min(file.getPlaybackControl()->getNumberOfFrames(color),
                        file.getPlaybackControl()->getNumberOfFrames(depth));
    color.destroy();
    depth.destroy();
    file.close();
  }
  ASSERT_GE(recorded, frames - 2) << "frames the recorder missed";
  // The nodelets open the file once it appears and start playing on their first subscriber:
  // both of this test's subscriptions must be connected by then.
  const ros::WallTime connect_deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::WallTime::now() < connect_deadline && !(plain.connected() && software.connected())) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_TRUE(plain.connected() && software.connected()) << "the driver nodelets do not publish";
  ASSERT_EQ(std::rename(partial.c_str(), oni.c_str()), 0);

  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && ros::WallTime::now() < deadline &&
         (plain.num_colors() < static_cast<size_t>(recorded) ||
          software.num_colors() < static_cast<size_t>(recorded))) {
    ros::WallDuration(0.1).sleep();
  }
  ros::WallDuration(1.0).sleep();  // nothing more may arrive
  std::remove(oni.c_str());

  for (auto* received : {&plain, &software}) {
    const bool sw = received == &software;
    const auto colors = received->colors();
    const auto depths = received->depths();
    std::printf("%s: %d frames recorded, %zu colour and %zu depth images received\n",
                sw ? "camera_sw" : "camera", recorded, colors.size(), depths.size());
    // OpenNI keeps only a stream's newest frame: a loaded machine may miss one or two.
    EXPECT_GE(colors.size() + 2, static_cast<size_t>(recorded)) << (sw ? "camera_sw" : "camera");
    EXPECT_LE(colors.size(), static_cast<size_t>(recorded));
    EXPECT_EQ(depths.size(), colors.size());
    std::vector<int> index;
    std::vector<ros::Time> stamps;
    for (const auto& [stamp, m] : colors) {
      ASSERT_EQ(m->encoding, "bgr8");
      ASSERT_EQ(m->width, 640u);
      ASSERT_EQ(m->height, 480u);
      const int i = FindEqual(ImageOf(*m), truth_bgr);
      ASSERT_GE(i, 0) << "colour at " << stamp << " is no rendered frame";
      EXPECT_TRUE(index.empty() || i > index.back()) << "frame " << i << " repeated or reordered";
      // Colour and depth of one instant carry one stamp.
      const auto d = Nearest(depths, stamp, 0.001);
      ASSERT_NE(d, depths.end()) << "no depth stamped as colour frame " << i;
      ASSERT_EQ(d->second->encoding, "16UC1");
      const cv::Mat depth = ImageOf(*d->second);
      const cv::Mat& expected = sw ? truth_sw_mm[i] : truth_mm[i];
      EXPECT_EQ(cv::norm(depth, expected, cv::NORM_INF), 0.0) << "depth of frame " << i;
      index.push_back(i);
      stamps.push_back(stamp);
    }
    // Stamps: the device clock mapped to ROS time, rising on the scenario's 100 ms spacing
    // within the mapping's bound (how close it comes depends on when frames arrive, which the
    // machine's load decides).
    for (size_t k = 1; k < stamps.size(); ++k) {
      const double expected_s = (simulator.stamp(index[k]).nanoseconds() -
                                 simulator.stamp(index[k - 1]).nanoseconds()) * 1e-9;
      ExpectDeviceSpacing(
          stamps[k] - stamps[k - 1], expected_s,
          std::string(sw ? "camera_sw" : "camera") + ": frame " + std::to_string(index[k]));
    }
  }
  // Software registration changed the depth (the Kinect's depth camera is 2.5 cm to the side).
  EXPECT_GT(cv::norm(truth_sw_mm[0], truth_mm[0], cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace icgm_slam::test
