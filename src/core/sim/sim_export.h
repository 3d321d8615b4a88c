// Turning simulator output into recordable data: millimetre depth images and the ground-truth
// and wheel-odometry trajectories written next to a simulated bag.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "core/dataset/trajectory.h"
#include "core/sim/simulator.h"

namespace icgm::sim {

// CV_32FC1 metres (NaN invalid) -> CV_16UC1 millimetres (0 invalid), rounded to the nearest
// millimetre; depths beyond 65.535 m become 0 (invalid), as OpenNI drivers report them.
cv::Mat DepthToMillimetres(const cv::Mat& depth_m);

// Ground-truth pose of camera_rgb_optical_frame in the world for every frame.
Trajectory CameraGroundTruth(const Simulator& sim);
// Wheel odometry (pose of base_link in odom) for every frame; empty for a handheld camera.
Trajectory WheelOdometryTrajectory(const Simulator& sim);

// "<dir>/<name>.bag" -> "<dir>/<name><suffix>" (e.g. ".gt.txt"); a path without the .bag
// extension just gets the suffix appended.
std::string SidecarPath(const std::string& bag_path, const std::string& suffix);

}  // namespace icgm::sim
