// Live equals offline: replays a bag (rendered by the simulator, or a real sequence converted
// with icgm_tum_to_bag) through the nodelets (feature extraction -> registration -> fusion) in
// real time on simulated time (/clock at ~rate, as `rosbag play --clock -r rate` would), runs
// the same bag through the core front end in process as icgm_slam_offline does (wheel odometry
// fed up to 50 ms after each frame, extrinsic from /tf_static), and compares both with the
// ground truth.
//
// Checks (with ~check, default true): every frame the pipeline can answer produced a relative
// pose and a fused pose, and the two ATEs differ by at most ~max_ate_difference_m. Always
// prints (and appends to ~report when given) the ATEs and the CPU time per frame of the nodelet
// manager vs the in-process front end, so launch_scripts/benchmark_live.sh can run it at other
// rates. With ~max_lag_frames >= 0 the replay holds its clock while the pipeline is more than
// that many frames behind (beyond the features' and registration's own delay), as the simulator
// nodelet's sync does: a loaded machine then slows the replay instead of dropping frames, so the
// comparison measures the pipeline and not the machine.
// The report also follows the frames stage by stage, from the nodelets' counts on /diagnostics
// (frame_counts.h): images the feature extraction received, skipped (its backpressure) and
// extracted; frames the registration paired with depth, refused, dropped and processed.
//
// Map (with ~compare_map and ~check): icgm_slam_offline (next to this binary) builds its map of
// the same bag (--bag --map); the map builder nodelet's map, saved through its save_map service
// after the replay, must have the same keyframes (stamps), the same robust features per keyframe
// and keyframe poses within ~max_keyframe_difference_m (and 0.1 degree). With ~flush_by_mode_switch
// the registration keeps a held keyframe (map_features.source tracker) until asked: the map builder
// is switched to localization and back before the save, and the switch must bring it into the map
// (the offline map has it from the end of the frames), through the service
// `<~keyframes_topic>/flush` (default /icgm/keyframes/flush); ~max_frames (> 0: the first frames
// only, live and offline) must end on a keyframe.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <icgm_slam/RegistrationResult.h>
#include <icgm_slam/SaveMap.h>
#include <icgm_slam/SetMapMode.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>
#include <opencv2/core.hpp>

#include "core/common/option_reader.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/map/map_store.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/slam/slam_options.h"
#include "core/slam/wheel_feed.h"
#include "ros_bridge/bag_reader.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"
#include "process_cpu.h"
#include "sibling_executable.h"

namespace icgm_slam::test {
namespace {

namespace topics = icgm::ros_bridge::topics;

double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// -1 when the trajectory cannot be aligned (an error unless `may_fail`: a short straight run).
double Ate(const icgm::Trajectory& gt, const icgm::Trajectory& est, bool may_fail) {
  icgm::TrajectoryEvaluation e;
  const icgm::Status s = icgm::EvaluateTrajectory(gt, est, icgm::TrajectoryEvalOptions{}, &e);
  EXPECT_TRUE(s.ok() || may_fail) << s.reason();
  return s.ok() ? e.ate.rmse : -1.0;
}

// The latest frame counts of each nodelet (status name "<nodelet>: frames") on /diagnostics.
class StageCounts {
 public:
  void Add(const diagnostic_msgs::DiagnosticArray& array) {
    for (const auto& status : array.status) {
      for (const auto& kv : status.values) counts_[status.name][kv.key] = std::stol(kv.value);
    }
  }
  // -1 when `nodelet` has not reported `key`.
  long Get(const std::string& nodelet, const std::string& key) const {
    const auto n = counts_.find(nodelet + ": frames");
    if (n == counts_.end()) return -1;
    const auto k = n->second.find(key);
    return k == n->second.end() ? -1 : k->second;
  }

