// Closed-loop navigation <-> ROS messages: velocity commands as geometry_msgs/Twist, pose
// sequences and planar paths as nav_msgs/Path, the robot's footprint as
// geometry_msgs/PolygonStamped, wheel odometry as nav_msgs/Odometry, and planar range scans as
// sensor_msgs/LaserScan. Round-trip tests in
// test/ros_bridge/navigation_msgs_test.cpp.
#pragma once

#include <string>
#include <vector>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PolygonStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/LaserScan.h>
#include <Eigen/Core>

#include "core/common/planar_scan.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/common/velocity_command.h"

namespace icgm::ros_bridge {

// Whether a navigation goal's pose can be used: a finite position and a finite orientation
// quaternion of non-zero length (not necessarily normalized), as move_base checks. The error
// names the bad part. The navigation uses the goal's position only; its heading is not driven to.
Status CheckGoalPose(const geometry_msgs::Pose& pose);

// linear.x and angular.z; a differential base ignores the other components, and so does the
// conversion back.
geometry_msgs::Twist ToTwistMsg(const VelocityCommand& cmd);
VelocityCommand FromTwistMsg(const geometry_msgs::Twist& msg);

// Every pose stamped with the path's header.
nav_msgs::Path ToPathMsg(const std::vector<Pose3>& poses, const std::string& frame_id, Time stamp);
std::vector<Pose3> FromPathMsg(const nav_msgs::Path& msg);
// A path on the floor plan (z = 0): each pose heads towards the next point; the last keeps the
// heading of the last segment. FromPlanarPathMsg gives the points back.
nav_msgs::Path ToPlanarPathMsg(const std::vector<Eigen::Vector2d>& points,
                               const std::string& frame_id, Time stamp);
std::vector<Eigen::Vector2d> FromPlanarPathMsg(const nav_msgs::Path& msg);

// A planar polygon (x, y in metres, in `frame_id`) at height z = 0.
geometry_msgs::PolygonStamped ToPolygonMsg(const std::vector<Eigen::Vector2d>& vertices,
                                           const std::string& frame_id, Time stamp);
std::vector<Eigen::Vector2d> FromPolygonMsg(const geometry_msgs::PolygonStamped& msg);
// A circular footprint of radius_m around the frame's origin as a polygon of `vertices` corners.
std::vector<Eigen::Vector2d> CircleFootprint(double radius_m, int vertices);

// Pose of `child_frame_id` in `frame_id` with its velocities in the child frame (REP-105).
struct OdometryData {
  Time stamp;
  Pose3 pose = Pose3::Identity();
  Eigen::Vector3d linear_velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_rps = Eigen::Vector3d::Zero();
};
nav_msgs::Odometry ToOdometryMsg(const OdometryData& odom, const std::string& frame_id,
                                 const std::string& child_frame_id);
OdometryData FromOdometryMsg(const nav_msgs::Odometry& msg);

// A planar scan in `frame_id` (the scanner's frame); angle_max is the last beam's angle;
// no intensities, no timing across the scan (time_increment, scan_time 0).
sensor_msgs::LaserScan ToLaserScanMsg(const PlanarScan& scan, const std::string& frame_id);
PlanarScan FromLaserScanMsg(const sensor_msgs::LaserScan& msg);

}  // namespace icgm::ros_bridge
