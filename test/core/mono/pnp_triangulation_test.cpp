// Triangulation and PnP on known points: exact views give the points and the pose back; the
// triangulation checks reject points behind a camera and rays that barely meet, and PnP in
// RANSAC ignores wrong correspondences.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/mono/pnp_pose.h"
#include "core/mono/triangulation.h"

namespace icgm {
namespace {

const Pose3 kCameraA = Pose3::Identity();
const Pose3 kCameraB = MakePose(Vec3(0.5, 0.0, 0.1),
                                Quat(Eigen::AngleAxisd(-0.08, Eigen::Vector3d::UnitY())));

Eigen::Vector2d Pixel(const CameraIntrinsics& k, const Pose3& world_camera,
                      const Eigen::Vector3d& p) {
  return k.Project(world_camera.inverse() * p);
}

TEST(TriangulationTest, RecoversKnownPoints) {
  const CameraIntrinsics k;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p(2.0 * u(rng), 1.5 * u(rng), 6.0 + 2.0 * u(rng));
    const TriangulatedPoint t =
        TriangulatePoint(k, kCameraA, Pixel(k, kCameraA, p), kCameraB, Pixel(k, kCameraB, p));
    ASSERT_TRUE(t.status.ok()) << t.status.reason();
    EXPECT_LT((t.point_world - p).norm(), 1e-6);
    EXPECT_GT(t.angle_deg, 1.0);
  }
}

TEST(TriangulationTest, RejectsPointsBehindAndSmallAngles) {
  const CameraIntrinsics k;
  // Pixels of a point in front of camera a but behind camera b (b looks the other way).
  const Pose3 turned = MakePose(Vec3(0.5, 0, 0), Quat(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())));
  const Eigen::Vector3d p(0.2, 0.1, 5.0);
  const Eigen::Vector3d behind = turned.inverse() * p;  // z < 0 in b
  ASSERT_LT(behind.z(), 0.0);
  const Eigen::Vector2d mirrored = k.Project(-behind);
  EXPECT_FALSE(TriangulatePoint(k, kCameraA, Pixel(k, kCameraA, p), turned, mirrored).status.ok());
  // 1 mm baseline at 5 m: the rays meet at ~0.01 deg.
  const Pose3 near = MakePose(Vec3(0.001, 0, 0), Quat::Identity());
  const TriangulatedPoint t =
      TriangulatePoint(k, kCameraA, Pixel(k, kCameraA, p), near, Pixel(k, near, p));
  EXPECT_FALSE(t.status.ok());
  EXPECT_LT(t.angle_deg, 0.1);
  // A pixel 5 px off in one view exceeds the 2 px reprojection bound.
  EXPECT_FALSE(TriangulatePoint(k, kCameraA, Pixel(k, kCameraA, p) + Eigen::Vector2d(0, 5.0),
                                kCameraB, Pixel(k, kCameraB, p))
                   .status.ok());
}

