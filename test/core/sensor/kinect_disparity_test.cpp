// The Kinect v1 raw-depth model: millimetres -> raw -> millimetres returns the depth within half
// a raw step of the inverse-depth model (the quantisation a Kinect has: 3 mm at 1 m, 49 mm at
// 4 m), depth rises with the raw value, and "no depth" maps both ways.
#include <cmath>

#include <gtest/gtest.h>

#include "core/sensor/kinect_disparity.h"

namespace icgm {
namespace {

TEST(KinectDisparity, RoundTripsWithinHalfARawStep) {
  for (int mm = kKinectMinDepthMm + 1; mm < kKinectMaxDepthMm; mm += 7) {
    const uint16_t raw = KinectMmToRaw(static_cast<uint16_t>(mm));
    ASSERT_LT(raw, kKinectRawNoDepth) << mm << " mm";
    const double z_m = mm * 1e-3;
    const double step_mm = 0.0030711016 * z_m * z_m * 1000.0;  // |d z / d raw| at z
    EXPECT_LE(std::abs(KinectRawToMm(raw) - mm), 0.5 * step_mm * 1.1 + 1.0) << mm << " mm";
  }
  EXPECT_NEAR(KinectRawToMm(0), 300, 1);
  EXPECT_NEAR(KinectRawToMm(KinectMmToRaw(1000)), 1000, 2);
}

TEST(KinectDisparity, DepthRisesWithRawAndNoDepthMapsBothWays) {
  uint16_t previous = 0;
  int valid = 0;
  for (uint16_t raw = 0; raw < 2048; ++raw) {
    const uint16_t mm = KinectRawToMm(raw);
    if (mm == 0) continue;
    EXPECT_GE(mm, previous) << raw;
    previous = mm;
    ++valid;
  }
  EXPECT_GT(valid, 1000);
  EXPECT_EQ(KinectRawToMm(kKinectRawNoDepth), 0);
  EXPECT_EQ(KinectMmToRaw(0), kKinectRawNoDepth);
  EXPECT_EQ(KinectMmToRaw(kKinectMaxDepthMm + 1), kKinectRawNoDepth);
  const uint16_t raw[3] = {0, 500, kKinectRawNoDepth};
  uint16_t mm[3];
  KinectRawToMm(raw, mm, 3);
  EXPECT_EQ(mm[0], KinectRawToMm(0));
  EXPECT_EQ(mm[1], KinectRawToMm(500));
  EXPECT_EQ(mm[2], 0);
}

}  // namespace
}  // namespace icgm
