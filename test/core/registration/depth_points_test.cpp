#include "core/registration/depth_points.h"

#include <gtest/gtest.h>

#include <limits>

namespace icgm {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics k;
  k.fx_px = 500;
  k.fy_px = 500;
  k.cx_px = 320;
  k.cy_px = 240;
  return k;
}

TEST(DepthPointsTest, BackProjectsValidDepth) {
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  std::vector<Eigen::Vector3d> pts;
  std::vector<uint8_t> valid;
  DepthRejectCounts counts;
  KeypointsToPoints({{420.f, 140.f}}, depth, Camera(), DepthPointOptions(), &pts, &valid, &counts);
  ASSERT_EQ(valid[0], 1);
  EXPECT_NEAR(pts[0].x(), 100.0 * 2.0 / 500.0, 1e-9);
  EXPECT_NEAR(pts[0].y(), -100.0 * 2.0 / 500.0, 1e-9);
  EXPECT_NEAR(pts[0].z(), 2.0, 1e-9);
  EXPECT_EQ(counts.total(), 0u);
}

TEST(DepthPointsTest, CountsEachRejectReason) {
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  depth.at<float>(10, 10) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(20, 20) = 0.0f;
  depth.at<float>(30, 30) = 9.0f;  // beyond max_depth_m = 6
  // A step edge: columns >= 300 of row band 100..110 are 1 m closer.
  depth(cv::Rect(300, 100, 40, 10)).setTo(1.0f);
  // Isolated depth far from the band but next to a hole: also a discontinuity.
  depth.at<float>(200, 401) = std::numeric_limits<float>::quiet_NaN();

  const std::vector<cv::Point2f> px = {
      {10.f, 10.f},    // NaN
      {20.f, 20.f},    // zero
      {30.f, 30.f},    // out of range
      {299.f, 105.f},  // background pixel next to the step
      {300.f, 105.f},  // foreground pixel next to the step
      {320.f, 105.f},  // inside the foreground: valid
      {400.f, 200.f},  // next to a hole
      {-3.f, 5.f},     // outside
      {100.f, 400.f},  // valid
  };
  std::vector<Eigen::Vector3d> pts;
  std::vector<uint8_t> valid;
  DepthRejectCounts c;
  KeypointsToPoints(px, depth, Camera(), DepthPointOptions(), &pts, &valid, &c);
  EXPECT_EQ(c.missing, 2u);
  EXPECT_EQ(c.out_of_range, 1u);
  EXPECT_EQ(c.discontinuity, 3u);
  EXPECT_EQ(c.outside_image, 1u);
  EXPECT_EQ(c.total(), 7u);
  EXPECT_EQ(valid, (std::vector<uint8_t>{0, 0, 0, 0, 0, 1, 0, 0, 1}));
  EXPECT_NEAR(pts[5].z(), 1.0, 1e-9);
}

TEST(DepthPointsTest, DiscontinuityTestCanBeDisabled) {
  cv::Mat depth(48, 64, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(30, 0, 34, 48)).setTo(1.0f);
  DepthPointOptions opt;
  opt.max_depth_jump_ratio = 0.0;
  double z = 0;
  EXPECT_EQ(LookupDepth(depth, {29.f, 5.f}, opt, &z), DepthLookup::kOk);
  EXPECT_EQ(z, 2.0);
  opt.max_depth_jump_ratio = 0.05;
  EXPECT_EQ(LookupDepth(depth, {29.f, 5.f}, opt, &z), DepthLookup::kDiscontinuity);
}

TEST(DepthPointsTest, WrongDepthTypeIsMissingNotACrash) {
  cv::Mat depth16(48, 64, CV_16UC1, cv::Scalar(1000));
  double z = 0;
  EXPECT_EQ(LookupDepth(depth16, {5.f, 5.f}, DepthPointOptions(), &z), DepthLookup::kMissing);
  EXPECT_EQ(LookupDepth(cv::Mat(), {5.f, 5.f}, DepthPointOptions(), &z), DepthLookup::kMissing);
}

}  // namespace
}  // namespace icgm
