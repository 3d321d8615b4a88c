#include "core/registration/rgbd_registration.h"

#include <gtest/gtest.h>

#include <random>

#include "core/common/option_reader.h"
#include "synthetic_rgbd.h"

namespace icgm {
namespace {

struct Scene {
  CameraIntrinsics k = test::TumLikeCamera();
  Pose3 truth;  // current camera in the reference frame
  cv::Mat depth_ref, depth_cur;
  std::vector<cv::Point2f> pts_ref, pts_cur;
};

// Keypoints on a grid of the reference view, transferred to the current view through the
// rendered geometry; `outliers` of them get a random (wrong) current position.
Scene MakeScene(const Pose3& motion, int outliers, uint32_t seed) {
  Scene s;
  s.truth = motion;
  s.depth_ref = test::RenderRoomDepth(Pose3::Identity(), s.k);
  s.depth_cur = test::RenderRoomDepth(motion, s.k);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(20.f, 620.f), v(20.f, 460.f);
  const Pose3 cur_from_ref = motion.inverse();
  for (int y = 30; y < 460; y += 40) {
    for (int x = 30; x < 620; x += 40) {
      const Eigen::Vector3d p_ref = s.k.BackProject(x, y, s.depth_ref.at<float>(y, x));
      const Eigen::Vector2d uv = s.k.Project(cur_from_ref * p_ref);
      if (uv.x() < 5 || uv.y() < 5 || uv.x() > 634 || uv.y() > 474) continue;
      s.pts_ref.emplace_back(static_cast<float>(x), static_cast<float>(y));
      s.pts_cur.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
  }
  for (int i = 0; i < outliers && i < static_cast<int>(s.pts_cur.size()); ++i) {
    s.pts_cur[i * 3 % s.pts_cur.size()] = cv::Point2f(u(rng), v(rng));
  }
  return s;
}

Pose3 TestMotion() {
  return MakePose(Vec3(0.08, -0.04, 0.06),
                  Quat(Eigen::AngleAxisd(5.0 * M_PI / 180.0, Vec3(0.3, 1.0, 0.1).normalized())));
}

TEST(RgbdRegistrationTest, RecoversKnownMotionFromRenderedDepth) {
  const Scene s = MakeScene(TestMotion(), 30, 1);
  ASSERT_GT(s.pts_ref.size(), 100u);
  const RegistrationResult r =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, s.depth_cur, s.k, RegistrationOptions());
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  const Pose3 err = Between(s.truth, r.relative_pose);
  EXPECT_LT(TranslationNorm(err), 0.002);
  EXPECT_LT(RotationAngleRad(err) * 180.0 / M_PI, 0.1);
  EXPECT_EQ(r.matches_2d, s.pts_ref.size());
  EXPECT_LE(r.inliers, r.matches_3d);
  EXPECT_GE(r.inliers, r.matches_3d - 32);  // the 30 wrong matches are the outliers
  EXPECT_NEAR(r.inlier_ratio, static_cast<double>(r.inliers) / r.matches_3d, 1e-12);
  EXPECT_LT(r.rmse_m, 0.01);
  EXPECT_EQ(r.inlier_indices.size(), r.inliers);
  // The covariance is symmetric positive definite and small for this well-constrained scene.
  EXPECT_TRUE(r.covariance.isApprox(r.covariance.transpose()));
  EXPECT_GT(r.covariance.diagonal().minCoeff(), 0.0);
  EXPECT_LT(r.covariance.diagonal().maxCoeff(), 1e-4);
}

TEST(RgbdRegistrationTest, WithoutReprojectionRefinementStillAccurate) {
  const Scene s = MakeScene(TestMotion(), 0, 2);
  RegistrationOptions opt;
  opt.refine_reprojection = false;
  const RegistrationResult r =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, s.depth_cur, s.k, opt);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  const Pose3 err = Between(s.truth, r.relative_pose);
  EXPECT_LT(TranslationNorm(err), 0.005);
  EXPECT_LT(RotationAngleRad(err) * 180.0 / M_PI, 0.2);
}

TEST(RgbdRegistrationTest, PixelSigmaDownweightsCoarseKeypoints) {
  // Half the keypoints are localised like a coarse pyramid level (4 px noise), half exactly;
  // telling the refinement which is which must give a more accurate pose than treating all
  // alike.
  Scene s = MakeScene(TestMotion(), 0, 5);
  std::mt19937 rng(11);
  std::normal_distribution<float> coarse(0.f, 4.f);
  std::vector<double> sigma(s.pts_cur.size(), 1.0);
  for (size_t i = 0; i < s.pts_cur.size(); i += 2) {
    s.pts_cur[i] += cv::Point2f(coarse(rng), coarse(rng));
    sigma[i] = 4.0;
  }
  RegistrationOptions opt;
  opt.inlier_threshold_m = 0.1;  // keep the noisy matches in the inlier set
  const RegistrationResult plain =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, s.depth_cur, s.k, opt);
  const RegistrationResult weighted =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, s.depth_cur, s.k, opt, &sigma);
  ASSERT_TRUE(plain.status.ok()) << plain.status.reason();
  ASSERT_TRUE(weighted.status.ok()) << weighted.status.reason();
  const double err_plain = TranslationNorm(Between(s.truth, plain.relative_pose));
  const double err_weighted = TranslationNorm(Between(s.truth, weighted.relative_pose));
  EXPECT_LT(err_weighted, 0.7 * err_plain) << err_weighted << " vs " << err_plain;
}

