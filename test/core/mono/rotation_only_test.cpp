// Rotation-only motion on synthetic points with a known motion: a camera that turns about its
// centre must give its rotation back despite outliers and pixel noise, with no parallax left;
// a camera that also moved leaves parallax that grows with the baseline over the depth.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/mono/rotation_only.h"
#include "synthetic_two_views.h"

namespace icgm {
namespace {

using TurnScene = test::TwoViewScene;

// Points 2-4 m in front of camera a seen again from b (T_a_b = a_b).
TurnScene MakeTurnScene(const CameraIntrinsics& k, const Pose3& a_b, double noise_px,
                        double outliers, uint32_t seed) {
  return test::MakeTwoViewScene(k, a_b, noise_px, outliers, seed, test::SceneBox{});
}

double TurnErrorDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

Pose3 Turn(double deg, const Vec3& t) {
  return MakePose(
      t, Quat(Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d(0.3, 1.0, 0.2).normalized())));
}

TEST(RotationOnlyTest, RecoversAPureRotationDespiteOutliers) {
  const CameraIntrinsics k;
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Pose3 a_b = Turn(8.0, Vec3::Zero());
    const TurnScene s = MakeTurnScene(k, a_b, 0.5, 0.3, seed);
    const RotationOnlyResult r = EstimateRotationOnly(s.pixels_a, s.pixels_b, k);
    ASSERT_TRUE(r.status.ok()) << r.status.reason();
    // b_R_a maps a's bearings into b: the inverse of a_b's rotation.
    EXPECT_LT(TurnErrorDeg(r.b_R_a, a_b.rotation().transpose()), 0.05);
    size_t wrong = 0;
    for (size_t i = 0; i < s.outlier.size(); ++i) wrong += r.inliers[i] == s.outlier[i];
    EXPECT_LT(wrong, 6u);
    // Only the pixel noise is left: well under a tenth of a degree.
    EXPECT_LT(r.median_parallax_deg, 0.1);
  }
}

TEST(RotationOnlyTest, ParallaxGrowsWithTheBaseline) {
  const CameraIntrinsics k;
  // Sideways baselines at 2-4 m: the true rotation leaves at most atan(b / 2 m) of parallax.
  // The fitted rotation absorbs part of a sideways motion (a turn and a shift look alike on
  // far points); what it cannot absorb comes from the spread of depths, and still grows with
  // the baseline, which is what tells a low-parallax view.
  double previous_truth = -1.0, previous_fit = -1.0;
  for (const double baseline_m : {0.0, 0.01, 0.03, 0.1}) {
    const Pose3 a_b = Turn(5.0, Vec3(baseline_m, 0.0, 0.0));
    const TurnScene s = MakeTurnScene(k, a_b, 0.0, 0.0, 4);
    const double truth = MedianParallaxDeg(a_b.rotation().transpose(), s.pixels_a, s.pixels_b, k);
    EXPECT_LT(truth, std::atan(baseline_m / 2.0) * 180.0 / M_PI + 1e-6);
    const RotationOnlyResult r = EstimateRotationOnly(s.pixels_a, s.pixels_b, k);
    ASSERT_TRUE(r.status.ok()) << r.status.reason();
    const double fit = MedianParallaxDeg(r.b_R_a, s.pixels_a, s.pixels_b, k);
    EXPECT_LE(fit, truth + 1e-6) << baseline_m;
    EXPECT_GT(truth, previous_truth) << baseline_m;
    EXPECT_GT(fit, previous_fit) << baseline_m;
    if (baseline_m == 0.0) {
      EXPECT_LT(fit, 1e-6);
    }
    if (baseline_m == 0.1) {
      EXPECT_GT(fit, 0.1);
    }
    std::printf("baseline %.2f m: parallax with the true rotation %.3f deg, fitted %.3f deg\n",
                baseline_m, truth, fit);
    previous_truth = truth;
    previous_fit = fit;
  }
}

TEST(RotationOnlyTest, TooFewMatchesIsAnErrorWithAReason) {
  const CameraIntrinsics k;
  const TurnScene s = MakeTurnScene(k, Turn(3.0, Vec3::Zero()), 0.0, 0.0, 5);
  const std::vector<Eigen::Vector2d> a(s.pixels_a.begin(), s.pixels_a.begin() + 10);
  const std::vector<Eigen::Vector2d> b(s.pixels_b.begin(), s.pixels_b.begin() + 10);
  const RotationOnlyResult r = EstimateRotationOnly(a, b, k);
  EXPECT_FALSE(r.status.ok());
  EXPECT_NE(r.status.reason().find("matches"), std::string::npos);
}

}  // namespace
}  // namespace icgm
