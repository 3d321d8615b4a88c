// Replays a crowded simulator bag through the feature extraction nodelet and checks its robust
// features against the simulator's ground-truth dynamic mask: ICGM must keep features on
// pedestrians much less often than they occur among all features.
#include <map>

#include <gtest/gtest.h>
#include <icgm_slam/RobustFeatures.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include "bag_replayer.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"

namespace icgm_slam::test {
namespace {

std::map<int64_t, cv::Mat> LoadMasks(const std::string& bag_path) {
  std::map<int64_t, cv::Mat> masks;
  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(icgm::ros_bridge::topics::kDynamicMask));
  for (const auto& m : view) {
    auto img = m.instantiate<sensor_msgs::Image>();
    cv::Mat mask;
    if (img && icgm::ros_bridge::MonoFromImageMsg(*img, &mask).ok()) {
      masks[icgm::ros_bridge::FromRos(img->header.stamp).nanoseconds()] = mask;
    }
  }
  return masks;
}

TEST(FeatureExtractionNodelet, RobustFeaturesAvoidPedestrians) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  ReplayOptions options;
  ASSERT_TRUE(pnh.getParam("bag", options.bag_path));
  pnh.param("max_frames", options.max_frames, 40);
  std::string mode = "double";
  pnh.param<std::string>("mode", mode, mode);
  const int delay = mode == "double" ? 1 : 0;
  const auto masks = LoadMasks(options.bag_path);
  ASSERT_FALSE(masks.empty()) << "bag has no ground-truth dynamic masks";

  std::vector<icgm_slam::RobustFeatures::ConstPtr> received;
  int debug_images = 0;
  cv::Size debug_size;
  ros::Subscriber sub = nh.subscribe<icgm_slam::RobustFeatures>(
      "/icgm/features", 100, [&](const icgm_slam::RobustFeatures::ConstPtr& m) {
        received.push_back(m);
      });
  ros::Subscriber debug_sub = nh.subscribe<sensor_msgs::Image>(
      "/icgm/features/debug_image", 5, [&](const sensor_msgs::Image::ConstPtr& m) {
        ++debug_images;
        debug_size = cv::Size(m->width, m->height);
      });

  // The registration announces each features message it takes from its input queues; the
  // extraction skips images while extracted frames wait there (backpressure). A frame is answered
  // once its features are out and the registration has taken all of them, so the replay goes at
  // the pace of the slowest nodelet and no image is skipped, however loaded the machine.
  int taken = 0;
  ros::Subscriber taken_sub = nh.subscribe<std_msgs::Header>(
      "/icgm/taken_frames", 100, [&](const std_msgs::Header::ConstPtr&) { ++taken; });
  const int frames = ReplayBag(nh, options, [&](int i) {
    const int out = static_cast<int>(received.size());
    return out >= i + 1 - delay && taken >= out;
  });
  ASSERT_GE(frames, 10) << received.size() << " features messages, " << taken
                        << " taken by the registration";
  EXPECT_EQ(static_cast<int>(received.size()), frames - delay);

  size_t all = 0, all_dynamic = 0, robust = 0, robust_dynamic = 0;
  for (const auto& msg : received) {
    auto it = masks.find(icgm::ros_bridge::FromRos(msg->header.stamp).nanoseconds());
    ASSERT_NE(it, masks.end()) << "features for a frame the bag does not have";
    const cv::Mat& mask = it->second;
    for (size_t k = 0; k < msg->keypoints.size(); ++k) {
      const int x = std::clamp(static_cast<int>(msg->keypoints[k].x), 0, mask.cols - 1);
      const int y = std::clamp(static_cast<int>(msg->keypoints[k].y), 0, mask.rows - 1);
      const bool dynamic = mask.at<uint8_t>(y, x) > 0;
      ++all;
      all_dynamic += dynamic;
      if (msg->robust[k]) {
        ++robust;
        robust_dynamic += dynamic;
      }
    }
  }
  const double all_share = static_cast<double>(all_dynamic) / std::max<size_t>(all, 1);
  const double robust_share = static_cast<double>(robust_dynamic) / std::max<size_t>(robust, 1);
  RecordProperty("dynamic_share_all", std::to_string(all_share));
  RecordProperty("dynamic_share_robust", std::to_string(robust_share));
  std::printf("features: %zu (%.1f%% on pedestrians), robust: %zu (%.1f%% on pedestrians)\n", all,
              100 * all_share, robust, 100 * robust_share);
  EXPECT_GT(all_share, 0.05) << "scenario should have features on pedestrians";
  EXPECT_GT(robust, all / 5) << "ICGM kept too few features";
  // Walking people are textured and move smoothly, so some of their features survive; ICGM must
  // at least halve their share among the features it keeps.
  EXPECT_LT(robust_share, 0.5 * all_share);
  EXPECT_GT(debug_images, 0) << "debug image not published to a subscriber";
  EXPECT_EQ(debug_size, cv::Size(640, 480));
}

}  // namespace
}  // namespace icgm_slam::test
