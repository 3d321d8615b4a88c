#include "core/optimization/bundle_adjustment.h"

#include <gtest/gtest.h>

#include <random>

#include "../registration/synthetic_rgbd.h"

namespace icgm {
namespace {

CameraIntrinsics Camera() { return test::TumLikeCamera(); }

bool BuiltWithCeres() {
  BaProblem p;
  p.world_camera = {Pose3::Identity(), Pose3::Identity()};
  p.points_world = {Vec3(0, 0, 2)};
  p.observations = {{0, 0, Eigen::Vector2d(318.6, 255.3), 1.0, 2.0},
                    {1, 0, Eigen::Vector2d(318.6, 255.3), 1.0, 2.0}};
  return BundleAdjust(Camera(), BundleAdjustmentOptions(), &p).reason().find("without Ceres") ==
         std::string::npos;
}

// Cameras on an arc looking at a cloud of points 1.5-4 m away; pixel noise 1 px (x the pyramid
// sigma), depth noise of the Kinect model; `wrong` observations get a random pixel.
struct Scene {
  std::vector<Pose3> truth;
  std::vector<Vec3> points;
  BaProblem problem;
};

Scene MakeScene(int cameras, int points, double wrong_fraction, uint32_t seed) {
  Scene s;
  std::mt19937 rng(seed);
  std::mt19937 wrong_rng(seed + 1000);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0), z(1.5, 4.0), unit(0.0, 1.0);
  const CameraIntrinsics k = Camera();
  for (int i = 0; i < cameras; ++i) {
    const double a = 0.05 * i;
    s.truth.push_back(MakePose(Vec3(0.1 * i, 0.02 * std::sin(i), 0.03 * i),
                               Quat(Eigen::AngleAxisd(a, Vec3::UnitY()))));
  }
  for (int j = 0; j < points; ++j) {
    const double d = z(rng);
    s.points.push_back(Vec3(u(rng) * 0.6 * d, u(rng) * 0.45 * d, d));
  }
  BaProblem& p = s.problem;
  BundleAdjustmentOptions o;
  std::vector<bool> initialised(points, false);
  p.points_world.assign(points, Vec3::Zero());
  for (int i = 0; i < cameras; ++i) {
    // Initial poses: truth with 2 cm / 1 deg errors (camera 0 exact and fixed).
    Pose3 init = s.truth[i];
    if (i > 0) {
      Eigen::Matrix<double, 6, 1> e;
      e << 0.02 * n01(rng), 0.02 * n01(rng), 0.02 * n01(rng), 0.017 * n01(rng), 0.017 * n01(rng),
          0.017 * n01(rng);
      init = init * ExpSE3(e);
    }
    p.world_camera.push_back(init);
    p.fixed.push_back(i == 0);
    for (int j = 0; j < points; ++j) {
      const Vec3 pc = s.truth[i].inverse() * s.points[j];
      if (pc.z() < 0.3) continue;
      const Eigen::Vector2d px = k.Project(pc);
      if (px.x() < 0 || px.y() < 0 || px.x() > 640 || px.y() > 480) continue;
      BaObservation ob;
      ob.camera = i;
      ob.point = j;
      ob.pixel_sigma_px = (j % 3 == 0) ? 1.44 : 1.0;
      ob.pixel_px = px + ob.pixel_sigma_px * Eigen::Vector2d(n01(rng), n01(rng));
      const double sd = o.depth_sigma_m + o.depth_sigma_per_m2 * pc.z() * pc.z();
      ob.depth_m = pc.z() + sd * n01(rng);
      if ((i * 131 + j * 7) % 100 < 100 * wrong_fraction) {
        ob.pixel_px = Eigen::Vector2d(640 * unit(wrong_rng), 480 * unit(wrong_rng));
      }
      if (!initialised[j]) {
        // Point from this (noisy) observation and the initial pose, as a map would start it.
        p.points_world[j] = init * k.BackProject(ob.pixel_px.x(), ob.pixel_px.y(), ob.depth_m);
        initialised[j] = true;
      }
      p.observations.push_back(ob);
    }
  }
  return s;
}

double MeanPoseError(const std::vector<Pose3>& a, const std::vector<Pose3>& b) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += TranslationNorm(Between(a[i], b[i]));
  return sum / a.size();
}

