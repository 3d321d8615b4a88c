// The inputs of icgm_slam_offline as frame sources of the core driver (core/slam/slam_runner.h):
// a TUM RGB-D folder, a rosbag (when the ROS bridge is built) or a simulator scenario rendered
// in process. Each also reports what it knows up front: intrinsics, ground truth, wheel odometry
// and the base_link -> camera extrinsic.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/dataset/trajectory.h"
#include "core/slam/slam_runner.h"

namespace icgm::tools {

struct OfflineSource {
  SlamFrameSource frames;
  CameraIntrinsics intrinsics;
  Trajectory groundtruth;     // camera in world, may be empty
  Trajectory wheel_odometry;  // odom -> base, may be empty
  std::optional<Pose3> base_to_camera;
  size_t expected_frames = 0;
  // Frames skipped because their images could not be read (warned and counted, not fatal).
  std::shared_ptr<size_t> skipped_frames = std::make_shared<size_t>(0);
};

// A TUM folder read with `intrinsics`; unreadable frames are skipped with a warning on stderr
// prefixed by `tool`. Throws LoadError.
OfflineSource OpenTumSource(const std::string& dir, const CameraIntrinsics& intrinsics,
                            const std::string& tool);

// A rosbag: synchronised RGB-D frames, camera_info, /tf_static and wheel odometry. `fallback`:
// intrinsics for a bag without camera_info; without it such a bag is an error naming the topic.
// Throws LoadError, or std::invalid_argument in a build without the ROS bridge.
OfflineSource OpenBagSource(const std::string& path,
                            const std::optional<CameraIntrinsics>& fallback);

// A simulator scenario rendered in process on a worker thread, with its ground-truth dynamic
// masks; `seed` replaces the scenario's seed. Throws LoadError.
OfflineSource OpenSimSource(const std::string& scenario_path, std::optional<int> seed);

}  // namespace icgm::tools
