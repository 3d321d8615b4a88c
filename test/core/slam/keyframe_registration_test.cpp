#include "core/slam/keyframe_registration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

namespace icgm {
namespace {

CameraIntrinsics Camera() { return CameraIntrinsics(); }

struct Scene {
  std::vector<Vec3> points_world;
  cv::Mat descriptors;  // one 32-byte ORB-like descriptor per world point
};

Scene MakeScene(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-2.0, 2.0), y(-1.5, 1.5), z(2.0, 4.5);
  std::uniform_int_distribution<int> byte(0, 255);
  Scene s;
  s.descriptors.create(n, 32, CV_8U);
  for (int i = 0; i < n; ++i) {
    s.points_world.emplace_back(x(rng), y(rng), z(rng));
    for (int b = 0; b < 32; ++b) s.descriptors.at<uint8_t>(i, b) = static_cast<uint8_t>(byte(rng));
  }
  return s;
}

// The keyframe of a camera at T_world_camera seeing the scene: projected keypoints (with pixel
// noise), camera-frame points (with depth noise), descriptors with `flipped_bits` random bits
// flipped. Points outside the image are not seen.
Keyframe Observe(const Scene& s, const Pose3& world_camera, int flipped_bits, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> pixel_noise(0.0, 0.3), depth_noise(0.0, 0.003);
  std::uniform_int_distribution<int> bit(0, 255);
  const CameraIntrinsics cam = Camera();
  Keyframe kf;
  std::vector<int> seen;
  for (size_t i = 0; i < s.points_world.size(); ++i) {
    const Vec3 p = world_camera.inverse() * s.points_world[i];
    if (p.z() < 0.5) continue;
    const Eigen::Vector2d uv = cam.Project(p);
    if (uv.x() < 0 || uv.y() < 0 || uv.x() >= cam.width_px || uv.y() >= cam.height_px) continue;
    kf.keypoints.emplace_back(cv::Point2f(static_cast<float>(uv.x() + pixel_noise(rng)),
                                          static_cast<float>(uv.y() + pixel_noise(rng))),
                              7.f);
    kf.points_m.push_back(p * (1.0 + depth_noise(rng)));
    seen.push_back(static_cast<int>(i));
  }
  kf.descriptors.create(static_cast<int>(seen.size()), 32, CV_8U);
  for (size_t k = 0; k < seen.size(); ++k) {
    s.descriptors.row(seen[k]).copyTo(kf.descriptors.row(static_cast<int>(k)));
    for (int f = 0; f < flipped_bits; ++f) {
      const int b = bit(rng);
      kf.descriptors.at<uint8_t>(static_cast<int>(k), b / 8) ^= static_cast<uint8_t>(1 << (b % 8));
    }
  }
  return kf;
}

TEST(KeyframeRegistrationTest, RecoversKnownTransformBetweenTwoViews) {
  const Scene scene = MakeScene(600, 1);
  const Pose3 world_candidate = Pose3::Identity();
  const Pose3 world_query =
      MakePose(Vec3(0.15, -0.05, 0.1),
               Quat(Eigen::AngleAxisd(6.0 * M_PI / 180.0, Vec3(0.2, 1.0, 0.1).normalized())));
  const Keyframe candidate = Observe(scene, world_candidate, 8, 2);
  const Keyframe query = Observe(scene, world_query, 8, 3);
  const KeyframeRegistration registration(LoopRegistrationOptions(), Camera());
  const RegistrationOutcome out = registration.Register(query, candidate);
  ASSERT_TRUE(out.status.ok()) << out.status.reason();
  const Pose3 beta_true = Between(world_candidate, world_query);
  const Pose3 error = Between(beta_true, out.relative_pose);
  EXPECT_LT(TranslationNorm(error), 0.01);
  EXPECT_LT(RotationAngleRad(error), 0.3 * M_PI / 180.0);
  EXPECT_GT(out.inliers, 200);
  // The information is a usable eq. 6.2 weight: symmetric positive definite.
  EXPECT_TRUE(out.information.isApprox(out.information.transpose(), 1e-6));
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6>(out.information).eigenvalues().minCoeff(), 0.0);
}

TEST(KeyframeRegistrationTest, ToleratesWrongMatchesWithAndWithoutIcgm) {
  const Scene scene = MakeScene(600, 4);
  const Pose3 world_query = MakePose(Vec3(-0.1, 0.05, 0.05), Quat::Identity());
  const Keyframe candidate = Observe(scene, Pose3::Identity(), 8, 5);
  Keyframe query = Observe(scene, world_query, 8, 6);
  // A quarter of the query's 3-D points belong to a moved object: right descriptors, wrong
  // geometry, like a pedestrian that walked between the two visits.
  for (size_t i = 0; i < query.points_m.size(); i += 4) query.points_m[i] += Vec3(0.4, 0, 0.3);
  for (bool use_icgm : {true, false}) {
    LoopRegistrationOptions options;
    options.use_icgm = use_icgm;
    const RegistrationOutcome out =
        KeyframeRegistration(options, Camera()).Register(query, candidate);
    ASSERT_TRUE(out.status.ok()) << out.status.reason();
    const Pose3 error = Between(world_query, out.relative_pose);
    EXPECT_LT(TranslationNorm(error), 0.01) << "use_icgm " << use_icgm;
    EXPECT_LT(RotationAngleRad(error), 0.3 * M_PI / 180.0) << "use_icgm " << use_icgm;
  }
}

TEST(KeyframeRegistrationTest, RejectsUnrelatedKeyframes) {
  const Keyframe a = Observe(MakeScene(600, 7), Pose3::Identity(), 8, 8);
  const Keyframe b = Observe(MakeScene(600, 9), Pose3::Identity(), 8, 10);
  const KeyframeRegistration registration(LoopRegistrationOptions(), Camera());
  const RegistrationOutcome out = registration.Register(a, b);
  EXPECT_FALSE(out.status.ok());
  EXPECT_FALSE(out.status.reason().empty());
  // And through the RegisterFn the loop-closure detector calls.
  EXPECT_FALSE(registration.AsRegisterFn()(a, b).status.ok());
}

TEST(KeyframeRegistrationTest, RejectsInconsistentOrEmptyKeyframes) {
  const Keyframe a = Observe(MakeScene(300, 11), Pose3::Identity(), 8, 12);
  Keyframe broken = a;
  broken.points_m.pop_back();
  const KeyframeRegistration registration(LoopRegistrationOptions(), Camera());
  EXPECT_FALSE(registration.Register(broken, a).status.ok());
  EXPECT_FALSE(registration.Register(Keyframe(), a).status.ok());
  Keyframe floats = a;
  a.descriptors.convertTo(floats.descriptors, CV_32F);
  EXPECT_FALSE(registration.Register(floats, a).status.ok());
}

}  // namespace
}  // namespace icgm
