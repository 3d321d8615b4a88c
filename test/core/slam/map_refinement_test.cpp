#include "core/slam/map_refinement.h"

#include <gtest/gtest.h>

#include <random>

#include "../registration/synthetic_rgbd.h"

namespace icgm {
namespace {

CameraIntrinsics Camera() { return test::TumLikeCamera(); }

// A map of keyframes on a line past a wall of textured points (every point has one random
// ORB-like descriptor, the same in every view), keypoints with 0.5 px noise, depths with the
// Kinect-like noise, and a chain of relative poses with a steady drift.
struct DriftingMap {
  HybridMap map;
  std::vector<Pose3> truth;
};

DriftingMap MakeMap(int keyframes, uint32_t seed) {
  DriftingMap m;
  const CameraIntrinsics k = Camera();
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<Vec3> points;
  cv::Mat descriptors(1500, 32, CV_8U);
  for (int j = 0; j < 1500; ++j) {
    points.emplace_back(u(rng) * 3.0 + 1.0, u(rng) * 1.2, 2.5 + 0.5 * u(rng));
    for (int b = 0; b < 32; ++b) descriptors.at<uint8_t>(j, b) = static_cast<uint8_t>(byte(rng));
  }
  Pose3 drifted = Pose3::Identity();
  for (int i = 0; i < keyframes; ++i) {
    const Pose3 truth = MakePose(Vec3(0.12 * i, 0.01 * std::sin(i), 0.0),
                                 Quat(Eigen::AngleAxisd(0.01 * i, Vec3::UnitY())));
    Keyframe kf;
    kf.stamp = Time::FromNanoseconds(1'000'000'000LL * (i + 1));
    for (int j = 0; j < 1500; ++j) {
      const Vec3 pc = truth.inverse() * points[j];
      const Eigen::Vector2d px = k.Project(pc);
      if (pc.z() < 0.5 || px.x() < 5 || px.y() < 5 || px.x() > 635 || px.y() > 475) continue;
      cv::KeyPoint kp(static_cast<float>(px.x() + 0.5 * n01(rng)),
                      static_cast<float>(px.y() + 0.5 * n01(rng)), 31.f);
      kf.keypoints.push_back(kp);
      kf.descriptors.push_back(descriptors.row(j));
      const double z = pc.z() + (0.002 + 0.003 * pc.z() * pc.z()) * n01(rng);
      kf.points_m.push_back(k.BackProject(kp.pt.x, kp.pt.y, z));
    }
    // Odometry with a steady 1 cm + 0.3 deg drift per step.
    if (i > 0) {
      const Pose3 step = Between(m.truth.back(), truth) *
                         MakePose(Vec3(0.01, 0.004, -0.006),
                                  Quat(Eigen::AngleAxisd(0.005, Vec3(0.2, 1.0, 0.1).normalized())));
      drifted = drifted * step;
      kf.relative_pose = step;
    }
    int id = -1;
    EXPECT_TRUE(m.map.AddKeyframe(kf, Mat6::Identity() * 1e4, &id).ok());
    m.truth.push_back(truth);
  }
  return m;
}

double MeanError(const std::vector<Pose3>& truth, const std::vector<Pose3>& poses) {
  double sum = 0;
  for (size_t i = 0; i < truth.size(); ++i) sum += TranslationNorm(Between(truth[i], poses[i]));
  return sum / truth.size();
}

TEST(MapRefinementTest, BundleAdjustmentRemovesOdometryDrift) {
  DriftingMap m = MakeMap(12, 1);
  std::vector<Pose3> before;
  for (const Keyframe& kf : m.map.keyframes()) before.push_back(kf.global_pose);
  const KeyframeRegistration registration(LoopRegistrationOptions(), Camera());
  MapRefinementOptions options;
  std::vector<Pose3> after;
  MapRefinementSummary summary;
  const Status st = RefineMapPoses(m.map, registration, Camera(), options, &after, &summary);
  if (!st.ok() && st.reason().find("without Ceres") != std::string::npos) {
    GTEST_SKIP() << st.reason();
  }
  ASSERT_TRUE(st.ok()) << st.reason();
  ASSERT_EQ(after.size(), before.size());
  // Neighbours beyond the odometry links were registered and joined into tracks.
  EXPECT_GT(summary.pairs_used, 11);
  EXPECT_GT(summary.tracks, 300);
  const double error_before = MeanError(m.truth, before);
  const double error_after = MeanError(m.truth, after);
  EXPECT_GT(error_before, 0.05);
  EXPECT_LT(error_after, 0.1 * error_before) << error_after << " vs " << error_before;
  EXPECT_TRUE(after[0].isApprox(before[0]));  // keyframe 0 is the gauge
}

TEST(MapRefinementTest, TooSmallMapIsRefused) {
  DriftingMap m = MakeMap(1, 2);
  std::vector<Pose3> poses;
  const KeyframeRegistration registration(LoopRegistrationOptions(), Camera());
  EXPECT_FALSE(RefineMapPoses(m.map, registration, Camera(), MapRefinementOptions(), &poses).ok());
  EXPECT_EQ(poses.size(), 1u);
}

}  // namespace
}  // namespace icgm
