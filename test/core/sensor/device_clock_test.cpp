// DeviceClock against a simulated device: a crystal 80 ppm fast, an unknown offset, transfer
// latencies of 2-12 ms (a few frames much later), and a device clock that restarts.
#include "core/sensor/device_clock.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace icgm {
namespace {

struct SimDevice {
  double drift = 80e-6;
  double host_at_zero_s = 1000.25;  // host time of device time 0
  std::mt19937 rng{7};
  // Host capture time of device time d_s.
  double CaptureHost(double d_s) const { return host_at_zero_s + d_s / (1.0 + drift); }
  double Latency() {
    std::uniform_real_distribution<double> u(0.002, 0.012);
    std::uniform_real_distribution<double> p(0.0, 1.0);
    return p(rng) < 0.03 ? 0.08 : u(rng);  // 3% of frames stall 80 ms
  }
};

Time Host(double s) { return Time::FromNanoseconds(static_cast<int64_t>(std::llround(s * 1e9))); }

TEST(DeviceClock, MapsCapturesWithinTheMinimumLatencyAndFindsTheDrift) {
  SimDevice dev;
  DeviceClock clock;
  double max_late_error = 0.0;
  for (int i = 0; i < 30 * 60; ++i) {  // one minute at 30 Hz
    const double d = i / 30.0 + 0.5;
    const double capture = dev.CaptureHost(d);
    const Time mapped = clock.Map(static_cast<uint64_t>(std::llround(d * 1e6)),
                                  Host(capture + dev.Latency()));
    const double error = mapped.seconds() - capture;
    // Never after the arrival; after warm-up, no later than the minimum latency plus jitter.
    EXPECT_LE(error, 0.012 + 1e-6);
    if (i > 30 * 25) max_late_error = std::max(max_late_error, std::fabs(error - 0.002));
  }
  EXPECT_LT(max_late_error, 0.0015);
  // The device runs fast: host seconds per device second are fewer, offset slope -80 ppm.
  EXPECT_NEAR(clock.drift_ppm(), -80.0, 15.0);
  EXPECT_EQ(clock.resets(), 0);
}

TEST(DeviceClock, SpacingOfMappedStampsFollowsTheDeviceNotTheArrivals) {
  SimDevice dev;
  dev.drift = 0.0;
  DeviceClock clock;
  Time previous;
  for (int i = 0; i < 30 * 30; ++i) {
    const double d = i / 30.0;
    const Time t = clock.Map(static_cast<uint64_t>(std::llround(d * 1e6)) + 1,
                             Host(dev.CaptureHost(d) + dev.Latency()));
    if (i > 30 * 3) {
      EXPECT_NEAR(DurationSeconds(t, previous), 1.0 / 30.0, 0.002) << i;
    }
    previous = t;
  }
}

TEST(DeviceClock, RestartsWhenTheDeviceClockRunsBackwards) {
  DeviceClock clock;
  for (int i = 0; i < 100; ++i) clock.Map(1000000 + i * 33333, Host(50.0 + i / 30.0 + 0.005));
  // Device re-opened: its clock starts again near zero.
  const Time t = clock.Map(500, Host(60.0));
  EXPECT_EQ(clock.resets(), 1);
  EXPECT_NEAR(t.seconds(), 60.0, 1e-6);
  const Time u = clock.Map(500 + 33333, Host(60.040));
  EXPECT_NEAR(DurationSeconds(u, t), 0.033333, 1e-4);
}

TEST(DeviceClock, RejectsBadOptions) {
  DeviceClockOptions o;
  EXPECT_TRUE(o.Validate().ok());
  o.bin_s = 0.0;
  EXPECT_FALSE(o.Validate().ok());
  o = DeviceClockOptions();
  o.max_drift_ppm = -1.0;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace icgm
