#include "core/registration/depth_consistency.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics k;
  k.fx_px = k.fy_px = 525.0;
  k.cx_px = 319.5;
  k.cy_px = 239.5;
  return k;
}

// Depth seen from `world_from_camera` of a slanted wall (world z = 3 + 0.5 x) and a "walker": a
// slab at z = 1.5 m spanning x in [walker_x, walker_x + 0.5], y in [-1, 1].
cv::Mat Render(const CameraIntrinsics& k, const Pose3& world_from_camera, double walker_x,
               cv::Mat* grey = nullptr) {
  cv::Mat depth(k.height_px, k.width_px, CV_32FC1, cv::Scalar(0.0f));
  if (grey) grey->create(k.height_px, k.width_px, CV_8UC1);
  const Eigen::Matrix3d r = world_from_camera.linear();
  const Eigen::Vector3d o = world_from_camera.translation();
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const Eigen::Vector3d ray = r * k.BackProject(u, v, 1.0);
      double best = INFINITY;
      // The slab, then the wall z = 3 + 0.5 x (slanted, so that a sideways motion shows in depth).
      const double s_slab = (1.5 - o.z()) / ray.z();
      const Eigen::Vector3d on_slab = o + s_slab * ray;
      if (s_slab > 0.0 && on_slab.x() >= walker_x && on_slab.x() <= walker_x + 0.5 &&
          std::abs(on_slab.y()) <= 1.0) {
        best = (r.transpose() * (on_slab - o)).z();  // depth along the camera's optical axis
      }
      const double s_wall = (3.0 + 0.5 * o.x() - o.z()) / (ray.z() - 0.5 * ray.x());
      double x_seen = on_slab.x() + 0.37;  // the slab's own stripes, shifted
      if (s_wall > 0.0 && (r.transpose() * (s_wall * ray)).z() < best) {
        best = (r.transpose() * (s_wall * ray)).z();
        x_seen = (o + s_wall * ray).x();
      }
      // Vertical bands 2 cm wide of pseudo-random grey on both surfaces.
      if (grey) {
        const auto band = static_cast<uint32_t>(std::floor(x_seen * 50.0) + 1000.0);
        grey->at<uint8_t>(v, u) = static_cast<uint8_t>(30 + (band * 2654435761u >> 24) % 200);
      }
      depth.at<float>(v, u) = static_cast<float>(best);
    }
  }
  return depth;
}

Pose3 CameraAt(double x) {
  Pose3 p = Pose3::Identity();
  p.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return p;
}

// Column range (pixels) of the walker seen from the camera at x_cam.
std::pair<double, double> WalkerColumns(const CameraIntrinsics& k, double x_cam, double walker_x) {
  return {k.cx_px + k.fx_px * (walker_x - x_cam) / 1.5,
          k.cx_px + k.fx_px * (walker_x + 0.5 - x_cam) / 1.5};
}

TEST(DepthConsistencyTest, TrueMotionAgreesAndMasksTheWalkerWhereItMovedIn) {
  const CameraIntrinsics k = Camera();
  // The camera moves 5 cm right, the walker 30 cm left.
  const cv::Mat ref = Render(k, CameraAt(0.0), 0.0);
  const cv::Mat cur = Render(k, CameraAt(0.05), -0.3);
  DepthConsistencyOptions o;
  DynamicMask mask;
  const Pose3 truth = CameraAt(0.05);  // ref_cur: current camera in the reference frame
  const DepthConsistency good = CheckDepthConsistency(ref, cur, truth, k, o, &mask);
  ASSERT_GT(good.compared, 10000u);
  // The walker's new place that showed wall before is in front; the rest agrees.
  EXPECT_GT(good.in_front, 500u);
  EXPECT_GT(good.AgreeingShare(), 0.6);
  // The walker's motion explains the walker only.
  const Pose3 walker_motion = CameraAt(0.3);
  const DepthConsistency bad = CheckDepthConsistency(ref, cur, walker_motion, k, o);
  EXPECT_LT(bad.AgreeingShare(), good.AgreeingShare() - 0.2);

  // Mask: inside the walker's part that covers former wall, not on the far wall.
  ASSERT_FALSE(mask.empty());
  const auto [left, right] = WalkerColumns(k, 0.05, -0.3);
  const auto [old_left, old_right] = WalkerColumns(k, 0.05, 0.0);
  const float in_walker = static_cast<float>((left + std::min(right, old_left)) / 2.0);
  EXPECT_TRUE(mask.Contains({in_walker, 240.0f}));
  EXPECT_FALSE(mask.Contains({static_cast<float>(right + 80.0), 240.0f}));
  EXPECT_FALSE(mask.Contains({static_cast<float>(left - 60.0), 240.0f}));
  EXPECT_GT(mask.Coverage(), 0.02);
  EXPECT_LT(mask.Coverage(), 0.3);
  (void)old_right;
}

