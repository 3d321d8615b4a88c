#include "nodelets/move_base_server.h"

#include <utility>

#include <geometry_msgs/Twist.h>
#include <ros/console.h>

#include "ros_bridge/navigation_msgs.h"

namespace icgm::nodelets {

MoveBaseServer::MoveBaseServer(ros::NodeHandle& nh, GoalCallback on_goal,
                               std::function<void()> on_cancel)
    : on_goal_(std::move(on_goal)), on_cancel_(std::move(on_cancel)) {
  cmd_pub_ = nh.advertise<geometry_msgs::Twist>("cmd_vel", 10);
  simple_goal_pub_ = nh.advertise<move_base_msgs::MoveBaseActionGoal>("move_base/goal", 1);
  simple_goal_sub_ = nh.subscribe<geometry_msgs::PoseStamped>(
      "move_base_simple/goal", 1, [this](const geometry_msgs::PoseStamped::ConstPtr& msg) {
        move_base_msgs::MoveBaseActionGoal goal;
        goal.header.stamp = ros::Time::now();
        goal.goal.target_pose = *msg;
        simple_goal_pub_.publish(goal);
      });
  server_ = std::make_unique<Server>(nh, "move_base", false);
  server_->registerGoalCallback([this] { GoalCb(); });
  server_->registerPreemptCallback([this] { PreemptCb(); });
  server_->start();
}

void MoveBaseServer::GoalCb() {
  const geometry_msgs::PoseStamped target = server_->acceptNewGoal()->target_pose;
  // A goal that is no pose (NaN, zero quaternion) preempts the active one and is aborted.
  Status s = ros_bridge::CheckGoalPose(target.pose);
  if (s.ok()) s = on_goal_(target);
  if (s.ok()) return;
  on_cancel_();
  Finish(false, s.reason());
}

void MoveBaseServer::PreemptCb() {
  on_cancel_();
  cmd_pub_.publish(geometry_msgs::Twist());
  // actionlib calls this for a cancel and for a newer goal alike: the text tells them apart.
  if (server_->isActive()) {
    server_->setPreempted(move_base_msgs::MoveBaseResult(), server_->isNewGoalAvailable()
                                                                ? "preempted by a newer goal"
                                                                : "cancelled");
  }
}

void MoveBaseServer::Drive(const VelocityCommand& command,
                           const move_base_msgs::MoveBaseFeedback* feedback) {
  cmd_pub_.publish(ros_bridge::ToTwistMsg(command));
  if (feedback) server_->publishFeedback(*feedback);
}

void MoveBaseServer::Finish(bool succeeded, const std::string& text) {
  cmd_pub_.publish(geometry_msgs::Twist());
  if (!server_->isActive()) return;
  if (succeeded) {
    ROS_INFO("navigation: goal succeeded (%s)", text.c_str());
    server_->setSucceeded(move_base_msgs::MoveBaseResult(), text);
  } else {
    ROS_WARN("navigation: goal aborted: %s", text.c_str());
    server_->setAborted(move_base_msgs::MoveBaseResult(), text);
  }
}

}  // namespace icgm::nodelets