 private:
  std::map<std::string, std::map<std::string, long>> counts_;
};

struct OfflineRun {
  icgm::Trajectory trajectory;        // T_odom_camera per frame
  double cpu_ms_per_frame = 0;        // the front end (ProcessFrame)
  double total_cpu_ms_per_frame = 0;  // with reading and decoding the bag, as the tool does
};

// The front end over the bag as icgm_slam_offline --bag runs it.
// `odometry_config` (may be empty: config_dir's odometry.yaml) as the nodelets' odometry_config;
// camera_only: no wheels, no extrinsic (a hand-held camera). pace_rate > 0: each frame is handed
// to the front end no sooner than its bag time divided by pace_rate after the first (as the
// replay hands them to the nodelets), instead of back to back.
OfflineRun RunOffline(const std::string& bag_path, const std::string& config_dir,
                      const std::string& odometry_config, bool camera_only, int max_frames,
                      double pace_rate = 0.0) {
  OfflineRun run;
  icgm::ros_bridge::BagReader reader(bag_path);
  icgm::ros_bridge::RgbdBagStream stream(reader, icgm::ros_bridge::RgbdBagTopics{});
  icgm::FrontendOptions options = icgm::LoadSlamOptions(config_dir).frontend;
  if (!odometry_config.empty()) {
    icgm::ReadFrontendOptions(icgm::OptionReader::FromFile(odometry_config),
                              icgm::OptionReader::FromFile(config_dir + "/icgm.yaml"), &options);
  }
  EXPECT_EQ(stream.base_to_camera().has_value(), !camera_only);
  if (stream.base_to_camera()) options.fusion.base_to_camera = *stream.base_to_camera();
  icgm::RgbdFrontend frontend(options, stream.intrinsics());
  icgm::WheelFeed wheel(0.05, stream.wheel_odometry().size() + 1);  // as icgm_slam_offline
  for (const auto& w : stream.wheel_odometry()) wheel.Add(w.stamp, w.pose);
  double cpu = 0;
  const double total0 = ThreadCpuMs();
  icgm::ros_bridge::RgbdBagFrame frame;
  std::optional<icgm::Time> first_stamp;
  const auto wall_start = std::chrono::steady_clock::now();
  while ((max_frames <= 0 || static_cast<int>(run.trajectory.size()) < max_frames) &&
         stream.Next(&frame)) {
    if (pace_rate > 0) {
      if (!first_stamp) first_stamp = frame.stamp;
      const double due_s = icgm::DurationSeconds(frame.stamp, *first_stamp) / pace_rate;
      std::this_thread::sleep_until(wall_start + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                     std::chrono::duration<double>(due_s)));
    }
    wheel.FeedUpTo(frame.stamp, [&](icgm::Time t, const icgm::Pose3& odom_base) {
      frontend.AddWheelOdometry(t, odom_base);
    });
    const double c0 = ThreadCpuMs();
    const icgm::FrontendFrameResult r =
        frontend.ProcessFrame(frame.stamp, frame.bgr, frame.depth_m, frame.depth_stamp);
    cpu += ThreadCpuMs() - c0;
    run.trajectory.push_back({r.stamp, r.odom_camera});
  }
  const double n = std::max<size_t>(1, run.trajectory.size());
  run.cpu_ms_per_frame = cpu / n;
  run.total_cpu_ms_per_frame = (ThreadCpuMs() - total0) / n;
  return run;
}

// The offline tool's map of the bag (as a user runs it), or an empty map when it failed.
icgm::HybridMap OfflineMap(const std::string& tool, const std::string& bag_path,
                           const std::string& config_dir, const std::string& odometry_config,
                           bool camera_only, int max_frames, const std::string& map_path) {
  std::string cmd = tool + " --bag " + bag_path + " --trajectory " + map_path + ".txt --map " +
                    map_path + " --icgm-config " + config_dir + "/icgm.yaml --map-config " +
                    config_dir + "/map.yaml --config " +
                    (odometry_config.empty() ? config_dir + "/odometry.yaml" : odometry_config) +
                    (camera_only ? " --camera-only" : "") +
                    (max_frames > 0 ? " --max-frames " + std::to_string(max_frames) : "") + " > " +
                    map_path + ".log 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  try {
    return icgm::LoadMap(map_path);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "offline map: " << e.what();
    return icgm::HybridMap();
  }
}