TEST(DepthConsistencyTest, EdgesLineUpOnlyUnderTheCamerasMotion) {
  const CameraIntrinsics k = Camera();
  cv::Mat grey_ref, grey_cur;
  const cv::Mat ref = Render(k, CameraAt(0.0), 0.0, &grey_ref);
  const cv::Mat cur = Render(k, CameraAt(0.05), -0.3, &grey_cur);
  DepthConsistencyOptions o;
  const DepthConsistency good = CheckEdgeConsistency(grey_ref, grey_cur, cur, CameraAt(0.05), k, o);
  const DepthConsistency walker = CheckEdgeConsistency(grey_ref, grey_cur, cur, CameraAt(0.3), k, o);
  const DepthConsistency off = CheckEdgeConsistency(grey_ref, grey_cur, cur, CameraAt(0.1), k, o);
  ASSERT_GT(good.compared, 500u);
  EXPECT_GT(good.AgreeingShare(), 0.6);
  EXPECT_LT(walker.AgreeingShare(), good.AgreeingShare() - 0.2);
  // 5 cm off sideways: the wall's bands no longer line up.
  EXPECT_LT(off.AgreeingShare(), good.AgreeingShare() - 0.2);
  // No grey image (features extracted elsewhere): nothing compared.
  EXPECT_EQ(CheckEdgeConsistency(cv::Mat(), grey_cur, cur, CameraAt(0.05), k, o).compared, 0u);
}

TEST(DepthConsistencyTest, StaticSceneHasNoMask) {
  const CameraIntrinsics k = Camera();
  const cv::Mat ref = Render(k, CameraAt(0.0), 0.1);
  const cv::Mat cur = Render(k, CameraAt(0.04), 0.1);  // the slab is static here
  DynamicMask mask;
  const DepthConsistency c = CheckDepthConsistency(ref, cur, CameraAt(0.04), k, {}, &mask);
  EXPECT_GT(c.AgreeingShare(), 0.97);
  EXPECT_LT(mask.Coverage(), 0.005);
  // Empty input: nothing compared, nothing masked.
  const DepthConsistency none = CheckDepthConsistency(cv::Mat(), cur, CameraAt(0.04), k, {}, &mask);
  EXPECT_EQ(none.compared, 0u);
  EXPECT_TRUE(mask.empty());
}

TEST(DepthConsistencyTest, PropagationFollowsTheCameraMotion) {
  const CameraIntrinsics k = Camera();
  DynamicMask previous;
  previous.step_px = 4;
  previous.cells = cv::Mat::zeros(120, 160, CV_8UC1);
  previous.cells(cv::Rect(70, 50, 10, 20)) = 255;  // pixels u 280-319, v 200-279
  const cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(1.5f));
  // The camera moves 0.1 m right: points at 1.5 m move 35 px left (about 9 cells).
  const Pose3 cur_prev = CameraAt(0.1).inverse();
  const DynamicMask moved = PropagateDynamicMask(previous, depth, cur_prev, k, 0);
  EXPECT_TRUE(moved.Contains({260.0f, 240.0f}));
  EXPECT_FALSE(moved.Contains({310.0f, 240.0f}));
  const DynamicMask grown = PropagateDynamicMask(previous, depth, cur_prev, k, 3);
  EXPECT_TRUE(grown.Contains({290.0f, 240.0f}));
  EXPECT_GT(grown.Coverage(), moved.Coverage());
}

}  // namespace
}  // namespace icgm
