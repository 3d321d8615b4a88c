// The navigation nodelet's move_base-style front: the `move_base` action server
// (move_base_msgs/MoveBaseAction), `move_base_simple/goal` forwarded to it as move_base does,
// and `cmd_vel`. Ending a goal in any way (succeeded, aborted, cancelled or preempted) publishes a
// zero Twist first, so the base stops at once; an ended goal's reason is its result text.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <actionlib/server/simple_action_server.h>
#include <geometry_msgs/PoseStamped.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <ros/node_handle.h>

#include "core/common/status.h"
#include "core/common/velocity_command.h"

namespace icgm::nodelets {

class MoveBaseServer {
 public:
  // `on_goal`: a new goal (it preempted any active one); a failed Status aborts it with the
  // reason. `on_cancel`: the goal ends here, not by the navigation (the client cancelled it, or
  // on_goal refused it); the zero Twist and the result follow.
  using GoalCallback = std::function<Status(const geometry_msgs::PoseStamped& target)>;
  MoveBaseServer(ros::NodeHandle& nh, GoalCallback on_goal, std::function<void()> on_cancel);

  bool active() const { return server_->isActive(); }
  // One control cycle's command and, for the client, the robot's pose.
  void Drive(const VelocityCommand& command, const move_base_msgs::MoveBaseFeedback* feedback);
  // Zero Twist, then the result with `text` (nothing more when no goal is active).
  void Finish(bool succeeded, const std::string& text);

 private:
  using Server = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;
  void GoalCb();
  void PreemptCb();

  ros::Publisher cmd_pub_, simple_goal_pub_;
  ros::Subscriber simple_goal_sub_;
  std::unique_ptr<Server> server_;
  GoalCallback on_goal_;
  std::function<void()> on_cancel_;
};

}  // namespace icgm::nodelets
