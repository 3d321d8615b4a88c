// Stamped pose sequences and their TUM RGB-D benchmark text format
// ("timestamp tx ty tz qx qy qz qw" per line, '#' comment lines; Sturm et al., IROS 2012).
// A pose maps the sensor frame into the world frame (T_world_sensor).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/common/pose.h"
#include "core/common/time.h"

namespace icgm {

struct StampedPose {
  Time stamp;
  Pose3 pose = Pose3::Identity();
};
using Trajectory = std::vector<StampedPose>;

// Reads a TUM trajectory in file order. Skips blank and '#' lines; normalizes quaternions.
// Throws LoadError naming file and line for a missing file, a line that is not exactly 8
// numbers, a non-finite value or a zero quaternion.
Trajectory ReadTumTrajectory(const std::string& path);

// Writes a TUM trajectory atomically (to "<path>.tmp" then renamed over `path`, so a reader
// never sees a half-written file). Throws LoadError when the file cannot be written.
void WriteTumTrajectory(const std::string& path, const Trajectory& trajectory);

// True when stamps are non-decreasing (the precondition of PoseAt).
bool IsSortedByStamp(const Trajectory& trajectory);
// Stable sort by stamp.
void SortByStamp(Trajectory* trajectory);
// The stamps, in order.
std::vector<Time> Stamps(const Trajectory& trajectory);

// Pose at time t from a trajectory sorted by stamp: the exact pose at a matching stamp, else
// interpolated (lerp translation, slerp rotation) between the two poses bracketing t. Returns
// nullopt outside [first, last] stamp (no extrapolation) or when the bracketing poses are more
// than max_gap_s apart (a hole in the trajectory).
std::optional<Pose3> PoseAt(const Trajectory& trajectory, Time t, double max_gap_s = 0.1);

}  // namespace icgm
