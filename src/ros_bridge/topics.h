// Default topic and frame names (the usual Kinect/openni2_launch and REP-105 names). Nodes take
// them as parameters; these are the defaults used by the simulator, converters and launch files.
#pragma once

namespace icgm::ros_bridge::topics {

inline constexpr char kRgbImage[] = "/camera/rgb/image_color";
inline constexpr char kRgbInfo[] = "/camera/rgb/camera_info";
inline constexpr char kDepthImageMm[] = "/camera/depth_registered/image_raw";  // 16UC1 mm
inline constexpr char kDepthImageM[] = "/camera/depth_registered/image";       // 32FC1 m
inline constexpr char kDepthInfo[] = "/camera/depth_registered/camera_info";
inline constexpr char kWheelOdom[] = "/odom";
inline constexpr char kTf[] = "/tf";
inline constexpr char kTfStatic[] = "/tf_static";
inline constexpr char kGroundTruthPose[] = "/ground_truth/pose";
inline constexpr char kDynamicMask[] = "/ground_truth/dynamic_mask";
inline constexpr char kScan[] = "/scan";  // sensor_msgs/LaserScan of a planar scanner

inline constexpr char kMapFrame[] = "map";
inline constexpr char kOdomFrame[] = "odom";
inline constexpr char kBaseFrame[] = "base_link";
inline constexpr char kCameraFrame[] = "camera_rgb_optical_frame";
inline constexpr char kScannerFrame[] = "base_scan";
inline constexpr char kWorldFrame[] = "world";

}  // namespace icgm::ros_bridge::topics
