// Replays a simulator bag through feature extraction -> registration -> fusion and checks the
// fused odometry (odom -> base_link) against the simulator's ground truth.
#include <optional>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "bag_replayer.h"
#include "core/map/se3_geodesic.h"
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
  // Lock-step replay: registration needs a reference (1) and waits for the wheel sample after
  // a frame's stamp + 50 ms, which the replay sends only after the next frame's images (2).
  const int delay = 3;

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

  // Twist: the base's velocity over each step in base_link, against the ground truth's over the
  // same step; its covariance is that of the step (a registration's, or the fallback model's)
  // over dt^2, so it is positive definite.
  double sq_v = 0, sq_w = 0, speed = 0;
  int steps = 0;
  for (size_t k = 1; k < odom.size(); ++k) {
    const double dt = (odom[k]->header.stamp - odom[k - 1]->header.stamp).toSec();
    const auto t0 = icgm::PoseAt(stream.ground_truth(),
                                 icgm::ros_bridge::FromRos(odom[k - 1]->header.stamp), 0.01);
    const auto t1 =
        icgm::PoseAt(stream.ground_truth(), icgm::ros_bridge::FromRos(odom[k]->header.stamp), 0.01);
    ASSERT_TRUE(t0 && t1 && dt > 0);
    const icgm::Vec6 truth =
        icgm::GeodesicLog(base_to_camera * icgm::Between(*t0, *t1) * base_to_camera.inverse()) / dt;
    const auto& tw = odom[k]->twist.twist;
    const Eigen::Vector3d v(tw.linear.x, tw.linear.y, tw.linear.z);
    const Eigen::Vector3d w(tw.angular.x, tw.angular.y, tw.angular.z);
    sq_v += (v - truth.head<3>()).squaredNorm();
    sq_w += (w - truth.tail<3>()).squaredNorm();
    speed += truth.head<3>().norm();
    ++steps;
    icgm::Mat6 c;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) c(i, j) = odom[k]->twist.covariance[6 * i + j];
    EXPECT_LT((c - c.transpose()).norm(), 1e-12 * c.norm()) << "step " << k;
    EXPECT_EQ(Eigen::LLT<icgm::Mat6>(c).info(), Eigen::Success) << "step " << k;
  }
  ASSERT_GT(steps, 10);
  const double rmse_v = std::sqrt(sq_v / steps), rmse_w = std::sqrt(sq_w / steps);
  std::printf("twist: %d steps, mean speed %.3f m/s, velocity RMSE %.4f m/s, %.4f rad/s\n", steps,
              speed / steps, rmse_v, rmse_w);
  // A step of 0.1 s turns a few millimetres of registration error into centimetres per second.
  EXPECT_LT(rmse_v, 0.25 * speed / steps);
  EXPECT_LT(rmse_w, 0.05);

  // The same pose is on tf (odom -> base_link) at the last stamp.
  const auto last = odom.back();
  ASSERT_TRUE(tf_buffer.canTransform("odom", "base_link", last->header.stamp, ros::Duration(2.0)));
  const auto tf = tf_buffer.lookupTransform("odom", "base_link", last->header.stamp);
  EXPECT_TRUE(icgm::ros_bridge::FromTransformMsg(tf.transform)
                  .isApprox(icgm::ros_bridge::FromPoseMsg(last->pose.pose), 1e-6));
}

}  // namespace
}  // namespace icgm_slam::test