// Keyframe by keyframe (in id order): stamp, robust feature count and pose L_n.
// Only offline keyframes stamped up to `last_processed` count (the last frames the live
// pipeline could not match have none).
void CompareMaps(const icgm::HybridMap& offline, const icgm::HybridMap& live,
                 icgm::Time last_processed, double max_m) {
  int offline_count = 0;
  for (const icgm::Keyframe& k : offline.keyframes()) offline_count += k.stamp <= last_processed;
  std::printf("map: live %d keyframes, offline %d (%d of them up to the last processed frame)\n",
              live.size(), offline.size(), offline_count);
  EXPECT_GT(offline_count, 1);
  ASSERT_EQ(live.size(), offline_count);
  double worst_m = 0, worst_deg = 0;
  size_t robust_live = 0, robust_offline = 0;
  for (int i = 0; i < live.size(); ++i) {
    const icgm::Keyframe& a = offline.keyframe(i);
    const icgm::Keyframe& b = live.keyframe(i);
    EXPECT_EQ(a.stamp, b.stamp) << "keyframe " << i;
    EXPECT_EQ(a.keypoints.size(), b.keypoints.size()) << "robust features of keyframe " << i;
    robust_offline += a.keypoints.size();
    robust_live += b.keypoints.size();
    const icgm::Pose3 d = a.global_pose.inverse() * b.global_pose;
    worst_m = std::max(worst_m, d.translation().norm());
    worst_deg = std::max(worst_deg, Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI);
  }
  std::printf(
      "map: robust features live %zu, offline %zu; keyframe poses differ by at most "
      "%.6f m, %.4f deg\n",
      robust_live, robust_offline, worst_m, worst_deg);
  EXPECT_LE(worst_m, max_m);
  EXPECT_LE(worst_deg, 0.1);
}

