// DeviceClock against a simulated device: a crystal 80 ppm fast, an unknown offset, transfer
// latencies of 2-12 ms (a few frames much later), and a device clock that restarts.
#include "core/sensor/device_clock.h"
#include "core/sensor/openni_camera.h"

#include <cmath>
#include <random>
#include <vector>

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
    const Time mapped =
        clock.Map(static_cast<uint64_t>(std::llround(d * 1e6)), Host(capture + dev.Latency()));
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

// A loaded host: arrivals late by up to seconds, bursts, stale host clock readings and the two
// streams read out of order. The ground truth is the simulated capture instant; mapped stamps must
// rise strictly with the device clock, keep its spacing, and not be bent by the late arrivals.
struct MappedFrame {
  double capture_s;  // host time of the capture (ground truth)
  uint64_t device_us;
  double mapped_s;
};

// Checks strict monotonicity and spacing against the device clock over consecutive frames of
// increasing device stamps: each mapped interval within `spacing_fraction` of the device interval.
void ExpectMonotonicOnDeviceSpacing(const std::vector<MappedFrame>& frames,
                                    double spacing_fraction) {
  for (size_t i = 1; i < frames.size(); ++i) {
    const double device_dt = (frames[i].device_us - frames[i - 1].device_us) * 1e-6;
    const double mapped_dt = frames[i].mapped_s - frames[i - 1].mapped_s;
    ASSERT_GT(mapped_dt, 0.0) << "stamp " << i << " not after stamp " << i - 1;
    EXPECT_NEAR(mapped_dt, device_dt, spacing_fraction * device_dt + 2e-6) << i;
  }
}

// The most the mapping may stretch or shrink an interval: its slew plus the largest drift.
double MaxSpacingChange(const DeviceClockOptions& o) { return o.max_slew + o.max_drift_ppm * 1e-6; }

TEST(DeviceClock, BacklogAtStartUpNeitherSendsStampsBackwardsNorRestarts) {
  // The frames of the first 1.5 s reach the host `late_s` late (a busy machine), the backlog
  // is then worked off (a frame every 1 ms, in order) and frames arrive 2-12 ms after capture.
  for (double late_s : {0.3, 0.8, 2.5}) {
    SCOPED_TRACE(late_s);
    SimDevice dev;
    DeviceClock clock;
    std::vector<MappedFrame> frames;
    double previous_arrival = 0.0;
    for (int i = 0; i < 30 * 40; ++i) {
      const double d = i / 30.0 + 0.5;
      const double capture = dev.CaptureHost(d);
      const double arrival =
          std::max(previous_arrival + 0.001, capture + dev.Latency() + (d < 2.0 ? late_s : 0.0));
      previous_arrival = arrival;
      const uint64_t device_us = static_cast<uint64_t>(std::llround(d * 1e6));
      frames.push_back({capture, device_us, clock.Map(device_us, Host(arrival)).seconds()});
    }
    EXPECT_EQ(clock.resets(), 0);
    ExpectMonotonicOnDeviceSpacing(frames, MaxSpacingChange(clock.options()));
    // Caught up: within the minimum latency plus jitter of the captures.
    for (size_t i = 30 * 35; i < frames.size(); ++i) {
      EXPECT_NEAR(frames[i].mapped_s - frames[i].capture_s, 0.002, 0.004) << i;
    }
  }
}

TEST(DeviceClock, StallOfSecondsIsDeliveredOnTheDeviceSpacing) {
  // After 5 s, the host stalls for 3 s; the frames captured meanwhile arrive in one burst.
  SimDevice dev;
  DeviceClock clock;
  std::vector<MappedFrame> frames;
  const double stall_end = dev.CaptureHost(8.0) + 0.01;
  for (int i = 0; i < 30 * 20; ++i) {
    const double d = i / 30.0;
    const double capture = dev.CaptureHost(d);
    double arrival = capture + dev.Latency();
    if (d >= 5.0 && d < 8.0) arrival = stall_end + i * 1e-5;
    const uint64_t device_us = static_cast<uint64_t>(std::llround(d * 1e6)) + 1;
    frames.push_back({capture, device_us, clock.Map(device_us, Host(arrival)).seconds()});
  }
  EXPECT_EQ(clock.resets(), 0);
  // From 4 s (the estimate settled) through the stall and after it.
  ExpectMonotonicOnDeviceSpacing(std::vector<MappedFrame>(frames.begin() + 30 * 4, frames.end()),
                                 0.06);
  for (size_t i = 30 * 2; i < frames.size(); ++i) {
    EXPECT_NEAR(frames[i].mapped_s - frames[i].capture_s, 0.002, 0.004) << i;
  }
  EXPECT_NEAR(clock.drift_ppm(), -80.0, 40.0);
}

