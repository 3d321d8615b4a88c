// A fakenect dump through the Kinect v1 driver and the driver nodelet (openni2_freenect.test):
// every frame pair of the dump arrives once (a loaded machine may miss one or two), 640x480
// bgr8 / 16UC1, colour equal to the dump's colour, depth equal to the dump's raw values in
// millimetres (camera) or to their software registration with the Kinect's depth camera
// (camera_sw), colour and depth of a pair on one stamp, stamps rising on the dump's device
// clock spacing (100 ms) within the clock mapping's bound.
#include <cmath>
#include <map>
#include <mutex>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include "core/dataset/camera_options.h"
#include "camera_images.h"
#include "core/sensor/depth_registration.h"
#include "core/sensor/fakenect_dump.h"
#include "core/sensor/kinect_disparity.h"

namespace icgm_slam::test {
namespace {

TEST(Openni2Freenect, FakenectDumpThroughTheKinectDriverAndTheNodelet) {
  ros::NodeHandle nh, pnh("~");
  std::string dump, camera_config;
  ASSERT_TRUE(pnh.getParam("dump", dump));
  ASSERT_TRUE(pnh.getParam("camera_config", camera_config));
  std::vector<icgm::FakenectFrame> frames;
  const icgm::Status read = icgm::ReadFakenectDump(dump, &frames);
  ASSERT_TRUE(read.ok()) << read.reason();
  // Truth from the dump: colour as BGR; depth decoded, and registered with the depth camera.
  icgm::DepthCameraCalibration depth_camera;
  ASSERT_TRUE(icgm::LoadDepthCameraCalibration(camera_config, &depth_camera));
  const icgm::DepthRegistration registration(depth_camera, icgm::LoadCameraIntrinsics(camera_config));
  std::vector<cv::Mat> bgr, mm, sw_mm;
  std::vector<uint64_t> device_us;
  for (const icgm::FakenectFrame& f : frames) {
    if (f.color) {
      bgr.emplace_back();
      cv::cvtColor(f.image, bgr.back(), cv::COLOR_RGB2BGR);
      device_us.push_back(f.timestamp / icgm::kKinectTicksPerUs);
    } else {
      mm.emplace_back(f.image.size(), CV_16UC1);
      icgm::KinectRawToMm(f.image.ptr<uint16_t>(), mm.back().ptr<uint16_t>(), f.image.total());
      sw_mm.push_back(registration.Register(mm.back()));
    }
  }
  ASSERT_EQ(bgr.size(), mm.size());
  const size_t n = bgr.size();
  CameraImages plain(nh, "camera"), software(nh, "camera_sw");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(40.0);
  while (ros::ok() && ros::WallTime::now() < deadline &&
         (plain.num_colors() < n || software.num_colors() < n)) {
    ros::WallDuration(0.1).sleep();
  }
  ros::WallDuration(1.0).sleep();  // nothing more may arrive

  for (auto* received : {&plain, &software}) {
    const char* ns = received == &plain ? "camera" : "camera_sw";
    const ImagesByStamp colors = received->colors(), depths = received->depths();
    EXPECT_GE(colors.size() + 2, n) << ns;
    EXPECT_LE(colors.size(), n) << ns;
    // The nodelets start their streams on the first subscriber: this test's other subscription
    // may connect a frame or two later and miss those of its topic (at the start only).
    EXPECT_LE(depths.size(), colors.size() + 2) << ns;
    EXPECT_LE(colors.size(), depths.size() + 2) << ns;
    int previous = -1;
    bool paired = false;
    ros::Time previous_stamp;
    for (const auto& [stamp, m] : colors) {
      ASSERT_EQ(m->encoding, "bgr8");
      ASSERT_EQ(m->width, 640u);
      ASSERT_EQ(m->height, 480u);
      const cv::Mat image = ImageOf(*m);
      int i = -1;
      for (size_t k = 0; k < n && i < 0; ++k) {
        if (cv::norm(image, bgr[k], cv::NORM_INF) == 0.0) i = static_cast<int>(k);
      }
      ASSERT_GE(i, 0) << ns << ": colour at " << stamp << " is no frame of the dump";
      EXPECT_GT(i, previous) << ns << ": frame " << i << " repeated or reordered";
      const auto d = depths.find(stamp);  // one device instant, one stamp
      if (d == depths.end() && !paired && i < 2) {
        previous = i;
        previous_stamp = stamp;
        continue;  // published before the depth subscription connected
      }
      ASSERT_NE(d, depths.end()) << ns << ": no depth stamped as colour frame " << i;
      paired = true;
      ASSERT_EQ(d->second->encoding, "16UC1");
      const cv::Mat& expected = received == &plain ? mm[i] : sw_mm[i];
      EXPECT_EQ(cv::norm(ImageOf(*d->second), expected, cv::NORM_INF), 0.0) << ns << ": depth of frame " << i;
      // Stamped on the device clock: rising with the dump's stamps, each interval the device's
      // within what the mapping guarantees whatever the arrivals (DeviceClock's slew and drift
      // bound). How close the mapping comes to the device spacing depends on when frames reach
      // the nodelet, which the machine's load decides: device_clock_test measures that on
      // simulated arrivals.
      if (previous >= 0) {
        ExpectDeviceSpacing(
            stamp - previous_stamp,
            (static_cast<double>(device_us[i]) - static_cast<double>(device_us[previous])) * 1e-6,
            std::string(ns) + ": frame " + std::to_string(i));
      }
      previous = i;
      previous_stamp = stamp;
    }
  }
  EXPECT_GT(cv::norm(sw_mm[0], mm[0], cv::NORM_INF), 0.0) << "registration changed nothing";
}

}  // namespace
}  // namespace icgm_slam::test