// The parallax a point would give at a given depth: equal to the measured angle of an exact
// triangulation at that depth, and unchanged when the other view's pixel is wrong (it is not
// used), so a gate on it does not select the points whose pixel noise enlarged their angle.
TEST(TriangulationTest, ExpectedParallaxIsTheAngleAtTheGivenDepth) {
  const CameraIntrinsics k;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.2, 0.1, 5.0), Eigen::Vector3d(-1.5, 0.8, 7.0),
        Eigen::Vector3d(0.0, 0.0, 3.0)}) {
    const Eigen::Vector2d pixel_b = Pixel(k, kCameraB, p);
    const double depth_b = (kCameraB.inverse() * p).z();
    const TriangulatedPoint t =
        TriangulatePoint(k, kCameraA, Pixel(k, kCameraA, p), kCameraB, pixel_b);
    ASSERT_TRUE(t.status.ok()) << t.status.reason();
    EXPECT_NEAR(ExpectedParallaxDeg(k, kCameraA, kCameraB, pixel_b, depth_b), t.angle_deg, 1e-9);
    // Twice as deep: about half the angle.
    EXPECT_NEAR(ExpectedParallaxDeg(k, kCameraA, kCameraB, pixel_b, 2.0 * depth_b),
                0.5 * t.angle_deg, 0.1 * t.angle_deg);
  }
  // Moving 0.1 m along the view: a point at the focus of expansion gives no parallax at any
  // depth; one 30 deg off the axis at 5 m depth (5 m / cos 30 deg along its ray) gives
  // atan2(0.1 sin 30 deg, 5 m / cos 30 deg + 0.1 cos 30 deg), 0.489 deg.
  const Pose3 ahead = MakePose(Vec3(0.0, 0.0, 0.1), Quat::Identity());
  const Eigen::Vector2d centre(k.cx_px, k.cy_px);
  EXPECT_LT(ExpectedParallaxDeg(k, kCameraA, ahead, centre, 5.0), 1e-6);
  const double off_axis = M_PI / 6.0;
  const Eigen::Vector3d off = ahead * Eigen::Vector3d(5.0 * std::tan(off_axis), 0.0, 5.0);
  const double expected_deg = std::atan2(0.1 * std::sin(off_axis),
                                         5.0 / std::cos(off_axis) + 0.1 * std::cos(off_axis)) *
                              180.0 / M_PI;
  EXPECT_NEAR(expected_deg, 0.489, 0.001);
  EXPECT_NEAR(ExpectedParallaxDeg(k, kCameraA, ahead, Pixel(k, ahead, off), 5.0), expected_deg,
              1e-6);
}

TEST(PnpTest, RecoversPoseDespiteOutliers) {
  const CameraIntrinsics k;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.5);
  const Pose3 truth = MakePose(Vec3(0.3, -0.1, 0.4),
                               Quat(Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.3, 1, 0).normalized())));
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<bool> wrong;
  while (points.size() < 200) {
    const Eigen::Vector3d p(3.0 * u(rng), 2.0 * u(rng), 6.0 + 2.0 * u(rng));
    const Eigen::Vector2d x = Pixel(k, truth, p);
    if (x.x() < 0 || x.y() < 0 || x.x() >= 640 || x.y() >= 480) continue;
    const bool bad = unit(rng) < 0.3;
    points.push_back(p);
    pixels.push_back(bad ? Eigen::Vector2d(640 * unit(rng), 480 * unit(rng))
                         : Eigen::Vector2d(x + Eigen::Vector2d(noise(rng), noise(rng))));
    wrong.push_back(bad);
  }
  PnpOptions options;
  for (const bool seeded : {false, true}) {
    const PnpResult r = EstimatePnpPose(
        points, pixels, k, options,
        seeded ? std::optional<Pose3>(MakePose(Vec3(0.25, -0.1, 0.35), Quat::Identity()))
               : std::nullopt);
    ASSERT_TRUE(r.status.ok()) << r.status.reason() << (seeded ? " (seeded)" : "");
    EXPECT_LT(TranslationNorm(Between(truth, r.world_camera)), 0.02);
    EXPECT_LT(RotationAngleRad(Between(truth, r.world_camera)) * 180.0 / M_PI, 0.2);
    size_t wrong_in = 0;
    for (size_t i = 0; i < wrong.size(); ++i) wrong_in += wrong[i] && r.inliers[i];
    EXPECT_LE(wrong_in, 3u);
    EXPECT_GT(r.num_inliers, 120u);
  }
}

TEST(PnpTest, TooFewCorrespondencesIsAnError) {
  const CameraIntrinsics k;
  const std::vector<Eigen::Vector3d> p(10, Eigen::Vector3d(0, 0, 5));
  const std::vector<Eigen::Vector2d> x(10, Eigen::Vector2d(320, 240));
  EXPECT_FALSE(EstimatePnpPose(p, x, k, PnpOptions()).status.ok());
}

}  // namespace
}  // namespace icgm
