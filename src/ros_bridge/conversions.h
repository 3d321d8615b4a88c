// The one place where ROS message types meet core types (time, poses, intrinsics, images).
// Every conversion here has a round-trip test in test/ros_bridge/conversions_test.cpp.
#pragma once

#include <string>

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <opencv2/core.hpp>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"

namespace icgm::ros_bridge {

ros::Time ToRos(Time t);
Time FromRos(const ros::Time& t);

geometry_msgs::Point ToPointMsg(const Vec3& v);
Vec3 FromPointMsg(const geometry_msgs::Point& msg);
geometry_msgs::Pose ToPoseMsg(const Pose3& p);
Pose3 FromPoseMsg(const geometry_msgs::Pose& msg);
geometry_msgs::Transform ToTransformMsg(const Pose3& p);
Pose3 FromTransformMsg(const geometry_msgs::Transform& msg);

sensor_msgs::CameraInfo ToCameraInfo(const CameraIntrinsics& k, const std::string& frame_id, Time t);
// Fails when K is zero/non-finite or the size is zero (a camera_info that was never calibrated).
Status FromCameraInfo(const sensor_msgs::CameraInfo& msg, double depth_scale, CameraIntrinsics* out);

// Wraps `image` (encodings bgr8, rgb8, mono8, 16UC1, 32FC1) into a message (copies the data).
sensor_msgs::Image ToImageMsg(const cv::Mat& image, const std::string& encoding,
                              const std::string& frame_id, Time t);
// Colour image -> CV_8UC3 BGR. Accepts bgr8, rgb8, bgra8, rgba8, mono8; anything else fails.
Status ColorFromImageMsg(const sensor_msgs::Image& msg, cv::Mat* bgr);
// The same without a copy when the message is bgr8 already: *bgr then points into msg.data and
// is valid only while the message lives and is not changed (keep its shared pointer as long as
// the image is used). Other encodings are converted as by ColorFromImageMsg.
Status ColorViewOfImageMsg(const sensor_msgs::Image& msg, cv::Mat* bgr);
// Depth image -> CV_32FC1 metres, NaN where invalid. Accepts 16UC1 (mm, or `depth_scale` units
// per metre) and 32FC1 (m); anything else, or a size mismatch with the data, fails.
Status DepthFromImageMsg(const sensor_msgs::Image& msg, double depth_scale_16u, cv::Mat* depth_m);
// The same into `buffer`, reused when it is CV_32FC1 of the image's size (else reallocated): the
// caller's own buffer, which nothing else may read (e.g. from DepthBuffers).
Status DepthFromImageMsgInto(const sensor_msgs::Image& msg, double depth_scale_16u,
                             cv::Mat* buffer);
// mono8 -> CV_8UC1.
Status MonoFromImageMsg(const sensor_msgs::Image& msg, cv::Mat* mono);

}  // namespace icgm::ros_bridge
