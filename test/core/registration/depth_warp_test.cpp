#include "core/registration/depth_warp.h"
#include "core/registration/rolling_shutter.h"

#include <cmath>

#include <gtest/gtest.h>

#include "synthetic_rgbd.h"

namespace icgm {
namespace {

// Row v of the depth image of a scene seen by a camera at `world_from_camera`: a wall z = 2.5 m
// (world) with a box face at z = 1.6 m for x in [-0.3, 0.2] (a depth edge), by ray casting.
void RenderSceneRow(const CameraIntrinsics& k, const Pose3& world_from_camera, int v,
                    cv::Mat* depth) {
  const Eigen::Matrix3d r = world_from_camera.linear();
  const Eigen::Vector3d o = world_from_camera.translation();
  for (int u = 0; u < k.width_px; ++u) {
    const Eigen::Vector3d ray_c = k.BackProject(u, v, 1.0);
    const Eigen::Vector3d ray_w = r * ray_c;
    double best = INFINITY;
    for (const double plane_z : {1.6, 2.5}) {
      const double s = (plane_z - o.z()) / ray_w.z();  // ray parameter, = camera depth
      if (!(s > 0.0)) continue;
      const Eigen::Vector3d p = o + s * ray_w;
      if (plane_z == 1.6 && (p.x() < -0.3 || p.x() > 0.2)) continue;
      best = std::min(best, s);
    }
    depth->at<float>(v, u) = std::isfinite(best) ? static_cast<float>(best) : 0.0f;
  }
}

cv::Mat RenderScene(const CameraIntrinsics& k, const Pose3& world_from_camera) {
  cv::Mat depth(k.height_px, k.width_px, CV_32FC1, cv::Scalar(0.0f));
  for (int v = 0; v < k.height_px; ++v) RenderSceneRow(k, world_from_camera, v, &depth);
  return depth;
}

struct Comparison {
  double rms_m = 0.0;
  double valid_fraction = 0.0;
};

// Away from the box edges (where a nearest-pixel lookup may pick either side).
Comparison Compare(const cv::Mat& a, const cv::Mat& truth) {
  double sum = 0.0;
  int n = 0, valid = 0, total = 0;
  for (int v = 0; v < a.rows; ++v) {
    for (int u = 0; u < a.cols; ++u) {
      const float t = truth.at<float>(v, u);
      bool near_edge = false;
      for (int dv = -3; dv <= 3 && !near_edge; ++dv) {
        for (int du = -3; du <= 3 && !near_edge; ++du) {
          const int uu = std::clamp(u + du, 0, a.cols - 1), vv = std::clamp(v + dv, 0, a.rows - 1);
          near_edge = std::abs(truth.at<float>(vv, uu) - t) > 0.05f;
        }
      }
      if (near_edge || u < 20 || v < 20 || u >= a.cols - 20 || v >= a.rows - 20) continue;
      ++total;
      const float z = a.at<float>(v, u);
      if (!std::isfinite(z) || z <= 0.0f) continue;
      ++valid;
      sum += (z - t) * (z - t);
      ++n;
    }
  }
  return {n ? std::sqrt(sum / n) : INFINITY, total ? static_cast<double>(valid) / total : 0.0};
}

TEST(WarpDepthImage, RendersTheSceneAtTheTargetPose) {
  const CameraIntrinsics k = test::TumLikeCamera();
  // Colour instant (target) and depth instant (source) 20 ms apart at 0.5 m/s sideways and
  // forwards with a slight turn.
  Pose3 target = Pose3::Identity();
  Pose3 source = Pose3::Identity();
  source.translation() = Eigen::Vector3d(0.008, -0.004, 0.006);
  source.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.3, 1.0, 0.1).normalized()).matrix();
  const cv::Mat depth_source = RenderScene(k, source);
  const cv::Mat depth_target = RenderScene(k, target);

