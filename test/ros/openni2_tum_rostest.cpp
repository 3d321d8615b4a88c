// Virtual OpenNI2 device (first frames of TUM fr1/xyz) -> openni2_camera driver nodelet ->
// feature extraction -> registration -> fusion, against icgm_slam_offline on the same frames.
// Checks the driver's topics (encodings, sizes, camera_info from the camera YAML, stamps spaced
// as the recording's) and that the fused odometry's ATE matches the offline run's.
// With ~cpu_report the test takes the frames' stamps from camera_info instead of the images (no
// image leaves the manager) and prints (and appends to ~report when given) the manager's CPU per
// fused pose, the virtual device's decoding thread left out (a real camera decodes in its
// hardware), next to the offline front end's CPU per frame on the same frames: the robot's own
// configuration, where the camera driver runs in the pipeline's manager and the images reach the
// nodelets without serialization (launch_scripts/benchmark_live.sh --driver).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/dataset/camera_options.h"
#include "core/dataset/trajectory.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/sensor/virtual_device_uri.h"
#include "process_cpu.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam::test {
namespace {

// Offset that carries TUM colour stamps onto the received ones (the device clock starts at the
// sequence's first image). When every frame arrived, the i-th received is the i-th recorded:
// the median difference. Otherwise the candidate that best explains every received stamp (the
// recording's spacing repeats, so a candidate a frame off may explain them almost as well).
double StampOffset(const std::vector<double>& received, const std::vector<double>& tum) {
  if (received.size() == tum.size()) {
    std::vector<double> differences;
    for (size_t i = 0; i < tum.size(); ++i) differences.push_back(received[i] - tum[i]);
    std::nth_element(differences.begin(), differences.begin() + differences.size() / 2,
                     differences.end());
    return differences[differences.size() / 2];
  }
  double best = 0.0, best_cost = 1e18;
  for (size_t k = 0; k < std::min<size_t>(tum.size(), 15); ++k) {
    const double offset = received.front() - tum[k];
    double cost = 0.0;
    for (double r : received) {
      double nearest = 1e9;
      for (double t : tum) nearest = std::min(nearest, std::fabs(r - offset - t));
      cost += nearest;
    }
    if (cost < best_cost) {
      best_cost = cost;
      best = offset;
    }
  }
  return best;
}

TEST(Openni2Driver, VirtualKinectThroughThePipelineMatchesOffline) {
  ros::NodeHandle nh, pnh("~");
  std::string tum_dir, tool, camera_config;
  int frames = 100;
  double rate = 0.5, max_diff = 0.004;
  ASSERT_TRUE(pnh.getParam("tum_dir", tum_dir));
  ASSERT_TRUE(pnh.getParam("offline_tool", tool));
  ASSERT_TRUE(pnh.getParam("camera_config", camera_config));
  pnh.getParam("frames", frames);
  pnh.getParam("rate", rate);
  pnh.getParam("max_ate_difference_m", max_diff);
  bool cpu_report = false;
  std::string report_path, manager = "/icgm_manager";
  pnh.getParam("cpu_report", cpu_report);
  pnh.getParam("report", report_path);
  pnh.getParam("manager", manager);
  // Wall time between /clock messages: every nodelet on simulated time receives each one.
  double clock_period_s = 0.002;
  pnh.getParam("clock_period_s", clock_period_s);
  // false: wall time, as on the robot (no /clock); the device then plays at rate 1 only.
  bool sim_time = true;
  pnh.getParam("sim_time", sim_time);
  ASSERT_TRUE(sim_time || rate == 1.0) << "wall time needs rate 1";

  std::mutex mutex;
  std::vector<double> rgb_stamps, depth_stamps;
  std::vector<std::string> problems;
  sensor_msgs::CameraInfo info;
  int infos = 0;
  icgm::Trajectory live;
  auto problem = [&](const std::string& p) {
    if (problems.size() < 10) problems.push_back(p);
  };
  ros::Subscriber rgb_sub, depth_sub;
  if (cpu_report) {
    // The stamps only: camera_info is published with each image under the image's stamp.
    rgb_sub = nh.subscribe<sensor_msgs::CameraInfo>(
        "/camera/rgb/camera_info", 200, [&](const sensor_msgs::CameraInfoConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex);
          rgb_stamps.push_back(m->header.stamp.toSec());
        });
  } else {
    rgb_sub = nh.subscribe<sensor_msgs::Image>(
        "/camera/rgb/image_color", 200, [&](const sensor_msgs::ImageConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex);
          if (m->encoding != "bgr8" || m->width != 640 || m->height != 480) problem("rgb " + m->encoding);
          if (m->header.frame_id != "camera_rgb_optical_frame") problem("rgb frame " + m->header.frame_id);
          rgb_stamps.push_back(m->header.stamp.toSec());
        });
    depth_sub = nh.subscribe<sensor_msgs::Image>(
        "/camera/depth_registered/image_raw", 200, [&](const sensor_msgs::ImageConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex);
          if (m->encoding != "16UC1" || m->width != 640 || m->height != 480) problem("depth " + m->encoding);
          depth_stamps.push_back(m->header.stamp.toSec());
        });
  }
  ros::Subscriber info_sub = nh.subscribe<sensor_msgs::CameraInfo>(
      "/camera/depth_registered/camera_info", 200, [&](const sensor_msgs::CameraInfoConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        info = *m;
        ++infos;
        if (cpu_report) depth_stamps.push_back(m->header.stamp.toSec());
      });
  ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 500, [&](const nav_msgs::OdometryConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        live.push_back({icgm::ros_bridge::FromRos(m->header.stamp),
                        icgm::ros_bridge::FromPoseMsg(m->pose.pose)});
      });
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // The driver opens the device once simulated time runs, and starts its streams as soon as
  // anyone (the pipeline) listens: the clock starts when this test's subscriptions are
  // connected, so that it sees the first frames too.
  const ros::WallTime connect_deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::WallTime::now() < connect_deadline &&
         (rgb_sub.getNumPublishers() == 0 ||
          (cpu_report ? info_sub : depth_sub).getNumPublishers() == 0)) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_GT(rgb_sub.getNumPublishers(), 0u) << "the driver nodelet does not publish colour";
  ASSERT_GT((cpu_report ? info_sub : depth_sub).getNumPublishers(), 0u)
      << "the driver nodelet does not publish depth";
  const int manager_pid = cpu_report ? NodePid(manager) : -1;
  if (cpu_report) {
    ASSERT_GT(manager_pid, 0) << "no pid for " << manager;
  }
  auto manager_cpu_ms = [&] {
    return ProcessCpuMsWithout(manager_pid, icgm::kVirtualDeviceLoaderThread);
  };
  const double manager_cpu0 = cpu_report ? manager_cpu_ms() : 0.0;
  const double manager_all_cpu0 = cpu_report ? ProcessCpuMs(manager_pid) : 0.0;
  double manager_cpu_at_last_pose = manager_cpu0, manager_all_cpu_at_last_pose = manager_all_cpu0;
  // Simulated time at `rate` of wall time, as the virtual device plays.
  ros::Publisher clock_pub = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  std::atomic<bool> stop{false};
  std::thread clock_thread([&] {
    const ros::WallTime start = ros::WallTime::now();
    while (sim_time && !stop) {
      rosgraph_msgs::Clock c;
      c.clock = ros::Time(1000.0 + rate * (ros::WallTime::now() - start).toSec());
      clock_pub.publish(c);
      ros::WallDuration(clock_period_s).sleep();
    }
  });

  // Until the sequence has played (frames / 30 Hz / rate) and the pipeline fell quiet.
  const ros::WallTime start = ros::WallTime::now();
  size_t last_count = 0;
  ros::WallTime last_change = start;
  while ((ros::WallTime::now() - start).toSec() < 150.0) {
    ros::WallDuration(0.5).sleep();
    std::lock_guard<std::mutex> lock(mutex);
    if (live.size() != last_count) {
      last_count = live.size();
      last_change = ros::WallTime::now();
      if (cpu_report) {
        manager_cpu_at_last_pose = manager_cpu_ms();
        manager_all_cpu_at_last_pose = ProcessCpuMs(manager_pid);
      }
    }
    if (last_count > 0 && (ros::WallTime::now() - last_change).toSec() > 8.0) break;
  }
  stop = true;
  clock_thread.join();
  spinner.stop();

  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& p : problems) ADD_FAILURE() << p;
  // A loaded machine misses a few frames (OpenNI keeps only a stream's newest one).
  ASSERT_GE(rgb_stamps.size(), static_cast<size_t>(frames * 0.8));
  EXPECT_GE(depth_stamps.size(), static_cast<size_t>(frames * 0.8));
  // camera_info from the camera YAML.
  const icgm::CameraIntrinsics k = icgm::LoadCameraIntrinsics(camera_config);
  ASSERT_GT(infos, 0);
  EXPECT_NEAR(info.K[0], k.fx_px, 1e-9);
  EXPECT_NEAR(info.K[2], k.cx_px, 1e-9);
  EXPECT_EQ(info.width, 640u);

  // Stamps: the recording's spacing on the simulated clock, within the clock mapping's jitter.
  icgm::CameraIntrinsics tum_k;
  tum_k.depth_scale = 5000.0;
  const icgm::TumDataset tum = icgm::TumDataset::Open(tum_dir, tum_k);
  std::vector<double> tum_rgb;
  for (size_t i = 0; i < std::min<size_t>(tum.size(), frames); ++i) tum_rgb.push_back(tum.frame(i).stamp.seconds());
  double offset = StampOffset(rgb_stamps, tum_rgb);
  {
    // Refine the offset (found from the first stamp alone) by the median signed residual.
    std::vector<double> signed_residuals;
    for (double r : rgb_stamps) {
      double best = 1e9;
      for (double t : tum_rgb) {
        if (std::fabs(r - offset - t) < std::fabs(best)) best = r - offset - t;
      }
      signed_residuals.push_back(best);
    }
    std::sort(signed_residuals.begin(), signed_residuals.end());
    offset += signed_residuals[signed_residuals.size() / 2];
  }
  // After the clock mapping's first second (its lower envelope still settling). The simulated
  // clock reaches the nodelet in steps (a /clock message every 2 ms of wall time, delivered late
  // under load), which would stamp single arrivals early; the mapping ignores such lone samples
  // and keeps the device's spacing.
  std::vector<double> errors;
  for (size_t i = 0; i < rgb_stamps.size(); ++i) {
    const double r = rgb_stamps[i];
    if (r < rgb_stamps.front() + 1.0) continue;
    double nearest = 1e9;
    for (double t : tum_rgb) nearest = std::min(nearest, std::fabs(r - offset - t));
    errors.push_back(nearest);
    if (nearest > 0.010) {
      std::printf("colour %zu stamped %.1f ms off the recording (%.1f ms after the previous)\n", i,
                  nearest * 1e3, (r - rgb_stamps[i - 1]) * 1e3);
    }
  }
  ASSERT_FALSE(errors.empty());
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2], worst = errors.back();
  EXPECT_LT(median, 0.006) << "received colour stamps stray from the recording's spacing";
  // The mapping follows the device clock: no frame strays by a sizeable part of a frame period.
  EXPECT_LT(worst, 0.010);
  EXPECT_TRUE(std::is_sorted(rgb_stamps.begin(), rgb_stamps.end()));

  // The fused odometry, carried to the TUM time base, against the offline run on the same input.
  ASSERT_GE(live.size(), static_cast<size_t>(frames * 0.7));
  icgm::Trajectory live_tum;
  for (const auto& s : live) {
    live_tum.push_back({icgm::Time::FromSeconds(s.stamp.seconds() - offset), s.pose});
  }
  // The offline tool on the same input: the same frames with the stamps the driver gave them
  // (carried to the recording's time base), as a TUM folder. When every frame arrived, the
  // i-th message is the i-th frame; otherwise the nearest recorded stamp says which it is.
  const std::string folder = "/tmp/icgm_openni2_tum_input_" + std::to_string(getpid());
  std::system(("rm -rf " + folder + " && mkdir -p " + folder).c_str());
  auto write_list = [&](const std::string& name, const std::vector<double>& received, bool rgb) {
    std::FILE* f = std::fopen((folder + "/" + name).c_str(), "w");
    ASSERT_NE(f, nullptr);
    const bool in_order = received.size() == tum_rgb.size();
    for (size_t i = 0; i < received.size(); ++i) {
      size_t k = i;
      if (!in_order) {
        k = 0;
        for (size_t j = 1; j < tum_rgb.size(); ++j) {
          if (std::fabs(received[i] - offset - tum_rgb[j]) <
              std::fabs(received[i] - offset - tum_rgb[k])) {
            k = j;
          }
        }
      }
      const icgm::RgbdFrameRef& ref = tum.frame(k);
      std::fprintf(f, "%.6f %s\n", received[i] - offset,
                   (rgb ? ref.rgb_path : ref.depth_path).c_str());
    }
    std::fclose(f);
  };
  write_list("rgb.txt", rgb_stamps, true);
  write_list("depth.txt", depth_stamps, false);
  std::system(("ln -s " + tum_dir + "/groundtruth.txt " + folder + "/groundtruth.txt").c_str());
  const std::string out = folder + "/offline.txt";
  const std::string summary = folder + "/offline_summary.txt";
  const std::string cmd = tool + " --tum " + folder + " --camera " + camera_config +
                          " --trajectory " + out + " > " + summary + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  // The offline front end's CPU per frame: the summary's "total, thread CPU" mean.
  double offline_cpu_ms = -1.0;
  {
    std::ifstream in(summary);
    std::string line;
    const std::string key = "total, thread CPU";
    while (std::getline(in, line)) {
      if (line.compare(0, key.size(), key) == 0) offline_cpu_ms = std::atof(line.c_str() + key.size());
    }
  }
  const icgm::Trajectory offline = icgm::ReadTumTrajectory(out);
  std::system(("rm -rf " + folder).c_str());
  icgm::TrajectoryEvaluation ev_live, ev_offline;
  ASSERT_TRUE(icgm::EvaluateTrajectory(tum.groundtruth(), live_tum, {}, &ev_live).ok());
  ASSERT_TRUE(icgm::EvaluateTrajectory(tum.groundtruth(), offline, {}, &ev_offline).ok());
  std::printf("driver -> pipeline on %d fr1/xyz frames: %zu colour, %zu odometry, stamps within "
              "%.1f ms (median %.1f ms); ATE live %.4f m, offline %.4f m\n",
              frames, rgb_stamps.size(), live.size(), worst * 1e3, median * 1e3, ev_live.ate.rmse,
              ev_offline.ate.rmse);
  EXPECT_LT(std::fabs(ev_live.ate.rmse - ev_offline.ate.rmse), max_diff);
  if (cpu_report) {
    ASSERT_GT(offline_cpu_ms, 0.0) << "no \"total, thread CPU\" line from " << cmd;
    const double live_cpu_ms = (manager_cpu_at_last_pose - manager_cpu0) / live.size();
    const double all_cpu_ms = (manager_all_cpu_at_last_pose - manager_all_cpu0) / live.size();
    char line[500];
    std::snprintf(line, sizeof(line),
                  "driver in the manager, fr1/xyz %d frames at rate %.2f: %zu fused poses of %zu "
                  "colour frames, ATE live %.4f m, offline %.4f m; CPU per frame: nodelet manager "
                  "%.1f ms (the virtual device's decoding left out; %.1f ms with it), offline "
                  "front end %.1f ms (%.2fx)\n",
                  frames, rate, live.size(), rgb_stamps.size(), ev_live.ate.rmse,
                  ev_offline.ate.rmse, live_cpu_ms, all_cpu_ms, offline_cpu_ms,
                  live_cpu_ms / offline_cpu_ms);
    std::printf("%s", line);
    if (!report_path.empty()) std::ofstream(report_path, std::ios::app) << line;
  }
}

}  // namespace
}  // namespace icgm_slam::test
