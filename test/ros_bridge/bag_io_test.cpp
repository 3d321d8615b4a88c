#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "ros_bridge/bag_reader.h"
#include "ros_bridge/bag_writer.h"
#include "ros_bridge/topics.h"

namespace icgm::ros_bridge {
namespace {

namespace fs = std::filesystem;

class BagIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("icgm_bag_io_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `n` frames 1/30 s apart; depth value of frame i is (1000 + i) mm, stamped
  // `depth_delay_s` after its colour image.
  std::string WriteBag(int n, bool with_info = true, bool reverse_last = false,
                       bool mask_after_depth = false, double depth_delay_s = 0.0) {
    const std::string path = (dir_ / "test.bag").string();
    BagWriter w(path);
    CameraIntrinsics k;
    w.WriteTransform(Time::FromSeconds(1), topics::kBaseFrame, topics::kCameraFrame,
                     MakePose({0.1, 0, 1}, Quat::Identity()), true);
    for (int i = 0; i < n; ++i) {
      Time t = Time::FromSeconds(1 + i / 30.0);
      if (reverse_last && i == n - 1) t = Time::FromSeconds(1.0);
      cv::Mat bgr(48, 64, CV_8UC3, cv::Scalar(i, 2 * i, 3));
      cv::Mat depth(48, 64, CV_16UC1, cv::Scalar(1000 + i));
      w.WriteImage(topics::kRgbImage, topics::kCameraFrame, t, bgr, "bgr8");
      w.WriteImage(topics::kDepthImageMm, topics::kCameraFrame,
                   Time::FromSeconds(t.seconds() + depth_delay_s), depth, "16UC1");
      if (mask_after_depth) {
        w.WriteImage(topics::kDynamicMask, topics::kCameraFrame, t,
                     cv::Mat(48, 64, CV_8UC1, cv::Scalar(10 * i)), "mono8");
      }
      if (with_info) w.WriteCameraInfo(topics::kRgbInfo, topics::kCameraFrame, t, k);
      w.WriteOdometry(topics::kWheelOdom, t, topics::kOdomFrame, topics::kBaseFrame,
                      MakePose({0.01 * i, 0, 0}, Quat::Identity()), {0.3, 0, 0}, {0, 0, 0});
      w.WritePose(topics::kGroundTruthPose, t, topics::kWorldFrame,
                  MakePose({0.02 * i, 0, 0}, Quat::Identity()));
    }
    w.Close();
    return path;
  }

  fs::path dir_;
};

TEST_F(BagIoTest, WrittenFramesReadBackSynchronised) {
  const std::string path = WriteBag(5);
  BagReader reader(path);
  ASSERT_NE(reader.FindTopic(topics::kRgbImage), nullptr);
  EXPECT_EQ(reader.FindTopic(topics::kRgbImage)->message_count, 5u);
  EXPECT_EQ(reader.FindTopic(topics::kRgbImage)->datatype, "sensor_msgs/Image");
  RgbdBagStream stream(reader, RgbdBagTopics{});
  EXPECT_EQ(stream.expected_frames(), 5u);
  ASSERT_TRUE(stream.base_to_camera().has_value());
  EXPECT_NEAR(stream.base_to_camera()->translation().z(), 1.0, 1e-12);
  EXPECT_EQ(stream.wheel_odometry().size(), 5u);
  EXPECT_EQ(stream.ground_truth().size(), 5u);
  EXPECT_NEAR(stream.ground_truth().back().pose.translation().x(), 0.08, 1e-12);
  RgbdBagFrame f;
  int count = 0;
  while (stream.Next(&f)) {
    EXPECT_EQ(f.bgr.at<cv::Vec3b>(3, 3)[0], count);
    EXPECT_NEAR(f.depth_m.at<float>(3, 3), (1000 + count) / 1000.0, 1e-6);
    ++count;
  }
  EXPECT_TRUE(stream.status().ok()) << stream.status().reason();
  EXPECT_EQ(count, 5);
}

// rosbag play latches a topic whose recorded connection says so: /tf_static must, or nodes
// subscribing after play's start-up delay never get the extrinsic.
TEST_F(BagIoTest, StaticTransformIsRecordedLatchedAndExtrinsicReadsBack) {
  const std::string path = WriteBag(3);
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(std::string(topics::kTfStatic)));
  ASSERT_EQ(view.getConnections().size(), 1u);
  const auto& header = *view.getConnections()[0]->header;
  ASSERT_TRUE(header.count("latching"));
  EXPECT_EQ(header.at("latching"), "1");
  EXPECT_EQ(header.at("type"), "tf2_msgs/TFMessage");
  bag.close();
  BagReader reader(path);
  RgbdBagStream stream(reader, RgbdBagTopics{});
  ASSERT_TRUE(stream.base_to_camera().has_value());
  EXPECT_NEAR(stream.base_to_camera()->translation().x(), 0.1, 1e-12);
}

TEST_F(BagIoTest, FramesCarryTheirDepthStamp) {
  // Depth 8 ms behind colour (within the pairing tolerance): paired, and its own stamp kept
  // for the front end's depth timing compensation.
  BagReader reader(WriteBag(4, true, false, false, /*depth_delay_s=*/0.008));
  RgbdBagStream stream(reader, RgbdBagTopics{});
  RgbdBagFrame f;
  int count = 0;
  while (stream.Next(&f)) {
    EXPECT_NEAR(DurationSeconds(f.depth_stamp, f.stamp), 0.008, 1e-6) << "frame " << count;
    EXPECT_NEAR(f.depth_m.at<float>(3, 3), (1000 + count) / 1000.0, 1e-6);
    ++count;
  }
  EXPECT_EQ(count, 4);
}

TEST_F(BagIoTest, MasksWrittenAfterDepthStillReachTheirFrame) {
  BagReader reader(WriteBag(4, true, false, /*mask_after_depth=*/true));
  RgbdBagStream stream(reader, RgbdBagTopics{});
  RgbdBagFrame f;
  int count = 0;
  while (stream.Next(&f)) {
    ASSERT_FALSE(f.dynamic_mask.empty()) << "frame " << count;
    EXPECT_EQ(f.dynamic_mask.at<uint8_t>(2, 2), 10 * count);
    ++count;
  }
  EXPECT_EQ(count, 4);
}

TEST_F(BagIoTest, MissingAndCorruptBagsAreLoadErrors) {
  EXPECT_THROW(BagReader((dir_ / "nope.bag").string()), LoadError);
  const std::string junk = (dir_ / "junk.bag").string();
  std::ofstream(junk) << "this is not a bag at all";
  EXPECT_THROW(BagReader{junk}, LoadError);
  // A truncated copy of a good bag is refused; the original is untouched and still readable.
  const std::string good = WriteBag(20);
  const auto size = fs::file_size(good);
  const std::string cut = (dir_ / "cut.bag").string();
  fs::copy_file(good, cut);
  fs::resize_file(cut, size / 2);
  EXPECT_THROW(BagReader{cut}, LoadError);
  EXPECT_EQ(fs::file_size(good), size);
  EXPECT_NO_THROW(BagReader{good});
}

TEST_F(BagIoTest, MissingTopicOrCameraInfoIsAClearError) {
  const std::string path = WriteBag(3, /*with_info=*/false);
  BagReader reader(path);
  try {
    RgbdBagStream s(reader, RgbdBagTopics{});
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("camera_info"), std::string::npos) << e.what();
  }
  RgbdBagTopics with_fallback;
  with_fallback.fallback_intrinsics = CameraIntrinsics{};
  EXPECT_NO_THROW(RgbdBagStream(reader, with_fallback));
  RgbdBagTopics wrong;
  wrong.rgb = "/no/such/topic";
  try {
    RgbdBagStream s(reader, wrong);
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/topic"), std::string::npos);
  }
}

TEST_F(BagIoTest, TimeGoingBackwardsIsDroppedAndCounted) {
  const std::string path = WriteBag(4, true, /*reverse_last=*/true);
  BagReader reader(path);
  RgbdBagStream stream(reader, RgbdBagTopics{});
  RgbdBagFrame f;
  int count = 0;
  Time last;
  while (stream.Next(&f)) {
    if (count > 0) {
      EXPECT_TRUE(last < f.stamp);
    }
    last = f.stamp;
    ++count;
  }
  // The bag is time-ordered by receive time, so the stale frame arrives first and the first
  // real frame at the same stamp is the one dropped; either way exactly one frame is lost.
  EXPECT_EQ(count, 3);
  size_t dropped = 0;
  for (const auto& [reason, n] : stream.dropped()) dropped += n;
  EXPECT_EQ(dropped, 1u);
}

}  // namespace
}  // namespace icgm::ros_bridge