  const cv::Mat warped = WarpDepthImage(depth_source, k, Between(target, source));
  const Comparison before = Compare(depth_source, depth_target);
  const Comparison after = Compare(warped, depth_target);
  EXPECT_GT(before.rms_m, 0.005);  // the depth image of the other instant is off by millimetres
  EXPECT_LT(after.rms_m, 0.0005);  // the warped one agrees to well under a millimetre
  EXPECT_GT(after.valid_fraction, 0.99);
}

TEST(WarpDepthImage, IdentityKeepsTheImageAndMarksMissingDepthNan) {
  const CameraIntrinsics k = test::TumLikeCamera();
  cv::Mat depth = RenderScene(k, Pose3::Identity());
  depth.at<float>(100, 100) = 0.0f;
  const cv::Mat warped = WarpDepthImage(depth, k, Pose3::Identity());
  EXPECT_TRUE(std::isnan(warped.at<float>(100, 100)));
  EXPECT_FLOAT_EQ(warped.at<float>(200, 300), depth.at<float>(200, 300));
  EXPECT_LT(Compare(warped, depth).rms_m, 1e-6);
}

TEST(WarpDepthImageByRow, BringsARollingShutterImageToTheStampInstant) {
  const CameraIntrinsics k = test::TumLikeCamera();
  // A hand-held sweep: 0.4 m/s sideways, 0.2 m/s forwards, turning at 0.5 rad/s about y; rows
  // read out over 30 ms with the stamp at the middle row.
  Vec6 twist;
  twist << 0.4, -0.1, 0.2, 0.1, 0.5, -0.1;
  RowTiming timing;
  timing.line_s = 0.03 / (k.height_px - 1);
  timing.first_row_s = -0.015;
  Pose3 world_from_stamp = Pose3::Identity();
  world_from_stamp.translation() = Eigen::Vector3d(0.05, 0.0, 0.1);
  const std::vector<Pose3> stamp_from_row = StampFromRowPoses(k.height_px, timing, twist);
  ASSERT_EQ(static_cast<int>(stamp_from_row.size()), k.height_px);
  cv::Mat rolling(k.height_px, k.width_px, CV_32FC1, cv::Scalar(0.0f));
  for (int v = 0; v < k.height_px; ++v) {
    RenderSceneRow(k, world_from_stamp * stamp_from_row[v], v, &rolling);
  }
  const cv::Mat truth = RenderScene(k, world_from_stamp);

  const Comparison before = Compare(rolling, truth);
  const Comparison after = Compare(WarpDepthImageByRow(rolling, k, stamp_from_row), truth);
  // A single pose for the whole image (the middle row's, i.e. the stamp's) leaves the top and
  // bottom rows' motion in the image.
  const Comparison one_pose = Compare(WarpDepthImage(rolling, k, Pose3::Identity()), truth);
  EXPECT_GT(before.rms_m, 0.002);
  EXPECT_GT(one_pose.rms_m, 0.002);
  EXPECT_LT(after.rms_m, 0.1 * before.rms_m);
  EXPECT_LT(after.rms_m, 0.0005);
  EXPECT_GT(after.valid_fraction, 0.99);
}

TEST(WarpDepthImageByRow, TheSamePoseForEveryRowIsTheSingleImageWarp) {
  const CameraIntrinsics k = test::TumLikeCamera();
  const cv::Mat depth = RenderScene(k, Pose3::Identity());
  Pose3 motion = Pose3::Identity();
  motion.translation() = Eigen::Vector3d(0.01, 0.002, -0.005);
  motion.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()).matrix();
  const cv::Mat a = WarpDepthImage(depth, k, motion);
  const cv::Mat b = WarpDepthImageByRow(depth, k, std::vector<Pose3>(k.height_px, motion));
  cv::Mat differ;
  cv::compare(a, b, differ, cv::CMP_NE);  // NaN != NaN: count those apart
  cv::Mat a_nan, b_nan;
  cv::compare(a, a, a_nan, cv::CMP_NE);
  cv::compare(b, b, b_nan, cv::CMP_NE);
  EXPECT_EQ(cv::countNonZero(a_nan != b_nan), 0);
  EXPECT_EQ(cv::countNonZero(differ & (a_nan == 0)), 0);
}

}  // namespace
}  // namespace icgm
