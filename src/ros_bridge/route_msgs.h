// Routes planned on the hybrid map's graph (core/nav/graph_planner.h) -> rviz messages: the route
// as a nav_msgs/Path and as a MarkerArray (line strip through the keyframe nodes, goal sphere).
#pragma once

#include <string>

#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/nav/graph_planner.h"

namespace icgm::ros_bridge {

// One pose per route node, at the node's position, heading (yaw about +z) towards the next node;
// the last pose keeps the heading of the last segment. An empty route gives an empty path.
nav_msgs::Path ToRoutePath(const GraphPlanner& graph, const Route& route,
                           const std::string& frame_id, Time stamp);
// A line strip through the route and a sphere at its goal; for an empty route both markers are
// DELETE actions, which clears an old route in rviz.
visualization_msgs::MarkerArray ToRouteMarkers(const GraphPlanner& graph, const Route& route,
                                               const std::string& frame_id, Time stamp);

}  // namespace icgm::ros_bridge
