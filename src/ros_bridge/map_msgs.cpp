#include "ros_bridge/map_msgs.h"

#include <cmath>

#include <sensor_msgs/point_cloud2_iterator.h>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

std_msgs::ColorRGBA Rgba(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker MakeMarker(const std::string& frame_id, Time stamp, const char* ns,
                                      int type, double scale) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.header.stamp = ToRos(stamp);
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = scale;
  return m;
}

namespace {

// One colour per session, so merged sessions are told apart.
std_msgs::ColorRGBA SessionColor(int session) {
  static const float kPalette[][3] = {{0.2f, 0.6f, 1.f}, {1.f, 0.6f, 0.1f}, {0.6f, 0.9f, 0.2f},
                                      {0.9f, 0.3f, 0.9f}, {0.3f, 0.9f, 0.9f}};
  const auto& c = kPalette[(session < 0 ? 0 : session) % 5];
  return Rgba(c[0], c[1], c[2]);
}

}  // namespace

visualization_msgs::MarkerArray ToGraphMarkers(const HybridMap& map, const std::string& frame_id,
                                               Time stamp) {
  auto nodes = MakeMarker(frame_id, stamp, "keyframes", visualization_msgs::Marker::SPHERE_LIST, 0.06);
  auto odometry = MakeMarker(frame_id, stamp, "odometry_links", visualization_msgs::Marker::LINE_LIST, 0.015);
  auto loops = MakeMarker(frame_id, stamp, "loop_links", visualization_msgs::Marker::LINE_LIST, 0.03);
  // Wheel links join the same keyframes as odometry links: drawn under them, thinner.
  auto wheel = MakeMarker(frame_id, stamp, "wheel_links", visualization_msgs::Marker::LINE_LIST, 0.008);
  odometry.color = Rgba(0.8f, 0.8f, 0.8f, 0.8f);
  wheel.color = Rgba(0.2f, 0.6f, 1.f, 0.8f);
  loops.color = Rgba(1.f, 0.15f, 0.15f);
  for (const Keyframe& kf : map.keyframes()) {
    nodes.points.push_back(ToPointMsg(kf.global_pose.translation()));
    nodes.colors.push_back(SessionColor(kf.session_id));
  }
  for (const Link& link : map.links()) {
    if (link.from_id < 0 || link.to_id < 0 || link.from_id >= map.size() || link.to_id >= map.size()) {
      continue;
    }
    auto& target = link.type == LinkType::kLoopClosure     ? loops
                   : link.type == LinkType::kWheelOdometry ? wheel
                                                           : odometry;
    target.points.push_back(ToPointMsg(map.keyframe(link.from_id).global_pose.translation()));
    target.points.push_back(ToPointMsg(map.keyframe(link.to_id).global_pose.translation()));
  }
  visualization_msgs::MarkerArray out;
  for (auto* m : {&nodes, &odometry, &wheel, &loops}) {
    // An empty list marker is invalid in rviz: send DELETE instead, which also clears old ones.
    if (m->points.empty()) m->action = visualization_msgs::Marker::DELETE;
    out.markers.push_back(*m);
  }
  return out;
}

sensor_msgs::PointCloud2 ToMapCloud(const HybridMap& map, const std::string& frame_id, Time stamp,
                                    double max_range_m) {
  size_t n = 0;
  for (const Keyframe& kf : map.keyframes()) n += kf.points_m.size();
  sensor_msgs::PointCloud2 cloud;
  cloud.header.frame_id = frame_id;
  cloud.header.stamp = ToRos(stamp);
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(2, "xyz", "rgb");
  modifier.resize(n);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  sensor_msgs::PointCloud2Iterator<uint8_t> r(cloud, "r"), g(cloud, "g"), b(cloud, "b");
  size_t kept = 0;
  for (const Keyframe& kf : map.keyframes()) {
    const auto c = SessionColor(kf.session_id);
    for (const Vec3& p : kf.points_m) {
      if (!p.allFinite() || p.norm() > max_range_m) continue;
      const Vec3 w = kf.global_pose * p;
      *x = static_cast<float>(w.x());
      *y = static_cast<float>(w.y());
      *z = static_cast<float>(w.z());
      *r = static_cast<uint8_t>(255 * c.r);
      *g = static_cast<uint8_t>(255 * c.g);
      *b = static_cast<uint8_t>(255 * c.b);
      ++x, ++y, ++z, ++r, ++g, ++b, ++kept;
    }
  }
  modifier.resize(kept);
  return cloud;
}

nav_msgs::Path ToKeyframePath(const HybridMap& map, const std::string& frame_id, Time stamp) {
  nav_msgs::Path path;
  path.header.frame_id = frame_id;
  path.header.stamp = ToRos(stamp);
  for (const Keyframe& kf : map.keyframes()) {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = frame_id;
    p.header.stamp = ToRos(kf.stamp);
    p.pose = ToPoseMsg(kf.global_pose);
    path.poses.push_back(p);
  }
  return path;
}

}  // namespace icgm::ros_bridge
