// Rotation-only motion on synthetic points with a known motion: a camera that turns about its
// centre must give its rotation back despite outliers and pixel noise, with no parallax left;
// a camera that also moved leaves parallax that grows with the baseline over the depth.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/mono/rotation_only.h"

namespace icgm {
namespace {

struct TurnScene {
  std::vector<Eigen::Vector2d> pixels_a, pixels_b;
  std::vector<bool> outlier;
};

// Points 2-4 m in front of camera a seen again from b (T_a_b = a_b).
TurnScene MakeTurnScene(const CameraIntrinsics& k, const Pose3& a_b, double noise_px,
                        double outliers, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  TurnScene s;
  const Pose3 b_a = a_b.inverse();
  while (s.pixels_a.size() < 200) {
    const Eigen::Vector3d p(2.0 * u(rng), 1.5 * u(rng), 3.0 + u(rng));
    const Eigen::Vector3d pb = b_a * p;
    const Eigen::Vector2d xa = k.Project(p), xb = k.Project(pb);
    const auto inside = [&](const Eigen::Vector2d& x) {
      return x.x() >= 0 && x.y() >= 0 && x.x() < k.width_px && x.y() < k.height_px;
    };
    if (pb.z() <= 0.1 || !inside(xa) || !inside(xb)) continue;
    const bool bad = unit(rng) < outliers;
    s.pixels_a.push_back(xa + Eigen::Vector2d(noise(rng), noise(rng)));
    s.pixels_b.push_back(bad ? Eigen::Vector2d(k.width_px * unit(rng), k.height_px * unit(rng))
                             : Eigen::Vector2d(xb + Eigen::Vector2d(noise(rng), noise(rng))));
    s.outlier.push_back(bad);
  }
  return s;
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
