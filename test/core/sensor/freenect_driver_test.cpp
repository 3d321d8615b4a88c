// The project's Kinect v1 OpenNI2 driver (freenect_driver.cpp) through OpenNI2 itself
// (OpenniCamera), on libfreenect's fakenect: a fakenect dump written from a simulated scenario
// (fakenect_dump.h) plays as a Kinect: every pair arrives on the dump's device stamps (60 MHz
// ticks -> us), colour equal to the dump's, depth equal to the dump's raw values in millimetres
// (no registration: fakenect has none). The end of the dump is reported once as the end of a
// recording (OpenNI's end-of-file device state), not as an unplugged Kinect.
//
// fakenect replaces libfreenect through the library path, which the loader reads at start-up:
// main() restarts the test with fakenect's folder first on LD_LIBRARY_PATH.
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/sensor/fakenect_dump.h"
#include "core/sensor/kinect_disparity.h"
#include "core/sensor/openni_camera.h"

namespace icgm {
namespace {

constexpr int kFrames = 15;

Time WallNow() {
  return Time::FromNanoseconds(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

bool FakenectFirst() {
  const char* path = std::getenv("LD_LIBRARY_PATH");
  return path != nullptr && std::string(path).rfind(ICGM_FAKENECT_DIR, 0) == 0;
}

TEST(FreenectDriver, PlaysAFakenectDumpThroughOpenni2) {
  if (!std::filesystem::exists(std::string(ICGM_FAKENECT_DIR) + "/libfreenect.so.0.5") ||
      !FakenectFirst()) {
    GTEST_SKIP() << "fakenect not found at " << ICGM_FAKENECT_DIR << " (libfreenect0.5)";
  }
  VirtualDeviceConfig config;
  config.source = "sim";
  config.scenario = std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml";
  std::unique_ptr<VirtualFrameSource> source;
  ASSERT_TRUE(OpenVirtualFrameSource(config, &source).ok());
  const std::string dir = std::getenv("FAKENECT_PATH");
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(WriteFakenectDump(source.get(), kFrames, dir).ok());
  std::vector<FakenectFrame> dump;
  ASSERT_TRUE(ReadFakenectDump(dir, &dump).ok());
  std::map<uint64_t, const FakenectFrame*> color_by_us, depth_by_us;
  for (const FakenectFrame& f : dump) {
    (f.color ? color_by_us : depth_by_us)[f.timestamp / kKinectTicksPerUs] = &f;
  }

  std::mutex mutex;
  std::condition_variable cv;
  std::map<uint64_t, RgbdPair> pairs;
  OpenniCameraOptions options;
  options.uri = "freenect://0";
  OpenniCamera camera;
  const Status opened = camera.Open(options, WallNow, [&](const RgbdPair& p) {
    std::lock_guard<std::mutex> lock(mutex);
    RgbdPair copy{p.color, p.depth};
    copy.color.image = p.color.image.clone();
    copy.depth.image = p.depth.image.clone();
    pairs.emplace(p.color.device_us, std::move(copy));
    cv.notify_all();
  });
  ASSERT_TRUE(opened.ok()) << opened.reason();
  EXPECT_NE(camera.description().find("Kinect v1"), std::string::npos) << camera.description();
  EXPECT_FALSE(camera.hardware_registration()) << "fakenect offers no registration";
  ASSERT_TRUE(camera.Start().ok());
  {
    std::unique_lock<std::mutex> lock(mutex);
    cv.wait_for(lock, std::chrono::seconds(20), [&] { return pairs.size() >= kFrames; });
  }
  // The end of the dump is the end of a recording (OpenNI's end-of-file state), said once, not
  // an unplugged Kinect.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!camera.end_of_recording() && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(camera.end_of_recording()) << "the end of the dump was not reported";
  // Longer than the driver's one-second failure window: an unplug would show by now.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_EQ(camera.recording_ends(), 1);
  EXPECT_FALSE(camera.disconnected()) << "the end of the dump read as an unplugged Kinect";
  const size_t pairs_at_end = camera.pairs();
  camera.Close();

  // A Kinect that is not there: one clear reason naming it.
  const OpenniCameraOptions absent_options = [&] {
    OpenniCameraOptions o = options;
    o.uri = "freenect://1";
    return o;
  }();
  OpenniCamera absent;
  const Status missing = absent.Open(absent_options, WallNow, [](const RgbdPair&) {});
  EXPECT_FALSE(missing.ok());
  EXPECT_NE(missing.reason().find("freenect://1"), std::string::npos) << missing.reason();
  EXPECT_NE(missing.reason().find("no Kinect v1 at index 1 (1 connected)"), std::string::npos)
      << missing.reason();
  EXPECT_EQ(missing.reason().find_first_of("\t\n"), std::string::npos) << "one line";
  std::printf("no second Kinect: %s\n", missing.reason().c_str());

  std::printf("%zu of %d pairs through the driver\n", pairs.size(), kFrames);
  // A loaded machine may lose a frame or two (OpenNI keeps a stream's newest frame only).
  EXPECT_GE(pairs.size(), kFrames - 2);
  EXPECT_EQ(pairs_at_end, pairs.size());
  for (const auto& [us, p] : pairs) {
    ASSERT_EQ(color_by_us.count(p.color.device_us), 1u) << "colour at " << us << " us not in the dump";
    ASSERT_EQ(depth_by_us.count(p.depth.device_us), 1u) << "depth at " << p.depth.device_us << " us";
    cv::Mat bgr;
    cv::cvtColor(color_by_us[p.color.device_us]->image, bgr, cv::COLOR_RGB2BGR);
    EXPECT_EQ(cv::norm(p.color.image, bgr, cv::NORM_INF), 0.0) << us;
    const cv::Mat& raw = depth_by_us[p.depth.device_us]->image;
    cv::Mat mm(raw.size(), CV_16UC1);
    KinectRawToMm(raw.ptr<uint16_t>(), mm.ptr<uint16_t>(), raw.total());
    EXPECT_EQ(cv::norm(p.depth.image, mm, cv::NORM_INF), 0.0) << us;
    EXPECT_GT(cv::countNonZero(p.depth.image), static_cast<int>(raw.total() / 2)) << us;
  }
  // The pairs keep the dump's spacing (100 ms between rendered frames).
  if (pairs.size() >= 2) {
    const double dt_us = static_cast<double>(std::prev(pairs.end())->first - pairs.begin()->first);
    const double dt_truth = static_cast<double>(std::prev(color_by_us.end())->first -
                                                color_by_us.begin()->first);
    EXPECT_LE(dt_us, dt_truth);
    EXPECT_GT(dt_us, 0.5 * dt_truth);
  }
}

}  // namespace
}  // namespace icgm

// Restarts with fakenect first on the library path and a dump folder for it (see above).
int main(int argc, char** argv) {
  if (!icgm::FakenectFirst()) {
    const char* old = std::getenv("LD_LIBRARY_PATH");
    const std::string path = std::string(ICGM_FAKENECT_DIR) + (old != nullptr && *old ? ":" + std::string(old) : "");
    setenv("LD_LIBRARY_PATH", path.c_str(), 1);
    const std::string dump = testing::TempDir() + "icgm_freenect_test_" + std::to_string(getpid());
    setenv("FAKENECT_PATH", dump.c_str(), 1);
    if (std::filesystem::exists(std::string(ICGM_FAKENECT_DIR) + "/libfreenect.so.0.5")) {
      execv("/proc/self/exe", argv);
    }
  }
  testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  if (const char* dump = std::getenv("FAKENECT_PATH")) std::filesystem::remove_all(dump);
  return result;
}