TEST(LiveEqualsOffline, NodeletsMatchTheOfflineFrontEnd) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string bag_path, config_dir, report_path, manager;
  ASSERT_TRUE(pnh.getParam("bag", bag_path));
  ASSERT_TRUE(pnh.getParam("config_dir", config_dir));
  pnh.param<std::string>("report", report_path, "");
  pnh.param<std::string>("manager", manager, "/icgm_manager");
  double rate = 1.0, max_ate_difference_m = 0.002;
  bool check = true;
  pnh.param("rate", rate, rate);
  pnh.param("max_ate_difference_m", max_ate_difference_m, max_ate_difference_m);
  pnh.param("check", check, check);
  int max_lag_frames = -1;
  pnh.param("max_lag_frames", max_lag_frames, max_lag_frames);
  std::string odometry_config;
  bool camera_only = false;
  pnh.param<std::string>("odometry_config", odometry_config, "");
  pnh.param("camera_only", camera_only, camera_only);
  bool compare_map = false;
  double max_keyframe_difference_m = 0.002;
  pnh.param("compare_map", compare_map, compare_map);
  int max_frames = 0;  // > 0: only the bag's first frames, live and offline
  pnh.param("max_frames", max_frames, max_frames);
  // Also the offline front end fed at the replay's pace (report only: a second offline run).
  bool paced_offline = false;
  pnh.param("paced_offline", paced_offline, paced_offline);
  pnh.param("max_keyframe_difference_m", max_keyframe_difference_m, max_keyframe_difference_m);
  bool flush_by_mode_switch = false;
  pnh.param("flush_by_mode_switch", flush_by_mode_switch, flush_by_mode_switch);
  std::string keyframes_topic;
  pnh.param<std::string>("keyframes_topic", keyframes_topic, "/icgm/keyframes");
  compare_map = compare_map && check;
  const std::string offline_tool = SiblingExecutable("icgm_slam_offline");
  const int delay = 1;  // registration needs a reference (features come without delay)

  // 1. Offline, before the replay (the two never share the CPU).
  cv::setNumThreads(1);
  const OfflineRun offline =
      RunOffline(bag_path, config_dir, odometry_config, camera_only, max_frames);
  ASSERT_GE(offline.trajectory.size(), 30u);
  const double paced_cpu_ms =
      paced_offline
          ? RunOffline(bag_path, config_dir, odometry_config, camera_only, max_frames, rate)
                .cpu_ms_per_frame
          : 0.0;
  icgm::ros_bridge::BagReader reader(bag_path);
  icgm::ros_bridge::RgbdBagStream stream(reader, icgm::ros_bridge::RgbdBagTopics{});
  ASSERT_FALSE(stream.ground_truth().empty()) << bag_path << " has no ground truth";
  ASSERT_EQ(stream.base_to_camera().has_value(), !camera_only);
  // Camera only: the odometry's child frame is the camera itself.
  const icgm::Pose3 base_to_camera = stream.base_to_camera().value_or(icgm::Pose3::Identity());
  const size_t wheel_listeners = camera_only ? 0 : 2;

  // 2. Live: the bag's sensor topics on simulated time at `rate`.
  std::vector<icgm_slam::RegistrationResult::ConstPtr> relative;
  std::vector<nav_msgs::Odometry::ConstPtr> odom;
  ros::Subscriber relative_sub = nh.subscribe<icgm_slam::RegistrationResult>(
      "/icgm/relative_pose", 1000,
      [&](const icgm_slam::RegistrationResult::ConstPtr& m) { relative.push_back(m); });
  ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 1000, [&](const nav_msgs::Odometry::ConstPtr& m) { odom.push_back(m); });
  StageCounts stages;
  ros::Subscriber diagnostics_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100,
      [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) { stages.Add(*m); });
  ros::Publisher clock_pub = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  ros::Publisher rgb_pub = nh.advertise<sensor_msgs::Image>(topics::kRgbImage, 100);
  ros::Publisher depth_pub = nh.advertise<sensor_msgs::Image>(topics::kDepthImageMm, 100);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>(topics::kRgbInfo, 100);
  ros::Publisher odom_pub = nh.advertise<nav_msgs::Odometry>(topics::kWheelOdom, 1000);
  ros::Publisher static_pub = nh.advertise<tf2_msgs::TFMessage>(topics::kTfStatic, 10, true);
  const ros::WallTime wait_end = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && ros::WallTime::now() < wait_end &&
         (rgb_pub.getNumSubscribers() == 0 || depth_pub.getNumSubscribers() == 0 ||
          info_pub.getNumSubscribers() == 0 || odom_pub.getNumSubscribers() < wheel_listeners ||
          relative_sub.getNumPublishers() == 0 || odom_sub.getNumPublishers() == 0)) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_GT(rgb_pub.getNumSubscribers(), 0u) << "pipeline did not subscribe";
  // The map builder subscribes to the keyframes before it offers its services.
  if (compare_map) {
    ASSERT_TRUE(ros::service::waitForService("/map_builder/save_map", 30000));
  }
  ros::WallDuration(0.5).sleep();  // synchronisers connected
  const int manager_pid = NodePid(manager);
  const double manager_cpu0 = manager_pid > 0 ? ProcessCpuMs(manager_pid) : -1;

  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  rosbag::View view(bag,
                    rosbag::TopicQuery({topics::kRgbImage, topics::kDepthImageMm, topics::kRgbInfo,
                                        topics::kWheelOdom, topics::kTfStatic}));
  const ros::WallTime wall0 = ros::WallTime::now();
  const ros::Time bag0 = view.getBeginTime();
  int frames = 0;
  ros::WallDuration held(0.0);  // wall time the replay waited for the pipeline
  ros::Time last_rgb_stamp, last_depth_stamp, last_clock;
  bool cut = false;  // ~max_frames ended the replay
  for (const rosbag::MessageInstance& m : view) {
    if (!ros::ok()) break;
    if (max_frames > 0 && frames >= max_frames && m.getTopic() == topics::kRgbImage) {
      cut = true;  // what came before this image (its depth too) matches the last frame
      break;
    }
    if (max_lag_frames >= 0 && m.getTopic() == topics::kRgbImage) {
      const ros::WallTime hold_start = ros::WallTime::now();
      const ros::WallTime give_up = hold_start + ros::WallDuration(10.0);
      while (ros::ok() && ros::WallTime::now() < give_up &&
             frames - delay - static_cast<int>(relative.size()) > max_lag_frames) {
        ros::spinOnce();
        ros::WallDuration(0.002).sleep();
      }
      held += ros::WallTime::now() - hold_start;
    }
    const ros::WallTime due = wall0 + held + ros::WallDuration((m.getTime() - bag0).toSec() / rate);
    const ros::WallDuration wait = due - ros::WallTime::now();
    if (wait > ros::WallDuration(0)) wait.sleep();
    // The clock moves with the bag's time: messages recorded at one instant (a simulated
    // frame's image, depth, camera_info and wheel sample) share one /clock message.
    if (m.getTime() != last_clock) {
      rosgraph_msgs::Clock clock;
      clock.clock = m.getTime();
      clock_pub.publish(clock);
      last_clock = m.getTime();
    }
    const std::string& t = m.getTopic();
    if (t == topics::kTfStatic) {
      static_pub.publish(m.instantiate<tf2_msgs::TFMessage>());
    } else if (t == topics::kWheelOdom) {
      odom_pub.publish(m.instantiate<nav_msgs::Odometry>());
    } else if (t == topics::kRgbImage) {
      const sensor_msgs::Image::ConstPtr image = m.instantiate<sensor_msgs::Image>();
      last_rgb_stamp = image->header.stamp;
      rgb_pub.publish(image);
      ++frames;
    } else if (t == topics::kDepthImageMm) {
      const sensor_msgs::Image::ConstPtr depth = m.instantiate<sensor_msgs::Image>();
      last_depth_stamp = depth->header.stamp;
      depth_pub.publish(depth);
    } else if (t == topics::kRgbInfo) {
      info_pub.publish(m.instantiate<sensor_msgs::CameraInfo>());
    }
    ros::spinOnce();
  }
  // The approximate-time synchroniser of features and depth matches a frame once a later
  // message shows that no closer partner will come: when the last depth image is stamped apart
  // from the last colour image (a real camera), nothing follows it and the last frame stays
  // unmatched. Frames with exactly equal stamps (simulated bags) are matched at once.
  const int held_at_end = !cut && last_depth_stamp != last_rgb_stamp ? 1 : 0;
  // Wait for the pipeline to finish what it got (bounded).
  const size_t expected = static_cast<size_t>(std::max(0, frames - delay - held_at_end));
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(20.0);
  while (ros::ok() && ros::WallTime::now() < end && odom.size() < expected) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ros::WallDuration(0.5).sleep();
  ros::spinOnce();
  const double manager_cpu_ms = manager_pid > 0 ? ProcessCpuMs(manager_pid) - manager_cpu0 : -1;
  // The nodelets publish their counts once a second after a change.
  const ros::WallTime counts_end = ros::WallTime::now() + ros::WallDuration(1.5);
  while (ros::ok() && ros::WallTime::now() < counts_end) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }

  // 3. Compare.
  icgm::Trajectory live, offline_common;
  for (const auto& m : odom) {
    const icgm::Time t = icgm::ros_bridge::FromRos(m->header.stamp);
    live.push_back({t, icgm::ros_bridge::FromPoseMsg(m->pose.pose) * base_to_camera});
  }
  for (const auto& p : offline.trajectory) {
    for (const auto& q : live) {
      if (q.stamp == p.stamp) offline_common.push_back(p);
    }
  }
  size_t vision = 0;
  for (const auto& r : relative) vision += r->success;
  // Frame by frame: the live relative motion against the offline one between the same stamps;
  // the first frame where they part says where the two paths differ.
  int differing = 0, first_differing = -1;
  for (size_t i = 0; i < relative.size(); ++i) {
    const icgm::Time t = icgm::ros_bridge::FromRos(relative[i]->header.stamp);
    const icgm::Time t_ref = icgm::ros_bridge::FromRos(relative[i]->reference_stamp);
    const icgm::StampedPose* a = nullptr;
    const icgm::StampedPose* b = nullptr;
    for (const auto& p : offline.trajectory) {
      if (p.stamp == t_ref) a = &p;
      if (p.stamp == t) b = &p;
    }
    if (!a || !b || !relative[i]->success) continue;
    const icgm::Pose3 step = a->pose.inverse() * b->pose;
    const icgm::Pose3 live_step = icgm::ros_bridge::FromPoseMsg(relative[i]->relative_pose);
    if ((step.translation() - live_step.translation()).norm() > 1e-3) {
      ++differing;
      if (first_differing < 0) first_differing = static_cast<int>(i);
    }
  }
  std::printf("relative motions differing from offline by > 1 mm: %d of %zu (first: #%d)\n",
              differing, relative.size(), first_differing);
  const bool short_run = max_frames > 0;  // may be too straight to align
  const double ate_offline_all = Ate(stream.ground_truth(), offline.trajectory, short_run);
  const double ate_offline = Ate(stream.ground_truth(), offline_common, short_run);
  const double ate_live = Ate(stream.ground_truth(), live, short_run);
  const double cpu_live = manager_cpu_ms / std::max<size_t>(1, relative.size());
  char line[512];
  std::snprintf(line, sizeof(line),
                "rate %.1f: %d frames, %zu relative poses (%zu vision), %zu fused; ATE live "
                "%.4f m, offline %.4f m on the same frames (%.4f m on all %zu), difference "
                "%.4f m; CPU per frame: nodelet manager %.1f ms, offline front end %.1f ms "
                "(%.2fx), offline with reading the bag %.1f ms (%.2fx)\n",
                rate, frames, relative.size(), vision, odom.size(), ate_live, ate_offline,
                ate_offline_all, offline.trajectory.size(), std::abs(ate_live - ate_offline),
                cpu_live, offline.cpu_ms_per_frame, cpu_live / offline.cpu_ms_per_frame,
                offline.total_cpu_ms_per_frame, cpu_live / offline.total_cpu_ms_per_frame);
  const std::string fe = "/feature_extraction", reg = "/rgbd_registration";
  const long received = stages.Get(fe, "images"), extracted = stages.Get(fe, "extracted");
  const long paired = stages.Get(reg, "paired"), dropped = stages.Get(reg, "dropped");
  const long processed = stages.Get(reg, "processed");
  char stage_line[512];
  std::snprintf(
      stage_line, sizeof(stage_line),
      "rate %.1f frames: %d in -> feature extraction: %ld received (%ld lost on the "
      "way), %ld skipped while the registration was busy, %ld extracted -> "
      "registration: %ld paired with depth (%ld extracted, never paired), %ld refused, %ld "
      "dropped pending, %ld processed -> %zu relative poses (the first frame has none)\n",
      rate, frames, received, frames - received, stages.Get(fe, "skipped"), extracted, paired,
      extracted - paired, stages.Get(reg, "refused"), dropped, processed, relative.size());
  char paced_line[256] = "";
  if (paced_offline) {
    std::snprintf(paced_line, sizeof(paced_line),
                  "rate %.1f paced: offline front end fed at the replay's pace %.1f ms per frame; "
                  "nodelet manager %.2fx that\n",
                  rate, paced_cpu_ms, cpu_live / paced_cpu_ms);
  }
  std::printf("%s%s%s", line, paced_line, stage_line);
  if (!report_path.empty()) {
    std::ofstream(report_path, std::ios::app) << line << paced_line << stage_line;
  }
  RecordProperty("ate_live_m", std::to_string(ate_live));
  RecordProperty("ate_offline_m", std::to_string(ate_offline));
  if (!check) return;
  if (compare_map) {
    ros::WallDuration(1.0).sleep();  // the last keyframes waiting for their odometry
    const std::string folder = "/tmp/icgm_live_offline_" + std::to_string(getpid());
    std::system(("mkdir -p " + folder).c_str());
    if (flush_by_mode_switch) {
      // The flush service follows the keyframes connection (icgm_slam.launch remaps
      // `keyframes` to ~keyframes_topic for both nodelets), not the nodelets' namespace.
      EXPECT_TRUE(ros::service::exists(keyframes_topic + "/flush", true));
      EXPECT_FALSE(ros::service::exists("/flush_keyframe", false)) << "the namespace's name";
      for (const char* mode : {"localization", "mapping"}) {
        icgm_slam::SetMapMode set;
        set.request.mode = mode;
        ASSERT_TRUE(ros::service::call("/map_builder/set_mode", set));
        ASSERT_TRUE(set.response.success) << set.response.message;
      }
    }
    icgm_slam::SaveMap save;
    save.request.path = folder + "/live.db";
    ASSERT_TRUE(ros::service::call("/map_builder/save_map", save));
    ASSERT_TRUE(save.response.success) << save.response.message;
    const icgm::HybridMap offline_map =
        OfflineMap(offline_tool, bag_path, config_dir, odometry_config, camera_only, max_frames,
                   folder + "/offline.db");
    // The offline keyframes of the frames the pipeline processed.
    const ros::Time last_processed = relative.empty() ? ros::Time() : relative.back()->header.stamp;
    CompareMaps(offline_map, icgm::LoadMap(save.request.path),
                icgm::ros_bridge::FromRos(last_processed), max_keyframe_difference_m);
    if (flush_by_mode_switch) {
      const bool held =
          offline_map.size() > 0 && offline_map.keyframe(offline_map.size() - 1).stamp ==
                                        icgm::ros_bridge::FromRos(last_processed);
      std::printf("map: the last processed frame %s a keyframe (held until the mode switch)\n",
                  held ? "made" : "did not make");
      EXPECT_TRUE(held) << "the check needs a keyframe held at the end: choose ~max_frames so "
                           "that the last frame makes one";
    }
    std::system(("rm -rf " + folder).c_str());
  }
  EXPECT_EQ(frames, static_cast<int>(offline.trajectory.size()));
  EXPECT_EQ(relative.size(), expected) << "every frame after the first needs a relative pose";
  EXPECT_EQ(odom.size(), expected);
  EXPECT_GE(offline_common.size(), expected);
  EXPECT_LE(std::abs(ate_live - ate_offline), max_ate_difference_m);
}

}  // namespace
}  // namespace icgm_slam::test
