// Lens undistortion against points of known ideal position: a point's raw (distorted) pixel is
// computed with OpenCV's projection model; the undistorted image has the point back at its ideal
// pixel, keypoints move back there, depth stays unmixed, and the caller's images are never
// written (a front end given the same image twice must see the raw image twice).
#include "core/features/lens_undistortion.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace icgm {
namespace {

// The Kinect of the TUM RGB-D benchmark's Freiburg 1 sequences, as published with it: several
// pixels of displacement towards the corners.
CameraIntrinsics Fr1Kinect() {
  CameraIntrinsics c;
  c.fx_px = 517.3;
  c.fy_px = 516.5;
  c.cx_px = 318.6;
  c.cy_px = 255.3;
  c.distortion_k1 = 0.2624;
  c.distortion_k2 = -0.9531;
  c.distortion_p1 = -0.0054;
  c.distortion_p2 = 0.0026;
  c.distortion_k3 = 1.1633;
  return c;
}

// Raw pixel at which the camera sees what the ideal pinhole camera sees at `ideal`.
cv::Point2d RawPixel(const CameraIntrinsics& c, const cv::Point2d& ideal) {
  const std::vector<cv::Point3d> ray{{(ideal.x - c.cx_px) / c.fx_px,
                                      (ideal.y - c.cy_px) / c.fy_px, 1.0}};
  std::vector<cv::Point2d> raw;
  const cv::Matx33d k(c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1);
  const cv::Vec<double, 5> d(c.distortion_k1, c.distortion_k2, c.distortion_p1, c.distortion_p2,
                             c.distortion_k3);
  cv::projectPoints(ray, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d, raw);
  return raw[0];
}

const std::vector<cv::Point2d> kIdealPoints{{40, 40}, {600, 60}, {320, 240}, {70, 430}, {590, 440}};

TEST(LensUndistortion, KeypointsReturnToTheirIdealPixels) {
  const CameraIntrinsics c = Fr1Kinect();
  const LensUndistortion undistortion(c);
  ASSERT_TRUE(undistortion.active());
  std::vector<cv::KeyPoint> keypoints;
  double largest_shift_px = 0;
  for (const auto& p : kIdealPoints) {
    const cv::Point2d raw = RawPixel(c, p);
    largest_shift_px = std::max(largest_shift_px, std::hypot(raw.x - p.x, raw.y - p.y));
    keypoints.emplace_back(cv::Point2f(raw), 7.0f);
  }
  EXPECT_GT(largest_shift_px, 3.0) << "the calibration moves corner points by pixels";
  undistortion.MoveKeypoints(&keypoints);
  for (size_t i = 0; i < keypoints.size(); ++i) {
    EXPECT_NEAR(keypoints[i].pt.x, kIdealPoints[i].x, 0.05) << i;
    EXPECT_NEAR(keypoints[i].pt.y, kIdealPoints[i].y, 0.05) << i;
    EXPECT_FLOAT_EQ(keypoints[i].size, 7.0f);
  }
}

TEST(LensUndistortion, ImagesMoveAndTheInputStaysRaw) {
  const CameraIntrinsics c = Fr1Kinect();
  const LensUndistortion undistortion(c);
  // Raw colour image: a bright dot where each ideal point is seen; raw depth: 2 m left of the
  // image centre column, 3 m right of it.
  cv::Mat raw(c.height_px, c.width_px, CV_8UC3, cv::Scalar(20, 20, 20));
  for (const auto& p : kIdealPoints) {
    cv::circle(raw, cv::Point(cvRound(RawPixel(c, p).x), cvRound(RawPixel(c, p).y)), 2,
               cv::Scalar(255, 255, 255), cv::FILLED);
  }
  cv::Mat depth(c.height_px, c.width_px, CV_32FC1, cv::Scalar(2.0f));
  depth.colRange(c.width_px / 2, c.width_px).setTo(3.0f);
  const cv::Mat raw_copy = raw.clone();
  const cv::Mat depth_copy = depth.clone();

  const cv::Mat ideal = undistortion.Colour(raw);
  const cv::Mat ideal_depth = undistortion.Depth(depth);
  EXPECT_EQ(cv::norm(raw, raw_copy, cv::NORM_INF), 0.0) << "the caller's colour image changed";
  EXPECT_EQ(cv::norm(depth, depth_copy, cv::NORM_INF), 0.0) << "the caller's depth changed";
  ASSERT_NE(ideal.data, raw.data);

  cv::Mat grey;
  cv::cvtColor(ideal, grey, cv::COLOR_BGR2GRAY);
  for (const auto& p : kIdealPoints) {
    const cv::Rect window(cvRound(p.x) - 6, cvRound(p.y) - 6, 13, 13);
    const cv::Moments m = cv::moments(grey(window) > 128, true);
    ASSERT_GT(m.m00, 0) << "no dot near " << p;
    EXPECT_NEAR(window.x + m.m10 / m.m00, p.x, 1.0) << p;
    EXPECT_NEAR(window.y + m.m01 / m.m00, p.y, 1.0) << p;
  }
  // Depth: only values of the input (nearest neighbour), NaN where no raw pixel exists.
  int nan = 0, mixed = 0;
  for (int v = 0; v < ideal_depth.rows; ++v) {
    for (int u = 0; u < ideal_depth.cols; ++u) {
      const float z = ideal_depth.at<float>(v, u);
      if (std::isnan(z)) {
        ++nan;
      } else if (z != 2.0f && z != 3.0f) {
        ++mixed;
      }
    }
  }
  EXPECT_EQ(mixed, 0);
  EXPECT_LT(nan, ideal_depth.total() / 10);  // the corners beyond the raw image
}

TEST(LensUndistortion, WithoutDistortionEverythingPassesThrough) {
  CameraIntrinsics c = Fr1Kinect();
  c.distortion_k1 = c.distortion_k2 = c.distortion_p1 = c.distortion_p2 = c.distortion_k3 = 0.0;
  const LensUndistortion undistortion(c);
  EXPECT_FALSE(undistortion.active());
  const cv::Mat image(c.height_px, c.width_px, CV_8UC3, cv::Scalar(1, 2, 3));
  EXPECT_EQ(undistortion.Colour(image).data, image.data);
  std::vector<cv::KeyPoint> keypoints{cv::KeyPoint(cv::Point2f(10.5f, 20.25f), 3.0f)};
  undistortion.MoveKeypoints(&keypoints);
  EXPECT_EQ(keypoints[0].pt, cv::Point2f(10.5f, 20.25f));
  // An image of another size than the camera's is left alone too.
  const LensUndistortion active(Fr1Kinect());
  const cv::Mat small(10, 10, CV_8UC3, cv::Scalar(0));
  EXPECT_EQ(active.Colour(small).data, small.data);
}

}  // namespace
}  // namespace icgm
