// Room keypoints of a wall 3 m away seen from two poses: with the true motion every one repeats
// and its match is exact; a common image shift of the second frame's keypoints (a ground truth
// off by a small pan) is found and removed; near keypoints, keypoints on a walker's mask and
// ones hidden in the second frame do not count; a wrong match is not correct.
#include "core/eval/keypoint_repeatability.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

class KeypointRepeatabilityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    k_.fx_px = k_.fy_px = 500;
    k_.cx_px = 320;
    k_.cy_px = 240;
    b_from_a_ = Pose3::Identity();
    b_from_a_.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()).matrix();
    b_from_a_.translation() = Eigen::Vector3d(0.01, 0.0, 0.0);
    depth_a_ = cv::Mat(480, 640, CV_32F, cv::Scalar(3.0f));
    depth_b_ = depth_a_.clone();
    for (int i = 0; i < 10; ++i) {
      const cv::Point2f p(100.0f + 40.0f * i, 150.0f + 15.0f * i);
      a_.emplace_back(p, 10.0f);
      const Eigen::Vector3d in_b = b_from_a_ * k_.BackProject(p.x, p.y, 3.0);
      // b's wall is a plane at 3 m in a's frame; b's depth map holds its depth in b's frame.
      const Eigen::Vector2d uv = k_.Project(in_b);
      b_.emplace_back(cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y())), 10.0f);
      depth_b_.at<float>(static_cast<int>(std::lround(uv.y())),
                         static_cast<int>(std::lround(uv.x()))) = static_cast<float>(in_b.z());
      matches_.emplace_back(i, i, 0.0f);
    }
  }

  KeypointRepeatabilityStats Measure(const cv::Mat& mask_a = cv::Mat()) const {
    return MeasureKeypointRepeatability(a_, depth_a_, mask_a, b_, depth_b_, cv::Mat(), matches_, k_,
                                        b_from_a_);
  }

  CameraIntrinsics k_;
  Pose3 b_from_a_;
  cv::Mat depth_a_, depth_b_;
  std::vector<cv::KeyPoint> a_, b_;
  std::vector<cv::DMatch> matches_;
};

TEST_F(KeypointRepeatabilityTest, TrueMotionRepeatsEveryRoomKeypointExactly) {
  const KeypointRepeatabilityStats s = Measure();
  EXPECT_EQ(s.room_keypoints, 10);
  EXPECT_EQ(s.repeated_1px, 10);
  EXPECT_EQ(s.matched, 10);
  EXPECT_EQ(s.matched_correct, 10);
  ASSERT_EQ(s.correct_errors_px.size(), 10u);
  for (double e : s.correct_errors_px) EXPECT_LT(e, 1e-3);
  EXPECT_LT(s.common_shift_px.norm(), 1e-3);
  EXPECT_EQ(s.shift_support, 10);
}

TEST_F(KeypointRepeatabilityTest, CommonShiftIsFoundAndRemoved) {
  for (cv::KeyPoint& k : b_) k.pt += cv::Point2f(2.0f, -1.0f);
  const KeypointRepeatabilityStats s = Measure();
  EXPECT_NEAR(s.common_shift_px.x(), 2.0, 1e-3);
  EXPECT_NEAR(s.common_shift_px.y(), -1.0, 1e-3);
  EXPECT_EQ(s.repeated_1px, 10);
  EXPECT_EQ(s.matched_correct, 10);
  for (double e : s.correct_errors_px) EXPECT_LT(e, 1e-3);
  for (double e : s.raw_errors_px) EXPECT_NEAR(e, std::sqrt(5.0), 1e-3);
  // One keypoint 1.5 px off the common shift: repeated within 2 px, not within 1 px.
  b_[3].pt += cv::Point2f(1.5f, 0.0f);
  const KeypointRepeatabilityStats t = Measure();
  EXPECT_EQ(t.repeated_1px, 9);
  EXPECT_EQ(t.repeated_2px, 10);
  EXPECT_NEAR(t.correct_errors_px[3], 1.5, 1e-3);
}

TEST_F(KeypointRepeatabilityTest, NearMaskedAndHiddenKeypointsDoNotCount) {
  depth_a_.at<float>(static_cast<int>(a_[0].pt.y), static_cast<int>(a_[0].pt.x)) = 1.2f;  // near
  cv::Mat mask_a(480, 640, CV_8U, cv::Scalar(0));
  mask_a.at<uint8_t>(static_cast<int>(a_[1].pt.y), static_cast<int>(a_[1].pt.x)) = 255;  // walker
  // Something steps in front of keypoint 2 in b.
  depth_b_.at<float>(static_cast<int>(std::lround(b_[2].pt.y)),
                     static_cast<int>(std::lround(b_[2].pt.x))) = 1.0f;
  const KeypointRepeatabilityStats s = Measure(mask_a);
  EXPECT_EQ(s.room_keypoints, 7);
  EXPECT_EQ(s.matched, 7);
}

TEST_F(KeypointRepeatabilityTest, WrongMatchIsNotCorrect) {
  matches_[4].trainIdx = 8;  // a different keypoint, about 170 px away
  const KeypointRepeatabilityStats s = Measure();
  EXPECT_EQ(s.matched, 10);
  EXPECT_EQ(s.matched_correct, 9);
  EXPECT_EQ(s.repeated_1px, 10);  // detection does not depend on the match
}

}  // namespace
}  // namespace icgm
