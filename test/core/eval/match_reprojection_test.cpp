// Matches between two views of points with known depth under a known motion: a correct match
// reprojects to ~0 px, a wrong one far, one without depth gives NaN.
#include "core/eval/match_reprojection.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(MatchReprojectionTest, CorrectWrongAndMissingDepth) {
  CameraIntrinsics k;
  k.fx_px = 500;
  k.fy_px = 500;
  k.cx_px = 320;
  k.cy_px = 240;
  Pose3 b_from_a = Pose3::Identity();
  b_from_a.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).matrix();
  b_from_a.translation() = Eigen::Vector3d(0.1, -0.02, 0.05);
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(2.0f));
  depth.at<float>(100, 100) = std::numeric_limits<float>::quiet_NaN();
  std::vector<cv::KeyPoint> a, b;
  for (const cv::Point2f p :
       {cv::Point2f(300, 200), cv::Point2f(450, 300), cv::Point2f(100, 100)}) {
    a.emplace_back(p, 10.0f);
    const Eigen::Vector2d uv = k.Project(b_from_a * k.BackProject(p.x, p.y, 2.0));
    b.emplace_back(cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y())), 10.0f);
  }
  const std::vector<cv::DMatch> matches = {
      {0, 0, 0.f}, {1, 0, 0.f}, {2, 2, 0.f}, {1, 1, 0.f}, {7, 1, 0.f}};
  const std::vector<double> e = MatchReprojectionErrorsPx(a, b, matches, depth, k, b_from_a);
  ASSERT_EQ(e.size(), matches.size());
  EXPECT_LT(e[0], 1e-3);
  EXPECT_GT(e[1], 50.0);          // keypoint 1 matched to 0's image
  EXPECT_TRUE(std::isnan(e[2]));  // no depth
  EXPECT_LT(e[3], 1e-3);
  EXPECT_TRUE(std::isnan(e[4]));  // index out of range
  // Without the motion the correct matches are off by the motion's image shift.
  const std::vector<double> still =
      MatchReprojectionErrorsPx(a, b, matches, depth, k, Pose3::Identity());
  EXPECT_GT(still[0], 10.0);
}

}  // namespace
}  // namespace icgm
