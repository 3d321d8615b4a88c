// Motion blur smears the image along the path of each pixel during the exposure: nothing
// changes without motion, and a sideways move spreads a one-pixel line over the expected width.
#include "core/sim/motion_blur.h"

#include <gtest/gtest.h>

namespace icgm::sim {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics K;
  K.fx_px = K.fy_px = 500.0;
  K.cx_px = 80.0;
  K.cy_px = 60.0;
  K.width_px = 160;
  K.height_px = 120;
  return K;
}

cv::Mat LineImage() {
  cv::Mat img(120, 160, CV_8UC3, cv::Scalar(0, 0, 0));
  img.col(80).setTo(cv::Scalar(240, 240, 240));
  return img;
}

TEST(MotionBlurTest, NoMotionLeavesTheImageUnchanged) {
  const cv::Mat depth(120, 160, CV_32FC1, cv::Scalar(2.0f));
  cv::Mat img = LineImage();
  ApplyMotionBlur(Camera(), depth, Pose3::Identity(), Pose3::Identity(), &img);
  EXPECT_EQ(cv::norm(img, LineImage(), cv::NORM_INF), 0.0);
}

TEST(MotionBlurTest, SidewaysMotionSpreadsALineOverItsPath) {
  // 2 m away, 2 cm each way: the line moves 5 px each way (10 px path).
  const cv::Mat depth(120, 160, CV_32FC1, cv::Scalar(2.0f));
  Pose3 start = Pose3::Identity(), end = Pose3::Identity();
  start.translation().x() = -0.02;
  end.translation().x() = 0.02;
  cv::Mat img = LineImage();
  ApplyMotionBlur(Camera(), depth, start, end, &img);
  const cv::Vec3b* row = img.ptr<cv::Vec3b>(60);
  int lit = 0;
  double total = 0.0;
  for (int u = 0; u < img.cols; ++u) {
    lit += row[u][1] > 0;
    total += row[u][1];
  }
  EXPECT_GE(lit, 9);
  EXPECT_LE(lit, 12);
  EXPECT_LT(row[80][1], 60);          // the line's energy is spread out ...
  EXPECT_NEAR(total, 240.0, 240.0 * 0.15);  // ... but kept
  // Rows are blurred alike: the motion is horizontal.
  EXPECT_EQ(cv::norm(img.row(10), img.row(100), cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace icgm::sim
