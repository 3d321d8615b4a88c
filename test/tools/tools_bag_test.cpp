// icgm_slam_offline on bags that lack what the run needs: camera_info (intrinsics) and the
// /tf_static extrinsic beside wheel odometry. Each is an error naming what is missing unless the
// user gives it explicitly; before, TUM fr1 intrinsics and an identity extrinsic were assumed.
// A bag whose frames stop reading part way is not a success either.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/dataset/camera_options.h"
#include "ros_bridge/bag_writer.h"
#include "ros_bridge/topics.h"
#include "tool_test_util.h"

namespace icgm::tools::testing {
namespace {

namespace topics = icgm::ros_bridge::topics;

struct BagContents {
  bool camera_info = true;
  bool wheels = false;
  bool tf_static = false;
  bool camera_info_once = false;  // only with the first frame's images
};
constexpr BagContents kNoCameraInfo{false, false, false};
constexpr BagContents kWheelsNoTfStatic{true, true, false};
constexpr BagContents kWheelsAndTfStatic{true, true, true};

// Five identical textured frames with flat depth at 2 m.
void WriteBag(const std::string& path, const BagContents& c) {
  const CameraIntrinsics K =
      LoadCameraIntrinsics(std::string(ICGM_SOURCE_DIR) + "/config/camera/tum_fr1.yaml");
  cv::RNG rng(7);
  cv::Mat small(30, 40, CV_8UC3), bgr;
  rng.fill(small, cv::RNG::UNIFORM, 0, 255);
  cv::resize(small, bgr, cv::Size(K.width_px, K.height_px), 0, 0, cv::INTER_NEAREST);
  const cv::Mat depth_mm(K.height_px, K.width_px, CV_16UC1, cv::Scalar(2000));
  ros_bridge::BagWriter bag(path);
  Pose3 base_to_camera = Pose3::Identity();
  base_to_camera.translation() = Eigen::Vector3d(0.1, 0.0, 0.5);
  for (int i = 0; i < 5; ++i) {
    const Time stamp = Time::FromNanoseconds(1'000'000'000LL + i * 33'000'000LL);
    if (c.tf_static && i == 0) {
      bag.WriteTransform(stamp, topics::kBaseFrame, topics::kCameraFrame, base_to_camera, true);
    }
    bag.WriteImage(topics::kRgbImage, topics::kCameraFrame, stamp, bgr, "bgr8");
    bag.WriteImage(topics::kDepthImageMm, topics::kCameraFrame, stamp, depth_mm, "16UC1");
    if (c.camera_info && (i == 0 || !c.camera_info_once)) {
      bag.WriteCameraInfo(topics::kRgbInfo, topics::kCameraFrame, stamp, K);
    }
    if (c.wheels) {
      bag.WriteOdometry(topics::kWheelOdom, stamp, topics::kOdomFrame, topics::kBaseFrame,
                        Pose3::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    }
  }
  bag.Close();
}

// Overwrites the compressed data of the bag's last chunk (format 2.0: records of a length-prefixed
// header, whose `op` field 0x05 marks a chunk, and length-prefixed data), so that reading stops
// with an error there. Returns false when the file holds no chunk.
bool CorruptLastChunk(const std::string& path) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  const auto read_u32 = [&f](std::streamoff at) {
    uint32_t v = 0;
    f.seekg(at);
    f.read(reinterpret_cast<char*>(&v), 4);
    return f ? v : 0u;
  };
  std::streamoff at = 13, last_chunk_data = -1;  // after "#ROSBAG V2.0\n"
  uint32_t last_chunk_bytes = 0;
  for (uint32_t header_len; (header_len = read_u32(at)) > 0;) {
    std::string header(header_len, '\0');
    f.read(header.data(), header_len);
    if (!f) break;
    const std::streamoff data_at = at + 4 + header_len + 4;
    const uint32_t data_len = read_u32(data_at - 4);
    for (size_t h = 0; h + 4 <= header.size();) {
      uint32_t field_len = 0;
      std::memcpy(&field_len, header.data() + h, 4);
      if (header.compare(h + 4, 4, "op=\x05") == 0) {
        last_chunk_data = data_at;
        last_chunk_bytes = data_len;
      }
      h += 4 + field_len;
    }
    at = data_at + data_len;
  }
  if (last_chunk_data < 0 || last_chunk_bytes == 0) return false;
  f.clear();
  f.seekp(last_chunk_data);
  const std::string garbage(last_chunk_bytes, '\xff');
  f.write(garbage.data(), garbage.size());
  return static_cast<bool>(f);
}

class ToolsBagTest : public ToolTest {
 protected:
  ToolRun Offline(const std::string& bag, std::vector<std::string> extra = {}) const {
    std::vector<std::string> args = {"--bag", bag, "--trajectory", Path("traj.txt")};
    args.insert(args.end(), extra.begin(), extra.end());
    return Run("icgm_slam_offline", args);
  }
};

TEST_F(ToolsBagTest, BagWithoutCameraInfoNeedsCamera) {
  WriteBag(Path("no_info.bag"), kNoCameraInfo);
  const ToolRun r = Offline(Path("no_info.bag"));
  EXPECT_EQ(r.exit_code, 1) << Describe(r);
  EXPECT_NE(r.err.find("/camera/rgb/camera_info"), std::string::npos) << Describe(r);
  EXPECT_NE(r.err.find("--camera"), std::string::npos) << Describe(r);
  const ToolRun given = Offline(Path("no_info.bag"), {"--camera", "config/camera/tum_fr1.yaml"});
  EXPECT_EQ(given.exit_code, 0) << Describe(given);
  // With camera_info no --camera is needed.
  WriteBag(Path("info.bag"), {});
  const ToolRun with_info = Offline(Path("info.bag"));
  EXPECT_EQ(with_info.exit_code, 0) << Describe(with_info);
}

TEST_F(ToolsBagTest, WheelsWithoutTfStaticNeedAnExplicitExtrinsic) {
  WriteBag(Path("no_tf.bag"), kWheelsNoTfStatic);
  const ToolRun r = Offline(Path("no_tf.bag"));
  EXPECT_EQ(r.exit_code, 1) << Describe(r);
  EXPECT_NE(r.err.find("/tf_static"), std::string::npos) << Describe(r);
  EXPECT_NE(r.err.find("--extrinsic-from-config"), std::string::npos) << Describe(r);
  EXPECT_FALSE(std::filesystem::exists(Path("traj.txt")));
  EXPECT_EQ(Offline(Path("no_tf.bag"), {"--extrinsic-from-config"}).exit_code, 0);
  EXPECT_EQ(Offline(Path("no_tf.bag"), {"--camera-only"}).exit_code, 0);
  // The extrinsic on /tf_static, or no wheels at all, needs neither.
  WriteBag(Path("tf.bag"), kWheelsAndTfStatic);
  const ToolRun with_tf = Offline(Path("tf.bag"));
  EXPECT_EQ(with_tf.exit_code, 0) << Describe(with_tf);
  WriteBag(Path("no_wheels.bag"), {});
  EXPECT_EQ(Offline(Path("no_wheels.bag")).exit_code, 0);
  // The options only apply to bags.
  EXPECT_EQ(Run("icgm_slam_offline", {"--sim", "config/sim/static_short.yaml", "--camera-only",
                                      "--trajectory", Path("t.txt")})
                .exit_code,
            2);
}

// Frames that stop reading part way (a corrupt chunk) keep what was built: the trajectory and
// the map of the frames before are written, and the run exits 1 saying where it stopped, its
// progress bar short of the end.
TEST_F(ToolsBagTest, ABagThatStopsReadingPartWayIsNotASuccess) {
  // Each colour image fills a chunk of its own, so the last chunk holds the last depth image only
  // and the first reads (camera_info) do not touch it.
  BagContents once;
  once.camera_info_once = true;
  WriteBag(Path("cut.bag"), once);
  ASSERT_EQ(Offline(Path("cut.bag")).exit_code, 0);
  ASSERT_TRUE(CorruptLastChunk(Path("cut.bag")));
  const ToolRun r = Offline(Path("cut.bag"), {"--map", Path("cut.db")});
  EXPECT_EQ(r.exit_code, 1) << Describe(r);
  EXPECT_NE(r.err.find("input ended early after 4 frames"), std::string::npos) << Describe(r);
  EXPECT_EQ(r.err.find("100%"), std::string::npos) << Describe(r);
  EXPECT_TRUE(std::filesystem::exists(Path("cut.db"))) << Describe(r);
  std::ifstream trajectory(Path("traj.txt"));
  size_t poses = 0;
  for (std::string line; std::getline(trajectory, line);) poses += !line.empty() && line[0] != '#';
  EXPECT_EQ(poses, 4u) << Describe(r);
}

}  // namespace
}  // namespace icgm::tools::testing