TEST(RgbdRegistrationTest, InvalidDepthIsCountedAndDropped) {
  Scene s = MakeScene(TestMotion(), 0, 3);
  // Blank out the left third of the current depth image.
  s.depth_cur(cv::Rect(0, 0, 200, 480)).setTo(0.0f);
  size_t expected_missing = 0;
  for (const auto& p : s.pts_cur) {
    if (std::lround(p.x) < 200) ++expected_missing;
  }
  ASSERT_GT(expected_missing, 10u);
  const RegistrationResult r =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, s.depth_cur, s.k, RegistrationOptions());
  EXPECT_EQ(r.depth_rejects.missing, expected_missing);
  EXPECT_LE(r.matches_3d, s.pts_ref.size() - expected_missing);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  EXPECT_LT(TranslationNorm(Between(s.truth, r.relative_pose)), 0.003);
}

TEST(RgbdRegistrationTest, AllZeroDepthIsRejectedWithReason) {
  const Scene s = MakeScene(TestMotion(), 0, 4);
  const cv::Mat zero = cv::Mat::zeros(480, 640, CV_32FC1);
  const RegistrationResult r =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, zero, s.k, RegistrationOptions());
  EXPECT_FALSE(r.status.ok());
  EXPECT_EQ(r.status.reason().rfind("too few 3D matches: 0 < 12", 0), 0u) << r.status.reason();
  EXPECT_EQ(r.depth_rejects.missing, s.pts_cur.size());
  EXPECT_TRUE(r.relative_pose.isApprox(Pose3::Identity()));
}

TEST(RgbdRegistrationTest, ImplausibleMotionIsRejected) {
  const Scene s = MakeScene(TestMotion(), 0, 5);
  RegistrationOptions opt;
  opt.max_translation_m = 0.05;  // the true motion is 0.108 m
  const RegistrationResult r =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, s.depth_cur, s.k, opt);
  EXPECT_FALSE(r.status.ok());
  EXPECT_EQ(r.status.reason().rfind("implausible motion: 0.1", 0), 0u) << r.status.reason();
  EXPECT_NE(r.status.reason().find("m > 0.05 m"), std::string::npos);
}

TEST(RgbdRegistrationTest, TooFewInliersIsRejected) {
  Scene s = MakeScene(TestMotion(), 0, 6);
  RegistrationOptions opt;
  opt.min_inliers = static_cast<int>(s.pts_ref.size()) + 1;
  const RegistrationResult r =
      RegisterRgbd(s.pts_ref, s.depth_ref, s.pts_cur, s.depth_cur, s.k, opt);
  EXPECT_EQ(r.status.reason().rfind("too few inliers: ", 0), 0u) << r.status.reason();
}

TEST(RgbdRegistrationTest, BadInputGivesStatusNotCrash) {
  const Scene s = MakeScene(TestMotion(), 0, 7);
  std::vector<cv::Point2f> shorter(s.pts_cur.begin(), s.pts_cur.end() - 1);
  EXPECT_NE(RegisterRgbd(s.pts_ref, s.depth_ref, shorter, s.depth_cur, s.k, {})
                .status.reason()
                .find("mismatch"),
            std::string::npos);
  cv::Mat depth16(480, 640, CV_16UC1, cv::Scalar(0));
  EXPECT_FALSE(RegisterRgbd(s.pts_ref, depth16, s.pts_cur, s.depth_cur, s.k, {}).status.ok());
}

TEST(RgbdRegistrationTest, ReadsOptionsWithRangeChecks) {
  RegistrationOptions opt;
  ReadOptions(OptionReader::FromString("inlier_threshold_m: 0.02\nmin_inliers: 25\n"), &opt);
  EXPECT_EQ(opt.inlier_threshold_m, 0.02);
  EXPECT_EQ(opt.min_inliers, 25);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("inlier_threshold_m: -1\n"), &opt), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("min_depth_m: 5\nmax_depth_m: 4\n"), &opt),
               LoadError);
}

}  // namespace
}  // namespace icgm
