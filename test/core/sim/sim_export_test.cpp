// Exported simulator data: millimetre depth encoding, trajectories and sidecar file names.
#include "core/sim/sim_export.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>

namespace icgm::sim {
namespace {

TEST(SimExportTest, DepthToMillimetresRoundsAndMarksInvalidAsZero) {
  cv::Mat depth(1, 6, CV_32FC1);
  depth.at<float>(0, 0) = 1.2344f;
  depth.at<float>(0, 1) = 1.2346f;
  depth.at<float>(0, 2) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(0, 3) = 70.0f;  // beyond the uint16 range
  depth.at<float>(0, 4) = 0.0f;
  depth.at<float>(0, 5) = 65.535f;
  const cv::Mat mm = DepthToMillimetres(depth);
  ASSERT_EQ(mm.type(), CV_16UC1);
  EXPECT_EQ(mm.at<uint16_t>(0, 0), 1234);
  EXPECT_EQ(mm.at<uint16_t>(0, 1), 1235);
  EXPECT_EQ(mm.at<uint16_t>(0, 2), 0);
  EXPECT_EQ(mm.at<uint16_t>(0, 3), 0);
  EXPECT_EQ(mm.at<uint16_t>(0, 4), 0);
  EXPECT_EQ(mm.at<uint16_t>(0, 5), 65535);
}

TEST(SimExportTest, SidecarPathReplacesBagExtension) {
  EXPECT_EQ(SidecarPath("rosbags/crowded.bag", ".gt.txt"), "rosbags/crowded.gt.txt");
  EXPECT_EQ(SidecarPath("out/run", ".odom.txt"), "out/run.odom.txt");
  EXPECT_EQ(SidecarPath(".bag", ".gt.txt"), ".bag.gt.txt");
}

TEST(SimExportTest, TrajectoriesFollowTheSimulatorAndSurviveTumRoundTrip) {
  SimOptions o;
  o.num_frames = 25;
  o.room.num_tables = 4;
  const Simulator sim(o);
  const Trajectory gt = CameraGroundTruth(sim);
  const Trajectory odom = WheelOdometryTrajectory(sim);
  ASSERT_EQ(gt.size(), sim.size());
  ASSERT_EQ(odom.size(), sim.size());
  for (size_t i = 0; i < sim.size(); ++i) {
    EXPECT_EQ(gt[i].stamp, sim.stamp(i));
    EXPECT_TRUE(gt[i].pose.isApprox(sim.T_world_camera(i)));
    EXPECT_TRUE(odom[i].pose.isApprox(sim.odometry(i).T_odom_base));
  }
  const std::string path =
      (std::filesystem::temp_directory_path() / "icgm_sim_export_test.gt.txt").string();
  WriteTumTrajectory(path, gt);
  const Trajectory back = ReadTumTrajectory(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.size(), gt.size());
  EXPECT_LT((back.back().pose.translation() - gt.back().pose.translation()).norm(), 1e-5);
  EXPECT_NEAR(back.back().stamp.seconds(), gt.back().stamp.seconds(), 1e-6);
}

}  // namespace
}  // namespace icgm::sim
