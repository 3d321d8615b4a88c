// The navigation nodelet's outputs besides cmd_vel: the action feedback and, for rviz, the
// route (latched, published when a goal starts) and, built only while someone listens, the
// local plan, the footprint and the obstacle grid (at most twice a second).
#pragma once

#include <string>

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>
#include <move_base_msgs/MoveBaseAction.h>

#include "core/nav/navigator.h"

namespace icgm::nodelets {

class NavigationViz {
 public:
  NavigationViz(ros::NodeHandle& nh, std::string map_frame, std::string base_frame);

  // The action feedback: the localized base in the map frame.
  move_base_msgs::MoveBaseFeedback Feedback(const Pose3& T_map_base, const ros::Time& now) const;
  void PublishRoute(const Navigator& navigator, const ros::Time& now);
  void PublishDebug(const Navigator& navigator, const ros::Time& now);

 private:
  std::string map_frame_, base_frame_;
  ros::Publisher route_pub_, local_plan_pub_, grid_pub_, footprint_pub_;
  ros::Time last_grid_;
};

}  // namespace icgm::nodelets
