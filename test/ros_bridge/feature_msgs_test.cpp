#include "ros_bridge/feature_msgs.h"

#include <gtest/gtest.h>

namespace icgm::ros_bridge {
namespace {

TrackedFrame MakeFrame(bool binary) {
  TrackedFrame f;
  f.stamp = Time::FromSeconds(12.5);
  for (int i = 0; i < 5; ++i) {
    f.features.keypoints.emplace_back(10.f * i, 20.f + i, 7.f, 30.f * i, 0.5f, i % 3);
    f.robust.push_back(i % 2);
  }
  f.features.binary = binary;
  f.features.descriptors = binary ? cv::Mat(5, 32, CV_8U) : cv::Mat(5, 128, CV_32F);
  cv::randu(f.features.descriptors, 0, 255);
  f.matches_to_previous = {cv::DMatch(0, 3, 1.f), cv::DMatch(4, 1, 2.f)};
  f.match_kept = {1, 0};
  return f;
}

TEST(FeatureMsgsTest, RoundTripBinaryAndFloat) {
  for (bool binary : {true, false}) {
    const TrackedFrame f = MakeFrame(binary);
    const auto msg = ToFeaturesMsg(f, Time::FromSeconds(12.4), "cam", 0.08);
    TrackedFrame back;
    ASSERT_TRUE(FromFeaturesMsg(msg, &back).ok());
    EXPECT_EQ(back.stamp, f.stamp);
    ASSERT_EQ(back.features.keypoints.size(), 5u);
    EXPECT_FLOAT_EQ(back.features.keypoints[3].pt.x, 30.f);
    EXPECT_EQ(back.features.keypoints[4].octave, 1);
    EXPECT_EQ(back.robust, f.robust);
    EXPECT_EQ(back.features.binary, binary);
    EXPECT_EQ(cv::norm(back.features.descriptors, f.features.descriptors, cv::NORM_INF), 0.0);
    ASSERT_EQ(back.matches_to_previous.size(), 2u);
    EXPECT_EQ(back.matches_to_previous[1].queryIdx, 4);
    EXPECT_EQ(back.matches_to_previous[1].trainIdx, 1);
    EXPECT_EQ(back.match_kept, f.match_kept);
    EXPECT_FLOAT_EQ(msg.icgm_threshold, 0.08f);
  }
}

TEST(FeatureMsgsTest, InconsistentMessagesAreRejected) {
  auto msg = ToFeaturesMsg(MakeFrame(true), Time(), "cam", 0.08);
  TrackedFrame back;
  auto bad = msg;
  bad.descriptors.pop_back();
  EXPECT_FALSE(FromFeaturesMsg(bad, &back).ok());
  bad = msg;
  bad.matches[0].index_current = 99;
  EXPECT_FALSE(FromFeaturesMsg(bad, &back).ok());
  bad = msg;
  bad.robust.pop_back();
  EXPECT_FALSE(FromFeaturesMsg(bad, &back).ok());
}

}  // namespace
}  // namespace icgm::ros_bridge
