#include "core/odometry/keyframe_bundle_adjustment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

namespace icgm {
namespace {

CameraIntrinsics KbaCamera() {
  CameraIntrinsics k;
  k.fx_px = 540.0;
  k.fy_px = 540.0;
  k.cx_px = 320.0;
  k.cy_px = 240.0;
  k.width_px = 640;
  k.height_px = 480;
  return k;
}

double DegreesBetween(const Pose3& a, const Pose3& b) {
  return RotationAngleRad(Between(a, b)) * 180.0 / M_PI;
}

// A plain room seen by three keyframes with known poses while the hand pans and slides: points
// on walls 3-4.5 m away (the far plain walls where a pan and a sideways slide look alike) and a
// few on desks 1.8-2.5 m away, each with a random 32-byte descriptor; pixel noise 0.3 px, depth
// noise of a structured-light sensor. Optionally walkers: points 1.2-1.8 m away that move 6 cm
// sideways between keyframes, keeping their descriptor.
struct KbaScene {
  CameraIntrinsics camera = KbaCamera();
  std::vector<Pose3> truth;
  std::vector<KeyframeBaView> views;
  std::vector<std::vector<int>> point_of_keypoint;  // per view; walkers >= num_static

  KbaScene(int num_static, int num_walkers, unsigned seed = 5) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), far(3.0, 4.5), desk(1.8, 2.5),
        walker(1.2, 1.8);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (int k = 0; k < 3; ++k) {
      Pose3 t = Pose3::Identity();
      t.translate(Vec3(0.02 * k, 0.004 * k, 0.015 * k));
      t.rotate(Eigen::AngleAxisd(0.6 * k * M_PI / 180.0, Vec3::UnitY()) *
               Eigen::AngleAxisd(0.2 * k * M_PI / 180.0, Vec3::UnitX()));
      truth.push_back(t);
    }
    const int n = num_static + num_walkers;
    cv::Mat descriptors(n, 32, CV_8U);
    cv::randu(descriptors, 0, 256);
    std::vector<Vec3> points;
    for (int i = 0; i < n; ++i) {
      const double z = i >= num_static ? walker(rng) : (i % 5 == 0 ? desk(rng) : far(rng));
      points.emplace_back(u(rng) * 0.5 * z, u(rng) * 0.4 * z, z);
    }
    views.resize(3);
    point_of_keypoint.resize(3);
    for (int k = 0; k < 3; ++k) {
      KeyframeBaView& v = views[k];
      v.odom_camera = truth[k];
      std::vector<int> rows;
      for (int i = 0; i < n; ++i) {
        Vec3 p = points[i];
        if (i >= num_static) p.x() += 0.06 * k;  // walkers move between keyframes
        const Vec3 pc = truth[k].inverse() * p;
        const Eigen::Vector2d px = camera.Project(pc);
        if (px.x() < 0 || px.y() < 0 || px.x() >= camera.width_px || px.y() >= camera.height_px) {
          continue;
        }
        v.pixels_px.emplace_back(static_cast<float>(px.x() + 0.3 * noise(rng)),
                                 static_cast<float>(px.y() + 0.3 * noise(rng)));
        v.pixel_sigma_px.push_back(1.0);
        const double sigma_z = 0.001 + 0.0015 * pc.z() * pc.z();
        const double z = pc.z() + sigma_z * noise(rng);
        v.points_camera.push_back(
            camera.BackProject(v.pixels_px.back().x, v.pixels_px.back().y, z));
        rows.push_back(i);
        point_of_keypoint[k].push_back(i);
      }
      v.descriptors.create(static_cast<int>(rows.size()), 32, CV_8U);
      for (size_t r = 0; r < rows.size(); ++r) {
        descriptors.row(rows[r]).copyTo(v.descriptors.row(static_cast<int>(r)));
        v.descriptors.at<uint8_t>(static_cast<int>(r), (k * 7 + static_cast<int>(r)) % 32) ^= 0x3;
      }
    }
  }

  // Moves keyframe k's estimate by a pan of `deg` about the vertical axis and the sideways
  // slide that keeps points at `depth_m` where they were: the two errors a single registration
  // against far walls cannot tell apart.
  void PanAndSlide(int k, double deg, double depth_m) {
    const double a = deg * M_PI / 180.0;
    Pose3 e = Pose3::Identity();
    e.translate(Vec3(std::tan(a) * depth_m, 0.0, 0.0));
    e.rotate(Eigen::AngleAxisd(a, Vec3::UnitY()));
    views[k].odom_camera = truth[k] * e;
  }
};

KeyframeBaOptions KbaOptions() {
  KeyframeBaOptions o;
  o.keyframes = 3;
  o.fixed_keyframes = 1;
  o.match_px = 12.0;
  o.iterations = 50;
  o.depth_sigma_m = 0.001;
  o.depth_sigma_per_m2 = 0.0015;
  return o;
}

