#include "core/mono/mono_input_queue.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

Time At(double s) { return Time::FromSeconds(s); }
Pose3 AtX(double x) {
  Pose3 p = Pose3::Identity();
  p.translation().x() = x;
  return p;
}

TEST(MonoInputQueueTest, WithoutWheelsImagesLeaveAtOnceInOrder) {
  MonoInputQueue q(false, 20);
  q.AddImage(At(1.0), cv::Mat(2, 2, CV_8UC1, cv::Scalar(1)));
  q.AddWheel(At(0.5), AtX(1.0));  // ignored
  q.AddImage(At(2.0), cv::Mat(2, 2, CV_8UC1, cv::Scalar(2)));
  MonoInput in;
  ASSERT_TRUE(q.Pop(&in));
  EXPECT_EQ(in.stamp, At(1.0));
  EXPECT_EQ(in.image.at<uint8_t>(0, 0), 1);
  EXPECT_TRUE(in.wheel.empty());
  ASSERT_TRUE(q.Pop(&in));
  EXPECT_EQ(in.stamp, At(2.0));
  EXPECT_FALSE(q.Pop(&in));
}

TEST(MonoInputQueueTest, ImageWaitsForTheWheelSampleCoveringItsStamp) {
  MonoInputQueue q(true, 20);
  q.AddWheel(At(0.9), AtX(0.9));
  q.AddImage(At(1.0), cv::Mat(2, 2, CV_8UC1));
  MonoInput in;
  EXPECT_FALSE(q.Pop(&in));  // no sample at or after 1.0 yet
  q.AddWheel(At(1.0), AtX(1.0));
  q.AddWheel(At(1.1), AtX(1.1));
  ASSERT_TRUE(q.Pop(&in));
  ASSERT_EQ(in.wheel.size(), 2u);  // up to the stamp, the later one stays for the next image
  EXPECT_EQ(in.wheel[0].stamp, At(0.9));
  EXPECT_EQ(in.wheel[1].stamp, At(1.0));
  EXPECT_DOUBLE_EQ(in.wheel[1].pose.translation().x(), 1.0);
  q.AddImage(At(1.2), cv::Mat(2, 2, CV_8UC1));
  EXPECT_FALSE(q.Pop(&in));
  q.AddWheel(At(1.25), AtX(1.25));
  ASSERT_TRUE(q.Pop(&in));
  ASSERT_EQ(in.wheel.size(), 1u);
  EXPECT_EQ(in.wheel[0].stamp, At(1.1));
}

TEST(MonoInputQueueTest, StoppedWheelsReleaseImagesAfterTheWaitBound) {
  MonoInputQueue q(true, 3);
  MonoInput in;
  for (int i = 0; i < 3; ++i) {
    q.AddImage(At(1.0 + i), cv::Mat(2, 2, CV_8UC1));
    EXPECT_FALSE(q.Pop(&in));
  }
  q.AddImage(At(4.0), cv::Mat(2, 2, CV_8UC1));  // 4 images without a wheel sample
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.Pop(&in));
    EXPECT_EQ(in.stamp, At(1.0 + i));
  }
  EXPECT_EQ(q.num_images(), 0u);
  q.AddImage(At(5.0), cv::Mat(2, 2, CV_8UC1));
  EXPECT_EQ(q.DropImages(), 1u);
  EXPECT_FALSE(q.Pop(&in));
}

}  // namespace
}  // namespace icgm
