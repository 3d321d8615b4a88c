// Options of the dynamic-scene RGB-D simulator, with units in the field names. Every struct is
// filled from the `sim:` section of a scenario YAML by one ReadOptions overload that checks
// ranges and rejects unknown keys (config/sim/*.yaml).
#pragma once

#include "core/common/camera.h"
#include "core/common/option_reader.h"

namespace icgm::sim {

// The cafeteria: an axis-aligned room [0, width] x [0, length] x [0, height] in the world frame
// (z up, floor at z = 0) furnished with tables, shelves and pillars.
struct RoomOptions {
  double width_m = 20.0;
  double length_m = 20.0;
  double height_m = 3.2;
  int num_tables = 22;
  int num_shelves = 8;
  int num_pillars = 4;
  // Fraction of the wall length covered by posters.
  double poster_coverage = 0.7;
  // Texture resolution of floor, walls and furniture.
  double texel_size_m = 0.01;
};

// The robot drives counter-clockwise around a rounded rectangle inset from the walls.
struct RouteOptions {
  double inset_m = 2.5;
  double corner_radius_m = 2.0;
  double speed_mps = 0.45;
  double acceleration_mps2 = 0.3;
  // > 0: the number of frames is derived so that the robot drives exactly this many laps.
  double laps = 0.0;
  // Arc length along the loop (from the middle of the south side) where the robot starts.
  double start_offset_m = 0.0;
};

// Pose of camera_rgb_optical_frame on base_link (base_link: x forward, y left, z up, on the
// floor; optical frame: x right, y down, z forward).
struct CameraMountOptions {
  double height_m = 1.0;
  double forward_m = 0.1;
  double pitch_down_deg = 8.0;
  // Positive turns the camera to the left (towards the inside of the loop); the default looks
  // forward and 30 deg to the right, at the poster-covered outer walls 2.5-5 m away, so that
  // most of the view stays within depth range on the straights.
  double yaw_left_deg = -30.0;
};

// Pedestrians walking between waypoints; a fraction of the waypoints is chosen so that the
// walker crosses the robot's view a few metres ahead of it.
struct CrowdOptions {
  int num_pedestrians = 0;
  double speed_mps = 1.1;
  double speed_stddev_mps = 0.2;
  double crossing_fraction = 0.4;
  // Pedestrians yield to the robot: they never come closer than this to base_link.
  double robot_clearance_m = 0.9;
};

// Kinect-like depth: sigma(z) = sigma_base_m + sigma_quadratic_per_m * (z - sigma_offset_m)^2,
// valid range [min_range_m, max_range_m], random dropout and holes along depth edges.
struct DepthNoiseOptions {
  double min_range_m = 0.5;
  double max_range_m = 6.0;
  double sigma_base_m = 0.0012;
  double sigma_quadratic_per_m = 0.0019;
  double sigma_offset_m = 0.4;
  double dropout_probability = 0.01;
  // A depth jump larger than this fraction of the depth marks an object edge.
  double edge_jump_fraction = 0.05;
  double edge_hole_probability = 0.5;
};

// Wheel odometry errors: odometry distance = true distance * (1 + scale_error) + noise, heading
// gains heading_bias_rad_per_m per metre driven plus noise; noise sigmas grow with sqrt(distance).
struct OdometryNoiseOptions {
  double scale_error = 0.02;
  double heading_bias_rad_per_m = 0.002;
  double distance_noise_m_per_sqrt_m = 0.003;
  double heading_noise_rad_per_sqrt_m = 0.002;
};

struct SimOptions {
  int seed = 1;
  // Frames to render; ignored when route.laps > 0.
  int num_frames = 150;
  double frame_rate_hz = 10.0;
  // Stamp of the first frame.
  double start_time_s = 1600000000.0;
  // Grey-level sigma of additive image noise.
  double image_noise_sigma = 2.0;
  CameraIntrinsics intrinsics;
  RoomOptions room;
  RouteOptions route;
  CameraMountOptions camera_mount;
  CrowdOptions crowd;
  DepthNoiseOptions depth_noise;
  OdometryNoiseOptions odometry;
};

// Each overload reads the keys of one section; all throw LoadError on a bad value or unknown key.
void ReadOptions(const OptionReader& reader, RoomOptions* options);
void ReadOptions(const OptionReader& reader, RouteOptions* options);
void ReadOptions(const OptionReader& reader, CameraMountOptions* options);
void ReadOptions(const OptionReader& reader, CrowdOptions* options);
void ReadOptions(const OptionReader& reader, DepthNoiseOptions* options);
void ReadOptions(const OptionReader& reader, OdometryNoiseOptions* options);
// `reader` is the `sim:` section: seed, num_frames, ..., camera: {fx_px, ...}, room: {...}, ...
void ReadOptions(const OptionReader& reader, SimOptions* options);

// Loads the `sim:` section of a scenario file; throws LoadError.
SimOptions LoadSimOptions(const std::string& path);

}  // namespace icgm::sim
