#include "core/registration/rolling_shutter.h"
#include "core/registration/sensor_timing.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "synthetic_rgbd.h"

namespace icgm {
namespace {

// A camera moving with a constant twist; rows read out over 30 ms, stamp at the middle row.
struct RollingView {
  CameraIntrinsics k = test::TumLikeCamera();
  Vec6 twist;
  RowTiming timing;
  Pose3 world_from_stamp = Pose3::Identity();
  std::vector<Pose3> stamp_from_row;

  explicit RollingView(const Vec6& twist_per_s) : twist(twist_per_s) {
    timing.line_s = 0.03 / (k.height_px - 1);
    timing.first_row_s = -0.015;
    world_from_stamp.translation() = Eigen::Vector3d(0.1, -0.05, 0.0);
    stamp_from_row = StampFromRowPoses(k.height_px, timing, twist);
  }
  // Where the rolling shutter sees world point p: the row whose capture pose projects p onto
  // that row (fixed point); NaN when off the image.
  cv::Point2f RollingPixel(const Eigen::Vector3d& p_world) const {
    double v = k.cy_px;
    Eigen::Vector2d q;
    for (int it = 0; it < 20; ++it) {
      const Pose3 pose = world_from_stamp * ExpSE3(timing.RowOffsetS(v) * twist);
      q = k.Project(pose.inverse() * p_world);
      v = std::clamp(q.y(), 0.0, k.height_px - 1.0);
    }
    return cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y()));
  }
  cv::Point2f StampPixel(const Eigen::Vector3d& p_world) const {
    const Eigen::Vector2d q = k.Project(world_from_stamp.inverse() * p_world);
    return cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y()));
  }
  // Depth at the stamp instant of a wall 2 m ahead of the stamp camera.
  cv::Mat WallDepthAtStamp() const {
    cv::Mat depth(k.height_px, k.width_px, CV_32FC1);
    const Eigen::Matrix3d r = world_from_stamp.linear();
    const Eigen::Vector3d o = world_from_stamp.translation();
    for (int v = 0; v < k.height_px; ++v) {
      for (int u = 0; u < k.width_px; ++u) {
        const Eigen::Vector3d ray_w = r * k.BackProject(u, v, 1.0);
        depth.at<float>(v, u) = static_cast<float>((kWallZ - o.z()) / ray_w.z());
      }
    }
    return depth;
  }
  static constexpr double kWallZ = 2.0;
};

// Keypoints at the rolling-shutter pixels of a grid of wall points, with their true pixels at
// the stamp instant.
void WallKeypoints(const RollingView& view, std::vector<cv::KeyPoint>* keypoints,
                   std::vector<cv::Point2f>* at_stamp) {
  for (double x = -1.0; x <= 1.0; x += 0.2) {
    for (double y = -0.7; y <= 0.7; y += 0.2) {
      const Eigen::Vector3d p(x, y, RollingView::kWallZ);
      const cv::Point2f px = view.RollingPixel(p);
      if (px.x < 5 || px.y < 5 || px.x > view.k.width_px - 5 || px.y > view.k.height_px - 5) {
        continue;
      }
      keypoints->emplace_back(px, 7.0f);
      at_stamp->push_back(view.StampPixel(p));
    }
  }
}

double MaxError(const std::vector<cv::KeyPoint>& keypoints, const std::vector<cv::Point2f>& truth) {
  double worst = 0.0;
  for (size_t i = 0; i < keypoints.size(); ++i) {
    worst = std::max(worst, static_cast<double>(cv::norm(keypoints[i].pt - truth[i])));
  }
  return worst;
}

TEST(DeskewKeypoints, MovesKeypointsToWhereTheCameraAtTheStampSeesThem) {
  Vec6 twist;
  twist << 0.4, -0.1, 0.2, 0.1, 0.5, -0.1;  // m/s and rad/s: a brisk hand-held sweep
  const RollingView view(twist);
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point2f> truth;
  WallKeypoints(view, &keypoints, &truth);
  ASSERT_GT(keypoints.size(), 40u);
  const double before_px = MaxError(keypoints, truth);
  DeskewKeypoints(view.stamp_from_row, view.WallDepthAtStamp(), view.k, &keypoints);
  const double after_px = MaxError(keypoints, truth);
  EXPECT_GT(before_px, 2.0);  // top and bottom rows are 15 ms away from the stamp
  EXPECT_LT(after_px, 0.05);
}

