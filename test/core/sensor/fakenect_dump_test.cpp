// A fakenect dump written from a simulated scenario holds what fakenect replays: INDEX.txt lines
// that fakenect's file-name format parses, one-line binary PPM/PGM headers, colour equal to the
// rendered image, depth as raw 11-bit values whose millimetres are the rendered depth within the
// Kinect's quantisation, each frame on its device time (60 MHz ticks).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/sensor/fakenect_dump.h"
#include "core/sensor/kinect_disparity.h"

namespace icgm {
namespace {

TEST(FakenectDump, HoldsTheSourceFramesAsFakenectReadsThem) {
  VirtualDeviceConfig config;
  config.source = "sim";
  config.scenario = std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml";
  std::unique_ptr<VirtualFrameSource> source;
  ASSERT_TRUE(OpenVirtualFrameSource(config, &source).ok());
  const std::string dir = testing::TempDir() + "icgm_fakenect_dump_test";
  std::filesystem::remove_all(dir);
  constexpr int kFrames = 3;
  ASSERT_TRUE(WriteFakenectDump(source.get(), kFrames, dir).ok());

  std::vector<FakenectFrame> frames;
  ASSERT_TRUE(ReadFakenectDump(dir, &frames).ok());
  ASSERT_EQ(frames.size(), 2u * kFrames);
  std::ifstream index(dir + "/INDEX.txt");
  std::string line;
  size_t i = 0;
  for (const FrameEvent& e : source->events()) {
    if (e.frame >= kFrames) continue;
    ASSERT_TRUE(std::getline(index, line));
    // fakenect's own parse of a file name.
    char type = 0;
    double time_s = 0.0;
    unsigned int ticks = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%c-%lf-%u-%*s", &type, &time_s, &ticks), 3) << line;
    EXPECT_EQ(type, e.color ? 'r' : 'd');
    EXPECT_EQ(ticks, e.device_us * kKinectTicksPerUs);
    std::ifstream file(dir + "/" + line, std::ios::binary);
    std::string header;
    std::getline(file, header);
    EXPECT_EQ(header, e.color ? "P6 640 480 255" : "P5 640 480 65535");
    file.seekg(0, std::ios::end);
    EXPECT_EQ(static_cast<size_t>(file.tellg()), header.size() + 1 + 640 * 480 * (e.color ? 3 : 2));

    const FakenectFrame& f = frames[i++];
    EXPECT_EQ(f.color, e.color);
    EXPECT_EQ(f.timestamp, ticks);
    EXPECT_NEAR(f.record_time_s - frames[0].record_time_s,
                (e.device_us - source->events().front().device_us) * 1e-6, 1e-6);
    std::string error;
    const cv::Mat truth = source->Load(e, &error);
    if (e.color) {
      EXPECT_EQ(cv::norm(f.image, truth, cv::NORM_INF), 0.0);
      continue;
    }
    size_t valid = 0;
    for (int y = 0; y < truth.rows; ++y) {
      for (int x = 0; x < truth.cols; ++x) {
        const uint16_t mm = truth.at<uint16_t>(y, x);
        const uint16_t back = KinectRawToMm(f.image.at<uint16_t>(y, x));
        if (mm < kKinectMinDepthMm || mm > kKinectMaxDepthMm) {
          ASSERT_EQ(back, 0) << x << "," << y;
          continue;
        }
        const double z_m = mm * 1e-3;
        ASSERT_LE(std::abs(back - mm), 0.5 * 0.0030711016 * z_m * z_m * 1000.0 * 1.1 + 1.0)
            << x << "," << y << ": " << mm << " mm";
        ++valid;
      }
    }
    EXPECT_GT(valid, truth.total() / 2);
  }
}

TEST(FakenectDump, MissingDumpIsAnError) {
  std::vector<FakenectFrame> frames;
  const Status s = ReadFakenectDump("/nonexistent/dump", &frames);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("INDEX.txt"), std::string::npos);
}

}  // namespace
}  // namespace icgm
