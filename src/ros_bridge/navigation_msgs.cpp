#include "ros_bridge/navigation_msgs.h"

#include <cmath>
#include <cstdio>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

Status CheckGoalPose(const geometry_msgs::Pose& pose) {
  const auto& p = pose.position;
  const auto& q = pose.orientation;
  char text[160];
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
    std::snprintf(text, sizeof(text), "goal position (%g, %g, %g) is not finite", p.x, p.y, p.z);
    return Status::Error(text);
  }
  const double norm2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  if (!std::isfinite(norm2) || norm2 < 1e-6) {
    std::snprintf(text, sizeof(text),
                  "goal orientation (%g, %g, %g, %g) is not a quaternion (%s); identity is "
                  "(0, 0, 0, 1)",
                  q.x, q.y, q.z, q.w, std::isfinite(norm2) ? "length about zero" : "not finite");
    return Status::Error(text);
  }
  return Status::Ok();
}

geometry_msgs::Twist ToTwistMsg(const VelocityCommand& cmd) {
  geometry_msgs::Twist msg;
  msg.linear.x = cmd.linear_mps;
  msg.angular.z = cmd.angular_radps;
  return msg;
}

VelocityCommand FromTwistMsg(const geometry_msgs::Twist& msg) {
  VelocityCommand cmd;
  cmd.linear_mps = msg.linear.x;
  cmd.angular_radps = msg.angular.z;
  return cmd;
}

nav_msgs::Path ToPathMsg(const std::vector<Pose3>& poses, const std::string& frame_id, Time stamp) {
  nav_msgs::Path path;
  path.header.frame_id = frame_id;
  path.header.stamp = ToRos(stamp);
  path.poses.resize(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    path.poses[i].header = path.header;
    path.poses[i].pose = ToPoseMsg(poses[i]);
  }
  return path;
}

std::vector<Pose3> FromPathMsg(const nav_msgs::Path& msg) {
  std::vector<Pose3> poses;
  poses.reserve(msg.poses.size());
  for (const auto& p : msg.poses) poses.push_back(FromPoseMsg(p.pose));
  return poses;
}

nav_msgs::Path ToPlanarPathMsg(const std::vector<Eigen::Vector2d>& points,
                               const std::string& frame_id, Time stamp) {
  std::vector<Pose3> poses;
  poses.reserve(points.size());
  double yaw = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (i + 1 < points.size()) {
      const Eigen::Vector2d d = points[i + 1] - points[i];
      if (d.norm() > 1e-9) yaw = std::atan2(d.y(), d.x());
    }
    poses.push_back(MakePose(Vec3(points[i].x(), points[i].y(), 0.0),
                             Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()))));
  }
  return ToPathMsg(poses, frame_id, stamp);
}

std::vector<Eigen::Vector2d> FromPlanarPathMsg(const nav_msgs::Path& msg) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(msg.poses.size());
  for (const auto& p : msg.poses) points.emplace_back(p.pose.position.x, p.pose.position.y);
  return points;
}

geometry_msgs::PolygonStamped ToPolygonMsg(const std::vector<Eigen::Vector2d>& vertices,
                                           const std::string& frame_id, Time stamp) {
  geometry_msgs::PolygonStamped msg;
  msg.header.frame_id = frame_id;
  msg.header.stamp = ToRos(stamp);
  msg.polygon.points.resize(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) {
    msg.polygon.points[i].x = static_cast<float>(vertices[i].x());
    msg.polygon.points[i].y = static_cast<float>(vertices[i].y());
  }
  return msg;
}

std::vector<Eigen::Vector2d> FromPolygonMsg(const geometry_msgs::PolygonStamped& msg) {
  std::vector<Eigen::Vector2d> vertices;
  vertices.reserve(msg.polygon.points.size());
  for (const auto& p : msg.polygon.points) vertices.emplace_back(p.x, p.y);
  return vertices;
}

std::vector<Eigen::Vector2d> CircleFootprint(double radius_m, int vertices) {
  std::vector<Eigen::Vector2d> polygon;
  for (int i = 0; i < vertices; ++i) {
    const double a = 2.0 * M_PI * i / vertices;
    polygon.emplace_back(radius_m * std::cos(a), radius_m * std::sin(a));
  }
  return polygon;
}

nav_msgs::Odometry ToOdometryMsg(const OdometryData& odom, const std::string& frame_id,
                                 const std::string& child_frame_id) {
  nav_msgs::Odometry m;
  m.header.stamp = ToRos(odom.stamp);
  m.header.frame_id = frame_id;
  m.child_frame_id = child_frame_id;
  m.pose.pose = ToPoseMsg(odom.pose);
  m.twist.twist.linear.x = odom.linear_velocity_mps.x();
  m.twist.twist.linear.y = odom.linear_velocity_mps.y();
  m.twist.twist.linear.z = odom.linear_velocity_mps.z();
  m.twist.twist.angular.x = odom.angular_velocity_rps.x();
  m.twist.twist.angular.y = odom.angular_velocity_rps.y();
  m.twist.twist.angular.z = odom.angular_velocity_rps.z();
  return m;
}

OdometryData FromOdometryMsg(const nav_msgs::Odometry& msg) {
  OdometryData odom;
  odom.stamp = FromRos(msg.header.stamp);
  odom.pose = FromPoseMsg(msg.pose.pose);
  const auto& v = msg.twist.twist.linear;
  const auto& w = msg.twist.twist.angular;
  odom.linear_velocity_mps = Eigen::Vector3d(v.x, v.y, v.z);
  odom.angular_velocity_rps = Eigen::Vector3d(w.x, w.y, w.z);
  return odom;
}

sensor_msgs::LaserScan ToLaserScanMsg(const PlanarScan& scan, const std::string& frame_id) {
  sensor_msgs::LaserScan msg;
  msg.header.stamp = ToRos(scan.stamp);
  msg.header.frame_id = frame_id;
  msg.angle_min = static_cast<float>(scan.angle_min_rad);
  msg.angle_increment = static_cast<float>(scan.angle_increment_rad);
  msg.angle_max = static_cast<float>(
      scan.ranges_m.empty() ? scan.angle_min_rad : scan.BeamAngle(scan.ranges_m.size() - 1));
  msg.range_min = static_cast<float>(scan.range_min_m);
  msg.range_max = static_cast<float>(scan.range_max_m);
  msg.ranges = scan.ranges_m;
  return msg;
}

PlanarScan FromLaserScanMsg(const sensor_msgs::LaserScan& msg) {
  PlanarScan scan;
  scan.stamp = FromRos(msg.header.stamp);
  scan.angle_min_rad = msg.angle_min;
  scan.angle_increment_rad = msg.angle_increment;
  scan.range_min_m = msg.range_min;
  scan.range_max_m = msg.range_max;
  scan.ranges_m = msg.ranges;
  return scan;
}

}  // namespace icgm::ros_bridge
