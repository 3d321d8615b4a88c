#include "core/registration/dense_refinement.h"

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

// Depth seen from `world_from_camera` in a plain room (camera frame convention: x right, y down,
// z forward): floor y = 1.2, side walls x = -2 and x = 2.5, back wall z = 4; plus a walker, a
// slab 0.8 m wide at depth `walker_z` in front of the camera spanning x in [-0.5, 0.3].
cv::Mat Render(const CameraIntrinsics& k, const Pose3& world_from_camera, double walker_z) {
  cv::Mat depth(k.height_px, k.width_px, CV_32FC1, cv::Scalar(0.0f));
  const Eigen::Matrix3d r = world_from_camera.linear();
  const Eigen::Vector3d o = world_from_camera.translation();
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const Eigen::Vector3d ray = r * k.BackProject(u, v, 1.0);
      double s_best = INFINITY;
      const auto plane = [&](int axis, double at) {
        if (std::abs(ray[axis]) < 1e-9) return;
        const double s = (at - o[axis]) / ray[axis];
        if (s > 0.0 && s < s_best) s_best = s;
      };
      plane(1, 1.2);
      plane(0, -2.0);
      plane(0, 2.5);
      plane(2, 4.0);
      if (walker_z > 0.0) {
        const double s = (walker_z - o.z()) / ray.z();
        const Eigen::Vector3d p = o + s * ray;
        if (s > 0.0 && s < s_best && p.x() >= -0.5 && p.x() <= 0.3 && p.y() >= -1.0) s_best = s;
      }
      depth.at<float>(v, u) = static_cast<float>((r.transpose() * (s_best * ray)).z());
    }
  }
  return depth;
}

Pose3 MakePose(double x, double y, double z, double yaw_deg) {
  Pose3 p = Pose3::Identity();
  p.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

double TranslationError(const Pose3& a, const Pose3& b) { return TranslationNorm(Between(a, b)); }
double RotationErrorDeg(const Pose3& a, const Pose3& b) {
  return RotationAngleRad(Between(a, b)) * 180.0 / M_PI;
}

class DenseRefinementTest : public ::testing::Test {
 protected:
  CameraIntrinsics k_ = Camera();
  DenseRefinementOptions options_;
  DepthConsistencyOptions consistency_;
  DynamicMask none_;
  // The camera moved 3 cm sideways and panned 0.4 deg; the start confuses part of the slide
  // with a pan (as a sparse registration on far, few static points does).
  Pose3 truth_ = MakePose(0.03, 0.0, 0.01, 0.4);
  Pose3 start_ = truth_ * MakePose(0.015, 0.0, 0.0, -0.3);
};

TEST_F(DenseRefinementTest, RecoversTheMotionFromTheRoomsSurfaces) {
  const cv::Mat ref = Render(k_, Pose3::Identity(), 0.0);
  const cv::Mat cur = Render(k_, truth_, 0.0);
  ASSERT_GT(TranslationError(start_, truth_), 0.012);
  const DenseRefinementResult r = RefineDense(ref, cur, cv::Mat(), cv::Mat(), start_, k_, options_,
                                              consistency_, none_, none_);
  ASSERT_TRUE(r.status.ok()) << r.status.reason() << " " << r.agreeing_before << " -> " << r.agreeing_after;
  EXPECT_LT(TranslationError(r.ref_cur, truth_), 0.002);
  EXPECT_LT(RotationErrorDeg(r.ref_cur, truth_), 0.05);
  EXPECT_GE(r.agreeing_after, 0.95 * r.agreeing_before);
  EXPECT_GT(r.points, 1000u);
}

TEST_F(DenseRefinementTest, AWalkerMovingAwayDoesNotPullTheEstimate) {
  // The walker covers the middle of the view and steps 8 cm away between the frames: its
  // pixels leave the static tolerance and never enter the alignment.
  const cv::Mat ref = Render(k_, Pose3::Identity(), 1.2);
  const cv::Mat cur = Render(k_, truth_, 1.28);
  const DenseRefinementResult r = RefineDense(ref, cur, cv::Mat(), cv::Mat(), start_, k_, options_,
                                              consistency_, none_, none_);
  ASSERT_TRUE(r.status.ok()) << r.status.reason() << " " << r.agreeing_before << " -> " << r.agreeing_after;
  EXPECT_LT(TranslationError(r.ref_cur, truth_), 0.003);
  EXPECT_LT(RotationErrorDeg(r.ref_cur, truth_), 0.08);
}

TEST_F(DenseRefinementTest, KeepsTheStartWhenTooFewStaticPixelsRemain) {
  const cv::Mat ref = Render(k_, Pose3::Identity(), 0.0);
  const cv::Mat cur = Render(k_, truth_, 0.0);
  // Every cell of the current image marked dynamic: nothing may be aligned.
  DynamicMask all;
  all.step_px = 4;
  all.cells = cv::Mat(k_.height_px / 4 + 1, k_.width_px / 4 + 1, CV_8UC1, cv::Scalar(255));
  const DenseRefinementResult r =
      RefineDense(ref, cur, cv::Mat(), cv::Mat(), start_, k_, options_, consistency_, all, none_);
  EXPECT_FALSE(r.status.ok());
  EXPECT_EQ(r.points, 0u);
  EXPECT_LT(TranslationError(r.ref_cur, start_), 1e-12);
}

TEST_F(DenseRefinementTest, RejectsCorrectionsBeyondTheBound) {
  const cv::Mat ref = Render(k_, Pose3::Identity(), 0.0);
  const cv::Mat cur = Render(k_, truth_, 0.0);
  options_.max_correction_m = 0.005;  // the needed correction is about 2 cm
  const DenseRefinementResult r = RefineDense(ref, cur, cv::Mat(), cv::Mat(), start_, k_, options_,
                                              consistency_, none_, none_);
  EXPECT_FALSE(r.status.ok());
  EXPECT_LT(TranslationError(r.ref_cur, start_), 1e-12);
}

}  // namespace
}  // namespace icgm
