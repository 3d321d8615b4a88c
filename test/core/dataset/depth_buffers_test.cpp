#include "core/dataset/depth_buffers.h"

#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "core/dataset/depth_image.h"

namespace icgm {
namespace {

cv::Mat RandomMillimetres(int rows, int cols, uint64_t seed) {
  cv::Mat raw(rows, cols, CV_16UC1);
  cv::RNG rng(seed);
  rng.fill(raw, cv::RNG::UNIFORM, 0, 8000);
  return raw;
}

// Bit-equal, NaN where the other is NaN.
bool SameDepth(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  for (int r = 0; r < a.rows; ++r) {
    for (int c = 0; c < a.cols; ++c) {
      const float x = a.at<float>(r, c), y = b.at<float>(r, c);
      if (!(x == y || (std::isnan(x) && std::isnan(y)))) return false;
    }
  }
  return true;
}

TEST(DepthBuffersTest, ReusesOnlyReleasedBuffers) {
  DepthBuffers buffers(2);
  cv::Mat a = buffers.Take(48, 64);
  ASSERT_EQ(a.type(), CV_32FC1);
  ASSERT_EQ(a.size(), cv::Size(64, 48));
  const uchar* const a_pixels = a.data;
  cv::Mat b = buffers.Take(48, 64);  // a is still held (a queued frame): another buffer
  const uchar* const b_pixels = b.data;
  EXPECT_NE(b_pixels, a_pixels);
  const cv::Mat c = buffers.Take(48, 64);  // both held, capacity reached: a third, not kept
  EXPECT_NE(c.data, a_pixels);
  EXPECT_NE(c.data, b_pixels);
  EXPECT_EQ(buffers.size(), 2u);
  // A shallow copy (a keyframe sharing its frame's depth) keeps a's pixels held.
  cv::Mat keyframe_depth = a;
  a.release();
  const cv::Mat d = buffers.Take(48, 64);
  EXPECT_NE(d.data, a_pixels);
  EXPECT_NE(d.data, b_pixels);
  // Released by everyone: handed out again.
  b.release();
  cv::Mat e = buffers.Take(48, 64);
  EXPECT_EQ(e.data, b_pixels);
  keyframe_depth.release();
  cv::Mat f = buffers.Take(48, 64);
  EXPECT_EQ(f.data, a_pixels);
  // Another image size: the released buffer is reallocated to it.
  f.release();
  const cv::Mat g = buffers.Take(24, 32);
  EXPECT_EQ(g.size(), cv::Size(32, 24));
  EXPECT_EQ(buffers.size(), 2u);
}

// Converting into a reused buffer gives what a new image gets, in the buffer's own pixels.
TEST(DepthBuffersTest, ConversionIntoABufferEqualsANewImage) {
  DepthBuffers buffers(1);
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const cv::Mat raw = RandomMillimetres(48, 64, seed);
    cv::Mat depth = buffers.Take(raw.rows, raw.cols);
    const uchar* const pixels = depth.data;
    ASSERT_TRUE(ToMetricDepth(raw, 1000.0, &depth, 0.3, 6.0));
    EXPECT_EQ(depth.data, pixels);
    EXPECT_TRUE(SameDepth(depth, ToMetricDepth(raw, 1000.0, 0.3, 6.0))) << "seed " << seed;
  }
  // A refused input empties the buffer handle (the pool keeps its pixels).
  cv::Mat depth = buffers.Take(4, 4);
  EXPECT_FALSE(ToMetricDepth(cv::Mat(4, 4, CV_8UC1, cv::Scalar(3)), 1000.0, &depth));
  EXPECT_TRUE(depth.empty());
}

}  // namespace
}  // namespace icgm
