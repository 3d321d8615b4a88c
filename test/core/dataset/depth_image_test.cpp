#include "core/dataset/depth_image.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "temp_dir.h"

namespace icgm {
namespace {

TEST(DepthImageTest, ScaledUint16ToMetres) {
  cv::Mat raw(2, 3, CV_16UC1);
  raw.at<uint16_t>(0, 0) = 5000;   // 1 m at TUM scale
  raw.at<uint16_t>(0, 1) = 0;      // no measurement
  raw.at<uint16_t>(0, 2) = 65535;  // 13.107 m
  raw.at<uint16_t>(1, 0) = 1;
  raw.at<uint16_t>(1, 1) = 12500;
  raw.at<uint16_t>(1, 2) = 2500;
  const cv::Mat d = ToMetricDepth(raw, 5000.0);
  ASSERT_EQ(d.type(), CV_32FC1);
  ASSERT_EQ(d.size(), raw.size());
  EXPECT_FLOAT_EQ(d.at<float>(0, 0), 1.0f);
  EXPECT_TRUE(std::isnan(d.at<float>(0, 1)));
  EXPECT_FLOAT_EQ(d.at<float>(0, 2), 65535.0f / 5000.0f);
  EXPECT_FLOAT_EQ(d.at<float>(1, 0), 0.0002f);
  EXPECT_FLOAT_EQ(d.at<float>(1, 1), 2.5f);
  EXPECT_EQ(CountValidDepth(d), 5);
  // Millimetre images with scale 1000.
  EXPECT_FLOAT_EQ(ToMetricDepth(raw, 1000.0).at<float>(1, 1), 12.5f);
}

TEST(DepthImageTest, RangeLimitsInvalidate) {
  cv::Mat raw(1, 4, CV_16UC1);
  raw.at<uint16_t>(0, 0) = 1000;   // 0.2 m
  raw.at<uint16_t>(0, 1) = 2500;   // 0.5 m (limit, kept)
  raw.at<uint16_t>(0, 2) = 20000;  // 4 m (limit, kept)
  raw.at<uint16_t>(0, 3) = 30000;  // 6 m
  const cv::Mat d = ToMetricDepth(raw, 5000.0, 0.5, 4.0);
  EXPECT_TRUE(std::isnan(d.at<float>(0, 0)));
  EXPECT_FLOAT_EQ(d.at<float>(0, 1), 0.5f);
  EXPECT_FLOAT_EQ(d.at<float>(0, 2), 4.0f);
  EXPECT_TRUE(std::isnan(d.at<float>(0, 3)));
}

TEST(DepthImageTest, EveryUint16ValueAsTheDivisionGivesIt) {
  // All 65536 raw values, with scales and ranges changing between calls (the conversion keeps
  // a table per scale and range): each pixel exactly raw / scale as a float, or NaN.
  cv::Mat raw(256, 256, CV_16UC1);
  for (int v = 0; v < 65536; ++v) raw.at<uint16_t>(v / 256, v % 256) = static_cast<uint16_t>(v);
  struct Case {
    double scale, min_m, max_m;
  };
  for (const Case& k : {Case{1000.0, 0.0, 1e9}, Case{5000.0, 0.5, 4.0}, Case{1000.0, 0.0, 1e9},
                        Case{1000.0, 0.3, 8.0}, Case{1035.0, 0.0, 1e9}}) {
    const cv::Mat d = ToMetricDepth(raw, k.scale, k.min_m, k.max_m);
    ASSERT_EQ(d.type(), CV_32FC1);
    for (int v = 0; v < 65536; ++v) {
      const float expected = static_cast<float>(v / k.scale);
      const float got = d.at<float>(v / 256, v % 256);
      if (v == 0 || expected < k.min_m || expected > k.max_m) {
        ASSERT_TRUE(std::isnan(got)) << "raw " << v << " scale " << k.scale;
      } else {
        ASSERT_EQ(got, expected) << "raw " << v << " scale " << k.scale;
      }
    }
  }
}

TEST(DepthImageTest, FloatIsAlreadyMetres) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  cv::Mat raw = (cv::Mat_<float>(1, 6) << 1.25f, nan, inf, -1.0f, 0.0f, 7.5f);
  for (double scale : {5000.0, 1.0, 0.0}) {  // scale is ignored for float depth
    const cv::Mat d = ToMetricDepth(raw, scale, 0.0, 5.0);
    ASSERT_EQ(d.type(), CV_32FC1);
    EXPECT_FLOAT_EQ(d.at<float>(0, 0), 1.25f);
    for (int c = 1; c < 6; ++c) EXPECT_TRUE(std::isnan(d.at<float>(0, c))) << c;
    EXPECT_EQ(CountValidDepth(d), 1);
  }
}

TEST(DepthImageTest, UnsupportedInputGivesEmpty) {
  EXPECT_TRUE(ToMetricDepth(cv::Mat(), 5000.0).empty());
  EXPECT_TRUE(ToMetricDepth(cv::Mat(2, 2, CV_8UC1, cv::Scalar(3)), 5000.0).empty());
  EXPECT_TRUE(ToMetricDepth(cv::Mat(2, 2, CV_16UC3, cv::Scalar(3)), 5000.0).empty());
  EXPECT_TRUE(ToMetricDepth(cv::Mat(2, 2, CV_64FC1, cv::Scalar(3)), 5000.0).empty());
  EXPECT_TRUE(ToMetricDepth(cv::Mat(2, 2, CV_16UC1, cv::Scalar(3)), 0.0).empty());
  EXPECT_TRUE(ToMetricDepth(cv::Mat(2, 2, CV_16UC1, cv::Scalar(3)), -5.0).empty());
  EXPECT_TRUE(ToMetricDepth(cv::Mat(2, 2, CV_16UC1, cv::Scalar(3)), 5000.0, 2.0, 1.0).empty());
  EXPECT_EQ(CountValidDepth(cv::Mat(2, 2, CV_8UC1)), 0);
}

TEST(DepthImageTest, NonContiguousRoiAndPngRoundTrip) {
  cv::Mat raw(40, 50, CV_16UC1);
  for (int r = 0; r < raw.rows; ++r) {
    for (int c = 0; c < raw.cols; ++c) raw.at<uint16_t>(r, c) = static_cast<uint16_t>(r * 100 + c);
  }
  const cv::Mat roi = raw(cv::Rect(5, 7, 20, 10));
  const cv::Mat d = ToMetricDepth(roi, 1000.0);
  ASSERT_EQ(d.size(), roi.size());
  EXPECT_FLOAT_EQ(d.at<float>(3, 4), ((7 + 3) * 100 + 5 + 4) / 1000.0f);

  testing::TempDir dir;
  const std::string path = dir.File("depth.png");
  ASSERT_TRUE(cv::imwrite(path, raw));
  const cv::Mat back = cv::imread(path, cv::IMREAD_UNCHANGED);
  const cv::Mat d2 = ToMetricDepth(back, 1000.0);
  EXPECT_FLOAT_EQ(d2.at<float>(39, 49), 3949 / 1000.0f);
  EXPECT_TRUE(std::isnan(d2.at<float>(0, 0)));
}

}  // namespace
}  // namespace icgm