TEST(KeyframeBundleAdjustmentTest, PanAgainstSlideErrorOfTwoKeyframesIsUndone) {
  KbaScene scene(400, 0);
  // The pan/slide pair leaves points at 3.7 m within a pixel of where they were.
  scene.PanAndSlide(1, 0.5, 3.7);
  scene.PanAndSlide(2, -0.6, 3.7);
  for (int k = 1; k < 3; ++k) {
    ASSERT_GT(TranslationNorm(Between(scene.truth[k], scene.views[k].odom_camera)), 0.03);
    ASSERT_GT(DegreesBetween(scene.truth[k], scene.views[k].odom_camera), 0.45);
  }
  const KeyframeBaResult r = AdjustKeyframes(scene.views, scene.camera, KbaOptions());
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  EXPECT_GT(r.points, 300u);
  EXPECT_LT(r.final_rms, r.initial_rms);
  // The fixed keyframe stays; the others come back from 30-40 mm / 0.5-0.6 deg to within
  // 6 mm / 0.08 deg (what is left lies along the same pan/slide direction: the noise of the
  // depth and of the parallax between desks and walls).
  EXPECT_LT(TranslationNorm(Between(scene.truth[0], r.odom_camera[0])), 1e-9);
  for (int k = 1; k < 3; ++k) {
    EXPECT_LT(TranslationNorm(Between(scene.truth[k], r.odom_camera[k])), 0.006) << k;
    EXPECT_LT(DegreesBetween(scene.truth[k], r.odom_camera[k]), 0.08) << k;
  }
}

TEST(KeyframeBundleAdjustmentTest, TracksJoinOnlyViewsOfOneStaticPoint) {
  KbaScene scene(300, 0);
  scene.PanAndSlide(2, 0.4, 3.7);
  size_t tracks = 0;
  const auto track = AssociateKeyframes(scene.views, scene.camera, KbaOptions(), &tracks);
  ASSERT_EQ(track.size(), 3u);
  // Every track holds views of one true point, and most points are tracked.
  std::vector<int> point_of_track(tracks, -1);
  size_t wrong = 0;
  for (int k = 0; k < 3; ++k) {
    for (size_t i = 0; i < track[k].size(); ++i) {
      const int t = track[k][i];
      if (t < 0) continue;
      int& p = point_of_track[static_cast<size_t>(t)];
      if (p < 0) p = scene.point_of_keypoint[k][i];
      wrong += p != scene.point_of_keypoint[k][i];
    }
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(tracks, 250u);
}

TEST(KeyframeBundleAdjustmentTest, WalkersMovingBetweenKeyframesDoNotPullThePoses) {
  // A third of the points on walkers that move 6 cm between keyframes; the depth and
  // projection gates keep most of them out of the tracks and the robust loss the rest
  // (from 30-40 mm / 0.5-0.6 deg to within 10 mm / 0.15 deg).
  KbaScene scene(300, 150);
  scene.PanAndSlide(1, 0.5, 3.7);
  scene.PanAndSlide(2, -0.6, 3.7);
  const KeyframeBaResult r = AdjustKeyframes(scene.views, scene.camera, KbaOptions());
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  for (int k = 1; k < 3; ++k) {
    EXPECT_LT(TranslationNorm(Between(scene.truth[k], r.odom_camera[k])), 0.010) << k;
    EXPECT_LT(DegreesBetween(scene.truth[k], r.odom_camera[k]), 0.15) << k;
  }
}

TEST(KeyframeBundleAdjustmentTest, FailuresLeaveThePosesWithAReason) {
  // Too few points seen twice.
  KbaScene sparse(20, 0);
  sparse.PanAndSlide(2, 0.5, 3.7);
  KeyframeBaResult r = AdjustKeyframes(sparse.views, sparse.camera, KbaOptions());
  EXPECT_FALSE(r.status.ok());
  EXPECT_NE(r.status.reason().find("points"), std::string::npos) << r.status.reason();
  EXPECT_TRUE(r.odom_camera[2].isApprox(sparse.views[2].odom_camera));
  // A correction beyond the bound is rejected.
  KbaScene scene(400, 0);
  scene.PanAndSlide(2, 0.5, 3.7);
  KeyframeBaOptions tight = KbaOptions();
  tight.max_correction_m = 0.005;
  r = AdjustKeyframes(scene.views, scene.camera, tight);
  EXPECT_FALSE(r.status.ok());
  EXPECT_NE(r.status.reason().find("bound"), std::string::npos) << r.status.reason();
  EXPECT_TRUE(r.odom_camera[2].isApprox(scene.views[2].odom_camera));
  // Every keyframe fixed: nothing to adjust.
  KeyframeBaOptions all_fixed = KbaOptions();
  all_fixed.fixed_keyframes = 3;
  EXPECT_FALSE(AdjustKeyframes(scene.views, scene.camera, all_fixed).status.ok());
}

}  // namespace
}  // namespace icgm
