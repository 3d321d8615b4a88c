// A wall 3 m away seen by a camera sliding sideways, with a person 1.5 m away standing in a
// different place in each frame: the background of a frame is the wall (the person is in too few
// of the other frames to count), the person is the foreground, the wall is not.
#include "core/eval/background_depth.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics k;
  k.fx_px = k.fy_px = 300;
  k.cx_px = 160;
  k.cy_px = 120;
  k.width_px = 320;
  k.height_px = 240;
  return k;
}

Pose3 CameraAt(double x_m) {
  Pose3 T = Pose3::Identity();
  T.translation() = Eigen::Vector3d(x_m, 0.0, 0.0);
  return T;
}

// Depth seen from a camera at x_m (looking along +z): a wall at z = 3 m and a 0.4 m wide person
// at z = 1.5 m centred at world x person_x_m.
cv::Mat Render(const CameraIntrinsics& k, double x_m, double person_x_m) {
  cv::Mat depth(k.height_px, k.width_px, CV_32FC1, cv::Scalar(3.0f));
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      const double world_x = x_m + (u - k.cx_px) * 1.5 / k.fx_px;  // the ray at 1.5 m
      if (std::abs(world_x - person_x_m) < 0.2) depth.at<float>(v, u) = 1.5f;
    }
  }
  return depth;
}

TEST(BackgroundDepthTest, WalkerInFrontOfTheWallIsForegroundAndTheWallIsNot) {
  const CameraIntrinsics k = Camera();
  std::vector<cv::Mat> depths;
  std::vector<Pose3> poses;
  for (int i = 0; i < 6; ++i) {
    const double x = 0.02 * i;
    depths.push_back(Render(k, x, -0.8 + 0.3 * i));  // the person walks 0.3 m per frame
    poses.push_back(CameraAt(x));
  }
  const double target_x = 0.05;
  const double person_x = 0.0;
  const cv::Mat target = Render(k, target_x, person_x);
  const cv::Mat background = BackgroundDepth(depths, poses, CameraAt(target_x), k);
  // Away from the borders (the slide leaves the outermost columns unseen) the wall at 3 m.
  for (int u = 20; u < k.width_px - 20; u += 10) {
    EXPECT_NEAR(background.at<float>(120, u), 3.0f, 1e-3) << "column " << u;
  }
  const cv::Mat fg = ForegroundMask(target, background);
  const int person_u = static_cast<int>(k.cx_px + (person_x - target_x) * k.fx_px / 1.5);
  EXPECT_EQ(fg.at<uint8_t>(120, person_u), 255);
  EXPECT_EQ(fg.at<uint8_t>(120, person_u + 60), 0);  // 0.3 m beside the person: wall
  // The person covers 0.4 m at 1.5 m: 80 columns of 320.
  EXPECT_NEAR(cv::countNonZero(fg) / static_cast<double>(fg.total()), 0.25, 0.02);
  // Standing in the same place in most frames, it becomes the background: not found.
  for (int i = 0; i < 6; ++i) depths[i] = Render(k, 0.02 * i, person_x);
  const cv::Mat stays =
      ForegroundMask(target, BackgroundDepth(depths, poses, CameraAt(target_x), k));
  EXPECT_EQ(cv::countNonZero(stays), 0);
}

}  // namespace
}  // namespace icgm
