// Replays a simulator bag through feature extraction -> registration -> fusion and checks the
// fused odometry (odom -> base_link) against the simulator's ground truth.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "bag_replayer.h"
#include "core/geometry/absolute_orientation.h"
#include "ros_bridge/bag_reader.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam::test {
namespace {

TEST(OdometryPipeline, FusedOdometryFollowsGroundTruth) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  ReplayOptions options;
  ASSERT_TRUE(pnh.getParam("bag", options.bag_path));
  pnh.param("max_frames", options.max_frames, 60);
  double max_ate_m = 0.05;
  pnh.param("max_ate_m", max_ate_m, max_ate_m);
  const int delay = 2;  // double-directional features (1) + registration needs a reference (1)

  icgm::ros_bridge::BagReader reader(options.bag_path);
  icgm::ros_bridge::RgbdBagStream stream(reader, icgm::ros_bridge::RgbdBagTopics{});
  ASSERT_TRUE(stream.base_to_camera().has_value());
  ASSERT_FALSE(stream.ground_truth().empty());
  const icgm::Pose3 base_to_camera = *stream.base_to_camera();

  std::vector<nav_msgs::Odometry::ConstPtr> odom;
  ros::Subscriber sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 200, [&](const nav_msgs::Odometry::ConstPtr& m) { odom.push_back(m); });
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener listener(tf_buffer);

  const int frames = ReplayBag(nh, options, [&](int i) {
    return static_cast<int>(odom.size()) >= i + 1 - delay;
  });
  ASSERT_GE(frames, 20);
  ASSERT_GE(static_cast<int>(odom.size()), frames - delay);

  std::vector<Eigen::Vector3d> est, gt;
  for (const auto& m : odom) {
    const icgm::Time t = icgm::ros_bridge::FromRos(m->header.stamp);
    const auto truth = icgm::PoseAt(stream.ground_truth(), t, 0.01);
    ASSERT_TRUE(truth.has_value()) << "no ground truth at " << t.ToString();
    EXPECT_EQ(m->header.frame_id, "odom");
    EXPECT_EQ(m->child_frame_id, "base_link");
    const icgm::Pose3 camera = icgm::ros_bridge::FromPoseMsg(m->pose.pose) * base_to_camera;
    est.push_back(camera.translation());
    gt.push_back(truth->translation());
  }
  icgm::SimilarityTransform align;
  ASSERT_TRUE(icgm::HornAlign(est, gt, false, &align).ok());
  double sq = 0, path = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    sq += (align.Apply(est[i]) - gt[i]).squaredNorm();
    if (i > 0) path += (gt[i] - gt[i - 1]).norm();
  }
  const double ate = std::sqrt(sq / est.size());
  std::printf("fused odometry: %zu poses over %.2f m of ground truth, ATE RMSE %.4f m\n",
              est.size(), path, ate);
  RecordProperty("ate_rmse_m", std::to_string(ate));
  EXPECT_GT(path, 0.3) << "scenario should move the camera";
  EXPECT_LT(ate, max_ate_m);

  // The same pose is on tf (odom -> base_link) at the last stamp.
  const auto last = odom.back();
  ASSERT_TRUE(tf_buffer.canTransform("odom", "base_link", last->header.stamp, ros::Duration(2.0)));
  const auto tf = tf_buffer.lookupTransform("odom", "base_link", last->header.stamp);
  EXPECT_TRUE(icgm::ros_bridge::FromTransformMsg(tf.transform)
                  .isApprox(icgm::ros_bridge::FromPoseMsg(last->pose.pose), 1e-6));
}

}  // namespace
}  // namespace icgm_slam::test

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "odometry_rostest");
  return RUN_ALL_TESTS();
}
