// Replays a simulator bag through feature extraction -> registration -> fusion and checks the
// fused odometry (odom -> base_link) against the simulator's ground truth.
#include <optional>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "bag_replayer.h"
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
  // Drift bounds as a fraction of the distance travelled.
  double max_drift_rmse_ratio = 0.04;
  pnh.param("max_drift_rmse_ratio", max_drift_rmse_ratio, max_drift_rmse_ratio);
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

  // Both trajectories anchored at the first fused pose: the error is the drift accumulated
  // since then (a Horn alignment is ill-posed on the straight start of the route).
  std::optional<icgm::Pose3> est0, gt0;
  double max_err = 0, sq = 0, path = 0;
  Eigen::Vector3d last_gt = Eigen::Vector3d::Zero();
  for (const auto& m : odom) {
    const icgm::Time t = icgm::ros_bridge::FromRos(m->header.stamp);
    const auto truth = icgm::PoseAt(stream.ground_truth(), t, 0.01);
    ASSERT_TRUE(truth.has_value()) << "no ground truth at " << t.ToString();
    EXPECT_EQ(m->header.frame_id, "odom");
    EXPECT_EQ(m->child_frame_id, "base_link");
    const icgm::Pose3 camera = icgm::ros_bridge::FromPoseMsg(m->pose.pose) * base_to_camera;
    if (!est0) {
      est0 = camera;
      gt0 = *truth;
    }
    const icgm::Pose3 est_rel = icgm::Between(*est0, camera);
    const icgm::Pose3 gt_rel = icgm::Between(*gt0, *truth);
    const double err = (est_rel.translation() - gt_rel.translation()).norm();
    max_err = std::max(max_err, err);
    sq += err * err;
    path += (gt_rel.translation() - last_gt).norm();
    last_gt = gt_rel.translation();
  }
  const double rmse = std::sqrt(sq / odom.size());
  std::printf("fused odometry: %zu poses over %.2f m of ground truth, drift RMSE %.4f m, max %.4f m\n",
              odom.size(), path, rmse, max_err);
  RecordProperty("drift_rmse_m", std::to_string(rmse));
  EXPECT_GT(path, 0.5) << "scenario should move the camera";
  EXPECT_LT(rmse, max_drift_rmse_ratio * path);
  EXPECT_LT(max_err, 2 * max_drift_rmse_ratio * path);

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
