// icgm_slam_offline on bags that lack what the run needs: camera_info (intrinsics) and the
// /tf_static extrinsic beside wheel odometry. Each is an error naming what is missing unless the
// user gives it explicitly; before, TUM fr1 intrinsics and an identity extrinsic were assumed.
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
    if (c.camera_info) bag.WriteCameraInfo(topics::kRgbInfo, topics::kCameraFrame, stamp, K);
    if (c.wheels) {
      bag.WriteOdometry(topics::kWheelOdom, stamp, topics::kOdomFrame, topics::kBaseFrame,
                        Pose3::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    }
  }
  bag.Close();
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

}  // namespace
}  // namespace icgm::tools::testing