TEST(DeskewKeypoints, WithoutDepthARotationIsStillUndone) {
  Vec6 twist;
  twist << 0.0, 0.0, 0.0, 0.3, -0.6, 0.2;  // rotation only: the shift needs no depth
  const RollingView view(twist);
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point2f> truth;
  WallKeypoints(view, &keypoints, &truth);
  ASSERT_GT(keypoints.size(), 40u);
  const cv::Mat no_depth(view.k.height_px, view.k.width_px, CV_32FC1,
                         cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  const double before_px = MaxError(keypoints, truth);
  DeskewKeypoints(view.stamp_from_row, no_depth, view.k, &keypoints);
  EXPECT_GT(before_px, 2.0);
  EXPECT_LT(MaxError(keypoints, truth), 0.05);
}

TEST(DeskewKeypoints, AGlobalShutterLeavesKeypointsInPlace) {
  Vec6 twist;
  twist << 0.4, -0.1, 0.2, 0.1, 0.5, -0.1;
  RollingView view(twist);
  view.timing = RowTiming();  // every row at the stamp
  view.stamp_from_row = StampFromRowPoses(view.k.height_px, view.timing, twist);
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point2f> truth;
  WallKeypoints(view, &keypoints, &truth);
  const std::vector<cv::KeyPoint> original = keypoints;
  DeskewKeypoints(view.stamp_from_row, view.WallDepthAtStamp(), view.k, &keypoints);
  ASSERT_EQ(keypoints.size(), original.size());
  for (size_t i = 0; i < keypoints.size(); ++i) {
    EXPECT_NEAR(keypoints[i].pt.x, original[i].pt.x, 1e-3);
    EXPECT_NEAR(keypoints[i].pt.y, original[i].pt.y, 1e-3);
  }
}

TEST(SensorTiming, VelocityAndDepthOffsetFromStampsAndPoses) {
  const Time t0 = Time::FromNanoseconds(5'000'000'000LL);
  const Time t1 = Time::FromNanoseconds(5'050'000'000LL);  // 50 ms later
  Pose3 p1 = Pose3::Identity();
  p1.translation() = Eigen::Vector3d(0.02, 0.0, -0.01);
  p1.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()).matrix();
  const std::optional<Vec6> twist = VelocityTwist(t0, Pose3::Identity(), t1, p1, 0.1);
  ASSERT_TRUE(twist.has_value());
  EXPECT_NEAR((*twist)(0), 0.4, 1e-9);   // m/s
  EXPECT_NEAR((*twist)(2), -0.2, 1e-9);
  EXPECT_NEAR((*twist)(4), 0.2, 1e-9);   // rad/s about y
  EXPECT_FALSE(VelocityTwist(t0, Pose3::Identity(), t1, p1, 0.04).has_value());  // too far apart
  EXPECT_FALSE(VelocityTwist(t1, p1, t0, Pose3::Identity(), 0.1).has_value());  // backwards

  CameraIntrinsics k = test::TumLikeCamera();
  k.depth_time_offset_s = -0.01;
  EXPECT_NEAR(DepthTimeOffsetS(t0, t1, k, 0.001), 0.04, 1e-12);
  EXPECT_EQ(DepthTimeOffsetS(t0, Time::FromNanoseconds(5'010'500'000LL), k, 0.001), 0.0);
  EXPECT_FALSE(HasRollingShutter(k));
  k.readout_s = 0.02;
  EXPECT_TRUE(HasRollingShutter(k));
  EXPECT_NEAR(ColourRowTiming(k).line_s * (k.height_px - 1), 0.02, 1e-12);
}

}  // namespace
}  // namespace icgm