TEST(BundleAdjustmentTest, RefinesPosesAndPointsTowardTruth) {
  if (!BuiltWithCeres()) GTEST_SKIP() << "built without Ceres";
  Scene s = MakeScene(8, 300, 0.0, 1);
  const double before = MeanPoseError(s.truth, s.problem.world_camera);
  BaSummary summary;
  const Status st = BundleAdjust(Camera(), BundleAdjustmentOptions(), &s.problem, &summary);
  ASSERT_TRUE(st.ok()) << st.reason();
  const double after = MeanPoseError(s.truth, s.problem.world_camera);
  EXPECT_GT(before, 0.01);
  EXPECT_LT(after, 0.003) << "before " << before;
  EXPECT_LT(summary.final_rms, summary.initial_rms);
  EXPECT_EQ(summary.fixed_cameras, 1);
  EXPECT_EQ(summary.cameras, 8);
  // The first camera was held.
  EXPECT_LT(TranslationNorm(Between(s.truth[0], s.problem.world_camera[0])), 1e-12);
  // Observed points: closer to the truth than their single-view initialisation.
  std::vector<bool> seen(s.points.size(), false);
  for (const BaObservation& o : s.problem.observations) seen[o.point] = true;
  const Scene initial = MakeScene(8, 300, 0.0, 1);
  double error_before = 0, error_after = 0;
  for (size_t j = 0; j < s.points.size(); ++j) {
    if (!seen[j]) continue;
    error_before += (s.points[j] - initial.problem.points_world[j]).norm();
    error_after += (s.points[j] - s.problem.points_world[j]).norm();
  }
  EXPECT_LT(error_after, 0.6 * error_before);
}

TEST(BundleAdjustmentTest, WrongObservationsAreFlaggedAsOutliers) {
  if (!BuiltWithCeres()) GTEST_SKIP() << "built without Ceres";
  Scene s = MakeScene(6, 300, 0.1, 2);
  const Scene clean = MakeScene(6, 300, 0.0, 2);  // same noise draws, no wrong pixels
  std::vector<uint8_t> inlier;
  BaSummary summary;
  ASSERT_TRUE(
      BundleAdjust(Camera(), BundleAdjustmentOptions(), &s.problem, &summary, &inlier).ok());
  int wrong = 0, wrong_flagged = 0, right_flagged = 0;
  for (size_t k = 0; k < inlier.size(); ++k) {
    const bool is_wrong =
        (s.problem.observations[k].pixel_px - clean.problem.observations[k].pixel_px).norm() > 1e-9;
    wrong += is_wrong;
    if (!inlier[k]) (is_wrong ? wrong_flagged : right_flagged)++;
  }
  ASSERT_GT(wrong, 50);
  EXPECT_GT(wrong_flagged, 0.9 * wrong);
  EXPECT_LT(right_flagged, 0.05 * (inlier.size() - wrong));
  EXPECT_LT(MeanPoseError(s.truth, s.problem.world_camera), 0.003);
}

TEST(BundleAdjustmentTest, PriorsHoldCamerasWithoutSharedPoints) {
  if (!BuiltWithCeres()) GTEST_SKIP() << "built without Ceres";
  Scene s = MakeScene(5, 200, 0.0, 3);
  // A sixth camera sees nothing; an exact relative-pose prior from camera 4 places it.
  const Pose3 extra_truth = s.truth[4] * MakePose(Vec3(0.2, 0, 0), Quat::Identity());
  s.problem.world_camera.push_back(MakePose(Vec3(5, 5, 5), Quat::Identity()));
  s.problem.fixed.push_back(0);
  BaRelativePose prior;
  prior.from = 4;
  prior.to = 5;
  prior.measured = Between(s.truth[4], extra_truth);
  prior.information = Mat6::Identity() * 1e4;
  s.problem.priors.push_back(prior);
  ASSERT_TRUE(BundleAdjust(Camera(), BundleAdjustmentOptions(), &s.problem).ok());
  EXPECT_LT(TranslationNorm(Between(extra_truth, s.problem.world_camera[5])), 0.01);
}

TEST(BundleAdjustmentTest, BadInputIsRefusedUnchanged) {
  Scene s = MakeScene(3, 50, 0.0, 4);
  const std::vector<Pose3> before = s.problem.world_camera;
  s.problem.observations.push_back({7, 0, Eigen::Vector2d(1, 1), 1.0, 1.0});
  const Status st = BundleAdjust(Camera(), BundleAdjustmentOptions(), &s.problem);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.reason().find("out of range"), std::string::npos) << st.reason();
  for (size_t i = 0; i < before.size(); ++i) {
    EXPECT_TRUE(before[i].isApprox(s.problem.world_camera[i]));
  }
  BaProblem lonely;  // one camera: nothing seen twice
  lonely.world_camera = {Pose3::Identity()};
  lonely.points_world = {Vec3(0, 0, 2)};
  lonely.observations = {{0, 0, Eigen::Vector2d(318.6, 255.3), 1.0, 2.0}};
  EXPECT_FALSE(BundleAdjust(Camera(), BundleAdjustmentOptions(), &lonely).ok());
}

}  // namespace
}  // namespace icgm