TEST(DeviceClock, HostClockReadStaleDoesNotPullStampsEarly) {
  // The host clock, read on arrival, sometimes lags (ROS simulated time delivered late): for
  // 200 ms every 2 s, arrivals read the time at the start of the lag, before their captures.
  SimDevice dev;
  dev.drift = 0.0;
  DeviceClock clock;
  std::vector<MappedFrame> frames;
  for (int i = 0; i < 30 * 20; ++i) {
    const double d = i / 30.0;
    const double capture = dev.CaptureHost(d);
    double arrival = capture + dev.Latency();
    const double phase = std::fmod(d, 2.0);
    if (d > 1.0 && phase >= 1.5 && phase < 1.7) arrival = dev.CaptureHost(d - (phase - 1.5));
    const uint64_t device_us = static_cast<uint64_t>(std::llround(d * 1e6)) + 1;
    frames.push_back({capture, device_us, clock.Map(device_us, Host(arrival)).seconds()});
  }
  EXPECT_EQ(clock.resets(), 0);
  ExpectMonotonicOnDeviceSpacing(frames, MaxSpacingChange(clock.options()));
  for (size_t i = 30; i < frames.size(); ++i) {
    EXPECT_NEAR(frames[i].mapped_s - frames[i].capture_s, 0.002, 0.004) << i;
  }
}

TEST(DeviceClock, ColourAndDepthReadOutOfOrderShareOneMapping) {
  // Two streams on one device clock: depth captured 15 ms before colour (as TUM's Kinect), each
  // read by its own thread; on a loaded host a depth frame is sometimes read after the colour
  // frame of its instant, so the device stamps seen by the clock step back.
  SimDevice dev;
  DeviceClock clock;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<MappedFrame> color, depth;
  struct Pending {
    bool is_color;
    double capture;
    uint64_t device_us;
    double arrival;
  };
  for (int i = 0; i < 30 * 20; ++i) {
    const double d = i / 30.0 + 1.0;
    const double dd = d - 0.015;
    std::vector<Pending> batch{
        {false, dev.CaptureHost(dd), static_cast<uint64_t>(std::llround(dd * 1e6)), 0.0},
        {true, dev.CaptureHost(d), static_cast<uint64_t>(std::llround(d * 1e6)), 0.0}};
    batch[0].arrival = batch[0].capture + dev.Latency();
    batch[1].arrival = batch[1].capture + dev.Latency();
    // Depth read late, after the colour frame.
    const bool late_depth = u(rng) < 0.2;
    if (late_depth) {
      batch[0].arrival = batch[1].arrival + 0.001;
      std::swap(batch[0], batch[1]);
    }
    for (const Pending& p : batch) {
      const double mapped = clock.Map(p.device_us, Host(p.arrival)).seconds();
      (p.is_color ? color : depth).push_back({p.capture, p.device_us, mapped});
    }
  }
  EXPECT_EQ(clock.resets(), 0);
  ExpectMonotonicOnDeviceSpacing(color, 0.06);
  ExpectMonotonicOnDeviceSpacing(depth, 0.06);
  for (size_t i = 30; i < color.size(); ++i) {
    EXPECT_NEAR(color[i].mapped_s - color[i].capture_s, 0.002, 0.004) << i;
    EXPECT_NEAR(depth[i].mapped_s - depth[i].capture_s, 0.002, 0.004) << i;
    // One instant's pair keeps the device's 15 ms between its frames.
    EXPECT_NEAR(color[i].mapped_s - depth[i].mapped_s, 0.015, 1e-3) << i;
  }
}

TEST(DeviceClock, ShortRecordingOnALoadedHostKeepsTheSpacingBoundFromItsFirstFrames) {
  // A two-second recording at 10 Hz played on a loaded host (as a fakenect dump through the
  // Kinect driver): colour and depth of one instant on one device stamp, each read by its own
  // thread and delayed by the scheduler by 2-40 ms, so few arrivals confirm each other and the
  // estimate moves while the mapping is young. The bound holds from the first interval.
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    SCOPED_TRACE(seed);
    SimDevice dev;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> delay(0.002, 0.040);
    DeviceClock clock;
    std::vector<MappedFrame> color, depth;
    for (int i = 0; i < 20; ++i) {
      const double d = 0.1 * i + 0.05;
      const double capture = dev.CaptureHost(d);
      const uint64_t device_us = static_cast<uint64_t>(std::llround(d * 1e6));
      const double color_arrival = capture + delay(rng), depth_arrival = capture + delay(rng);
      const bool color_first = color_arrival <= depth_arrival;
      for (bool is_color : {color_first, !color_first}) {
        const double mapped =
            clock.Map(device_us, Host(is_color ? color_arrival : depth_arrival)).seconds();
        (is_color ? color : depth).push_back({capture, device_us, mapped});
      }
    }
    EXPECT_EQ(clock.resets(), 0);
    ExpectMonotonicOnDeviceSpacing(color, MaxSpacingChange(clock.options()));
    for (size_t i = 0; i < color.size(); ++i) {
      EXPECT_EQ(color[i].mapped_s, depth[i].mapped_s) << "one instant, one stamp: " << i;
    }
  }
}

TEST(OpenniCameraOptions, ARecordingThatDoesNotExistIsRefusedUpFront) {
  OpenniCameraOptions o;
  EXPECT_TRUE(o.Validate().ok());
  o.uri = "/nonexistent_folder/session.oni";
  const Status s = o.Validate();
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("recording '/nonexistent_folder/session.oni' does not exist"),
            std::string::npos)
      << s.reason();
  o.wait_for_recording = true;  // a recording still being written: opened once it appears
  EXPECT_TRUE(o.Validate().ok());
  o.wait_for_recording = false;
  o.uri = "icgm-virtual://tum?dir=/somewhere";  // a device URI: opened (and retried) later
  EXPECT_TRUE(o.Validate().ok());
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
