#include "ros_bridge/route_msgs.h"

#include <cmath>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

Vec3 FromPointMsg(const geometry_msgs::Point& msg) { return Vec3(msg.x, msg.y, msg.z); }

geometry_msgs::Point ToPointMsg(const Vec3& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

nav_msgs::Path ToRoutePath(const GraphPlanner& graph, const Route& route,
                           const std::string& frame_id, Time stamp) {
  nav_msgs::Path path;
  path.header.frame_id = frame_id;
  path.header.stamp = ToRos(stamp);
  const size_t n = route.nodes.size();
  double yaw = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Vec3& p = graph.position(route.nodes[i]);
    if (i + 1 < n) {
      const Vec3 d = graph.position(route.nodes[i + 1]) - p;
      if (d.head<2>().norm() > 1e-9) yaw = std::atan2(d.y(), d.x());
    }
    geometry_msgs::PoseStamped pose;
    pose.header = path.header;
    pose.pose.position = ToPointMsg(p);
    pose.pose.orientation.z = std::sin(yaw / 2);
    pose.pose.orientation.w = std::cos(yaw / 2);
    path.poses.push_back(pose);
  }
  return path;
}

visualization_msgs::MarkerArray ToRouteMarkers(const GraphPlanner& graph, const Route& route,
                                               const std::string& frame_id, Time stamp) {
  visualization_msgs::Marker line;
  line.header.frame_id = frame_id;
  line.header.stamp = ToRos(stamp);
  line.ns = "route";
  line.type = visualization_msgs::Marker::LINE_STRIP;
  line.action = visualization_msgs::Marker::ADD;
  line.pose.orientation.w = 1.0;
  line.scale.x = 0.05;
  line.color.r = 0.1f;
  line.color.g = 0.9f;
  line.color.b = 0.2f;
  line.color.a = 1.f;
  visualization_msgs::Marker goal = line;
  goal.ns = "route_goal";
  goal.type = visualization_msgs::Marker::SPHERE;
  goal.scale.x = goal.scale.y = goal.scale.z = 0.2;
  for (int node : route.nodes) line.points.push_back(ToPointMsg(graph.position(node)));
  // A line strip needs two points; a one-node route is shown by the goal sphere alone.
  if (line.points.size() < 2) line.action = visualization_msgs::Marker::DELETE;
  if (route.nodes.empty()) {
    goal.action = visualization_msgs::Marker::DELETE;
  } else {
    goal.pose.position = ToPointMsg(graph.position(route.nodes.back()));
  }
  visualization_msgs::MarkerArray out;
  out.markers = {line, goal};
  return out;
}

}  // namespace icgm::ros_bridge
