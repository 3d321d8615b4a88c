#include "nodelets/navigation_viz.h"

#include <utility>

#include <geometry_msgs/PolygonStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>

#include "ros_bridge/conversions.h"
#include "ros_bridge/map_product_msgs.h"
#include "ros_bridge/navigation_msgs.h"

namespace icgm::nodelets {

namespace rb = icgm::ros_bridge;

NavigationViz::NavigationViz(ros::NodeHandle& nh, std::string map_frame, std::string base_frame)
    : map_frame_(std::move(map_frame)), base_frame_(std::move(base_frame)) {
  // The route latched: rviz started later still shows it.
  route_pub_ = nh.advertise<nav_msgs::Path>("route", 1, true);
  local_plan_pub_ = nh.advertise<nav_msgs::Path>("local_plan", 1);
  grid_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("obstacle_grid", 1);
  footprint_pub_ = nh.advertise<geometry_msgs::PolygonStamped>("footprint", 1);
}

move_base_msgs::MoveBaseFeedback NavigationViz::Feedback(const Pose3& T_map_base,
                                                         const ros::Time& now) const {
  move_base_msgs::MoveBaseFeedback feedback;
  feedback.base_position.header.frame_id = map_frame_;
  feedback.base_position.header.stamp = now;
  feedback.base_position.pose = ros_bridge::ToPoseMsg(T_map_base);
  return feedback;
}

void NavigationViz::PublishRoute(const Navigator& navigator, const ros::Time& now) {
  route_pub_.publish(rb::ToPlanarPathMsg(navigator.route(), map_frame_, rb::FromRos(now)));
}

void NavigationViz::PublishDebug(const Navigator& navigator, const ros::Time& now) {
  const Time t = rb::FromRos(now);
  if (local_plan_pub_.getNumSubscribers() > 0) {
    local_plan_pub_.publish(rb::ToPlanarPathMsg(navigator.local_path(), map_frame_, t));
  }
  if (footprint_pub_.getNumSubscribers() > 0) {
    footprint_pub_.publish(rb::ToPolygonMsg(
        rb::CircleFootprint(navigator.options().navigator.robot_radius_m, 24), base_frame_, t));
  }
  if (grid_pub_.getNumSubscribers() > 0 && (now - last_grid_).toSec() >= 0.5) {
    grid_pub_.publish(rb::ToOccupancyGridMsg(navigator.obstacles().Export(), map_frame_, t));
    last_grid_ = now;
  }
}

}  // namespace icgm::nodelets
