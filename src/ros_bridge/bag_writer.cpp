#include "ros_bridge/bag_writer.h"

#include <geometry_msgs/PoseStamped.h>
#include <boost/make_shared.hpp>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include "core/common/status.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/navigation_msgs.h"
#include "ros_bridge/topics.h"

namespace icgm::ros_bridge {

BagWriter::BagWriter(const std::string& path) : bag_(std::make_unique<rosbag::Bag>()), path_(path) {
  try {
    bag_->open(path, rosbag::bagmode::Write);
    bag_->setCompression(rosbag::compression::LZ4);
  } catch (const rosbag::BagException& e) {
    throw LoadError("cannot write bag '" + path + "': " + e.what());
  }
}

BagWriter::~BagWriter() { Close(); }

void BagWriter::Close() {
  if (bag_ && bag_->isOpen()) bag_->close();
}

void BagWriter::WriteImage(const std::string& topic, const std::string& frame_id, Time stamp,
                           const cv::Mat& image, const std::string& encoding) {
  bag_->write(topic, ToRos(stamp), ToImageMsg(image, encoding, frame_id, stamp));
}

void BagWriter::WriteCameraInfo(const std::string& topic, const std::string& frame_id,
                                Time stamp, const CameraIntrinsics& intrinsics) {
  bag_->write(topic, ToRos(stamp), ToCameraInfo(intrinsics, frame_id, stamp));
}

void BagWriter::WriteOdometry(const std::string& topic, Time stamp, const std::string& frame_id,
                              const std::string& child_frame_id, const Pose3& pose,
                              const Eigen::Vector3d& linear_velocity_mps,
                              const Eigen::Vector3d& angular_velocity_rps) {
  OdometryData odom;
  odom.stamp = stamp;
  odom.pose = pose;
  odom.linear_velocity_mps = linear_velocity_mps;
  odom.angular_velocity_rps = angular_velocity_rps;
  const nav_msgs::Odometry m = ToOdometryMsg(odom, frame_id, child_frame_id);
  bag_->write(topic, ToRos(stamp), m);
}

void BagWriter::WritePose(const std::string& topic, Time stamp, const std::string& frame_id,
                          const Pose3& pose) {
  geometry_msgs::PoseStamped m;
  m.header.stamp = ToRos(stamp);
  m.header.frame_id = frame_id;
  m.pose = ToPoseMsg(pose);
  bag_->write(topic, ToRos(stamp), m);
}

void BagWriter::WriteTransform(Time stamp, const std::string& parent, const std::string& child,
                               const Pose3& pose, bool is_static) {
  tf2_msgs::TFMessage m;
  geometry_msgs::TransformStamped t;
  t.header.stamp = ToRos(stamp);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = ToTransformMsg(pose);
  m.transforms.push_back(t);
  if (!is_static) {
    bag_->write(topics::kTf, ToRos(stamp), m);
    return;
  }
  // Latched, as tf2's static broadcaster publishes it: `rosbag play` then latches it too, so
  // nodes that subscribe after the first message (default --delay) still get the extrinsic.
  auto header = boost::make_shared<ros::M_string>();
  (*header)["type"] = ros::message_traits::datatype(m);
  (*header)["md5sum"] = ros::message_traits::md5sum(m);
  (*header)["message_definition"] = ros::message_traits::definition(m);
  (*header)["callerid"] = "/icgm_bag_writer";
  (*header)["latching"] = "1";
  bag_->write(topics::kTfStatic, ToRos(stamp), m, header);
}

}  // namespace icgm::ros_bridge
