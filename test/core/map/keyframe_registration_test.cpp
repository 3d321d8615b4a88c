#include "core/map/keyframe_registration.h"

#include <gtest/gtest.h>

#include <random>

#include "core/common/camera.h"
#include "core/common/option_reader.h"
#include "core/map/map_options.h"
#include "test_poses.h"

namespace icgm {
namespace {

const CameraIntrinsics kCamera;

// A scene of random points 2-4 m ahead seen by the candidate camera, and the query camera at
// `beta` (query in candidate frame). `movers` query features keep their descriptor but their
// 3D point moved 0.5 m (a person walked away), which registration must not follow.
struct Scene {
  Keyframe candidate;
  Keyframe query;
};

Scene MakeScene(const Pose3& beta, int points, int movers, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-1.5, 1.5);
  std::uniform_real_distribution<double> uz(2.0, 4.0);
  std::uniform_int_distribution<int> byte(0, 255);
  Scene s;
  for (int i = 0; i < points; ++i) {
    const Eigen::Vector3d p(ux(rng), ux(rng) * 0.8, uz(rng));
    cv::Mat d(1, 32, CV_8U);
    for (int c = 0; c < 32; ++c) d.at<uint8_t>(0, c) = static_cast<uint8_t>(byte(rng));
    const Eigen::Vector2d uv = kCamera.Project(p);
    s.candidate.keypoints.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 7.f);
    s.candidate.points_m.push_back(p);
    s.candidate.descriptors.push_back(d);
    Eigen::Vector3d q = beta.inverse() * p;
    if (i < movers) q += Eigen::Vector3d(0.5, 0.0, 0.2);
    if (q.z() < 0.5) continue;
    const Eigen::Vector2d uvq = kCamera.Project(q);
    s.query.keypoints.emplace_back(static_cast<float>(uvq.x()), static_cast<float>(uvq.y()), 7.f);
    s.query.points_m.push_back(q);
    s.query.descriptors.push_back(d);
  }
  return s;
}

KeyframeRegistrationOptions Options() {
  KeyframeRegistrationOptions o;
  o.ransac.min_inliers = 20;
  return o;
}

TEST(KeyframeRegistrationTest, RecoversTheRelativePoseDespiteMovers) {
  const Pose3 beta = MakePose(Vec3(0.25, -0.05, 0.15),
                              Quat(Eigen::AngleAxisd(0.12, Vec3(0.1, 1, 0).normalized())));
  const Scene s = MakeScene(beta, 200, 40, 3);
  const RegistrationOutcome out = RegisterKeyframes(s.query, s.candidate, Options());
  ASSERT_TRUE(out.status.ok()) << out.status.reason();
  EXPECT_LT(test::PoseDistance(out.relative_pose, beta), 1e-6);
  EXPECT_GE(out.inliers, 100);
  EXPECT_LE(out.inliers, 160);  // the 40 moved points are not inliers
  EXPECT_GT(out.information(0, 0), 0.0);
  EXPECT_GT(out.information(5, 5), 0.0);
  // The RegisterFn binding gives the same answer.
  const RegistrationOutcome bound = MakeKeyframeRegisterFn(Options())(s.query, s.candidate);
  EXPECT_LT(test::PoseDistance(bound.relative_pose, out.relative_pose), 1e-12);
}

TEST(KeyframeRegistrationTest, UnrelatedOrEmptyModelsAreRejectedWithReason) {
  const Scene a = MakeScene(Pose3::Identity(), 150, 0, 1);
  const Scene b = MakeScene(Pose3::Identity(), 150, 0, 2);
  RegistrationOutcome out = RegisterKeyframes(a.query, b.candidate, Options());
  EXPECT_FALSE(out.status.ok());
  EXPECT_NE(out.status.reason().find("rejected"), std::string::npos);
  out = RegisterKeyframes(Keyframe{}, b.candidate, Options());
  EXPECT_FALSE(out.status.ok());
  // Too far to be a plausible loop.
  KeyframeRegistrationOptions strict = Options();
  strict.max_translation_m = 0.1;
  const Scene far = MakeScene(MakePose(Vec3(0.3, 0, 0), Quat::Identity()), 150, 0, 4);
  out = RegisterKeyframes(far.query, far.candidate, strict);
  EXPECT_FALSE(out.status.ok());
  EXPECT_NE(out.status.reason().find("implausible"), std::string::npos);
}

TEST(KeyframeRegistrationTest, ShippedConfigsLoad) {
  const OptionReader icgm_root =
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/icgm.yaml");
  const OptionReader map_root =
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/map.yaml");
  KeyframeRegistrationOptions options;
  options.ransac.max_iterations = 1;
  std::vector<std::string> unused{"placeholder"};
  ReadOptions(icgm_root, map_root, &options, &unused);
  EXPECT_EQ(options.ransac.max_iterations, 500);
  EXPECT_TRUE(unused.empty());
}

}  // namespace
}  // namespace icgm
