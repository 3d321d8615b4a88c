#include "ros_bridge/route_msgs.h"

#include <cmath>

#include "ros_bridge/conversions.h"
#include "ros_bridge/map_msgs.h"

namespace icgm::ros_bridge {

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
  auto line = MakeMarker(frame_id, stamp, "route", visualization_msgs::Marker::LINE_STRIP, 0.05);
  line.color = Rgba(0.1f, 0.9f, 0.2f);
  auto goal = MakeMarker(frame_id, stamp, "route_goal", visualization_msgs::Marker::SPHERE, 0.2);
  goal.color = line.color;
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
