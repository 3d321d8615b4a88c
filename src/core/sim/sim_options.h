// Options of the dynamic-scene RGB-D simulator, with units in the field names. Every struct is
// filled from the `sim:` section of a scenario YAML by one ReadOptions overload that checks
// ranges and rejects unknown keys (config/sim/*.yaml).
#pragma once

#include <string>

#include "core/common/camera.h"
#include "core/common/option_reader.h"

namespace icgm {
namespace sim {

// How the camera moves (`camera_motion`): wheeled (on the robot's base_link driving the loop
// route, with wheel odometry) or handheld (HandheldOptions; no base_link, no wheel odometry, no
// route).
enum class CameraMotion { kWheeled, kHandheld };

}  // namespace sim

template <>
struct EnumNames<sim::CameraMotion> {
  static constexpr EnumName<sim::CameraMotion> kNames[] = {
      {sim::CameraMotion::kWheeled, "wheeled"}, {sim::CameraMotion::kHandheld, "handheld"}};
};

namespace sim {

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
  // Contrast of the textures around their mean colour: 1 keeps them as drawn, 0 makes the
  // surface one flat colour (plain painted walls, a plain floor, bare furniture).
  double wall_contrast = 1.0;
  double floor_contrast = 1.0;
  double furniture_contrast = 1.0;
  // Desks standing against the walls (0.75 m high), placed after the tables, and chairs (0.9 m
  // high) pulled up to them.
  int num_desks = 0;
  int num_chairs = 0;
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
  // Share of the pedestrians that do not yield: they walk their way as if the robot were not
  // there, only keeping personal_space_m between their body and the camera's position (fixed
  // route) or the robot's footprint (closed loop: they see the robot's body, but do not make
  // room when it drives at them).
  double non_yielding_fraction = 0.0;
  double personal_space_m = 0.3;
  // Where crossing walkers aim: min..max ahead of the camera along its view, min..max to the
  // side opposite to where they are.
  double crossing_min_ahead_m = 1.5;
  double crossing_max_ahead_m = 5.0;
  double crossing_min_side_m = 0.8;
  double crossing_max_side_m = 4.0;
};

// A camera held in the hand of a person standing in the room (camera_motion: handheld): it
// drifts slowly around its start position, pans and tilts a little and shakes with the hand.
// The motion is a smooth random function of time (sums of sinusoids with random phases), so
// poses between frames (motion blur) are exact.
struct HandheldOptions {
  // Start position of the camera on the floor plan, height of the optical centre.
  double x_m = 3.0;
  double y_m = 1.0;
  double height_m = 1.4;
  // Mean viewing direction: yaw from the world x axis (counter-clockwise), pitch below level.
  double yaw_deg = 90.0;
  double pitch_down_deg = 10.0;
  // Slow drift of the position: mean speed and the mean period of its oscillations (the drift
  // stays within about speed * period / 4 of the start).
  double drift_speed_mps = 0.08;
  double drift_period_s = 8.0;
  // Slow panning (yaw), tilting (pitch) and rolling: amplitudes and the mean period.
  double pan_amplitude_deg = 8.0;
  double tilt_amplitude_deg = 3.0;
  double roll_amplitude_deg = 2.0;
  double pan_period_s = 7.0;
  // Hand shake: position and angle amplitudes of 1-5 Hz components.
  double jitter_m = 0.002;
  double jitter_deg = 0.25;
  // A person walking with the camera (0: standing): the start position moves along the mean
  // viewing direction (yaw_deg) at walk_speed_mps, bobbing up and down by walk_bob_m (peak to
  // peak) at walk_step_hz steps per second and swaying sideways as much at half that rate.
  // The whole walk must stay inside the room.
  double walk_speed_mps = 0.0;
  double walk_bob_m = 0.02;
  double walk_step_hz = 1.8;
  // A recorded hand's motion replayed instead of the random drift, pan, tilt, roll and shake
  // ("": the random motion): a TUM trajectory of a camera's optical frame (a relative path is
  // taken from the scenario file's folder). The camera starts at the pose above (position,
  // yaw_deg, pitch_down_deg, no roll) and moves as the recording moves relative to its pose at
  // recorded_start_s after its first stamp (poses interpolated; held at the last one).
  std::string recorded_trajectory;
  double recorded_start_s = 0.0;
};

// Kinect-like depth: sigma(z) = sigma_base_m + sigma_quadratic_per_m * (z - sigma_offset_m)^2,
// valid range [min_range_m, max_range_m], random dropout and holes along depth edges. With
// disparity_focal_baseline_px_m > 0 the depth is also quantized as a structured-light sensor
// measures it: disparity d = f * b / z (pixels), perturbed by disparity_sigma_px and rounded to
// steps of disparity_step_px (Kinect / Xtion: 1/8 px), so neighbouring pixels on a surface
// share one depth and the depth moves in steps of z^2 * step / (f * b) (28 mm at 3 m).
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
  // Structured-light quantization (0: none, the depth keeps the Gaussian noise only).
  double disparity_focal_baseline_px_m = 0.0;
  double disparity_step_px = 0.125;
  double disparity_sigma_px = 0.0;
  // Xtion-like missing depth (all off by default):
  // - shadow_band_px > 0: the projector's shadow, every pixel on the far side of a depth edge
  //   within this many pixels of the nearer surface (deeper than it by edge_jump_fraction) has
  //   no depth;
  // - solid holes in blocks of hole_block_px: a block has no depth with probability
  //   hole_probability, plus far_hole_probability times how far its depth lies between
  //   far_hole_start_m and max_range_m (dark, shiny and distant surfaces);
  // - border_band_px > 0: no depth within this many pixels of the image border (the Xtion's
  //   depth registered to the colour camera leaves such a band: 16-17 px left, right and
  //   bottom on the Bonn crowd excerpt, 11% of the image with the ragged border).
  int shadow_band_px = 0;
  int hole_block_px = 8;
  double hole_probability = 0.0;
  double far_hole_start_m = 0.0;
  double far_hole_probability = 0.0;
  int border_band_px = 0;
};

// Wheel odometry errors: odometry distance = true distance * (1 + scale_error) + noise, heading
// gains heading_bias_rad_per_m per metre driven plus noise; noise sigmas grow with sqrt(distance).
struct OdometryNoiseOptions {
  double scale_error = 0.02;
  double heading_bias_rad_per_m = 0.002;
  double distance_noise_m_per_sqrt_m = 0.003;
  double heading_noise_rad_per_sqrt_m = 0.002;
};

// The robot's differential-drive base when velocity commands drive it (ClosedLoopSimulator):
// speed and acceleration limits, actuation noise and the footprint used to count collisions.
struct DriveOptions {
  double max_linear_mps = 1.0;
  double max_angular_radps = 1.5;
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_radps2 = 3.0;
  // Actuation noise: the achieved velocity is the limited command times (1 + N(0, sigma^2)),
  // drawn every step.
  double linear_noise_fraction = 0.02;
  double angular_noise_fraction = 0.02;
  // The robot's footprint: a disc around base_link.
  double robot_radius_m = 0.3;
};

// A planar range scanner on the robot (ClosedLoopSimulator::RenderScan), beside the forward
// camera: e.g. a laser scanner seeing beside and behind the base, as robots of the iWs09's
// class carry. Its plane is horizontal at height_m above the floor, its centre forward_m ahead
// of base_link, beam 0 at -fov_deg / 2 from the base's heading, `beams` beams evenly over the
// field of view (360: all round). It sees the walls, the furniture reaching its plane (pillars,
// shelves; tables below it are not seen) and the walkers' body parts at that height (at 1.0 m:
// torso and arms); ranges get Gaussian noise of range_noise_m. Off: no scan.
struct ScannerOptions {
  bool enabled = false;
  double height_m = 1.0;
  double forward_m = 0.0;
  double fov_deg = 360.0;
  int beams = 720;
  double min_range_m = 0.1;
  double max_range_m = 8.0;
  double range_noise_m = 0.01;
};

struct SimOptions {
  CameraMotion camera_motion = CameraMotion::kWheeled;
  int seed = 1;
  // Seed of the pedestrians (looks, speeds, walks); < 0: follows `seed`.
  int crowd_seed = -1;
  // Frames to render; ignored when route.laps > 0.
  int num_frames = 150;
  double frame_rate_hz = 10.0;
  // Stamp of the first frame.
  double start_time_s = 1600000000.0;
  // Grey-level sigma of additive image noise.
  double image_noise_sigma = 2.0;
  // Exposure time of the colour image, centred on the stamp: the static scene is blurred along
  // the path each pixel takes while the camera moves during it (0: no motion blur).
  double exposure_s = 0.0;
  CameraIntrinsics intrinsics;
  RoomOptions room;
  RouteOptions route;
  CameraMountOptions camera_mount;
  HandheldOptions handheld;
  CrowdOptions crowd;
  DepthNoiseOptions depth_noise;
  OdometryNoiseOptions odometry;
  DriveOptions drive;
  ScannerOptions scanner;

  bool handheld_camera() const { return camera_motion == CameraMotion::kHandheld; }
  int effective_crowd_seed() const { return crowd_seed < 0 ? seed : crowd_seed; }
};

// Each overload reads the keys of one section; all throw LoadError on a bad value or unknown key.
void ReadOptions(const OptionReader& reader, RoomOptions* options);
void ReadOptions(const OptionReader& reader, RouteOptions* options);
void ReadOptions(const OptionReader& reader, CameraMountOptions* options);
void ReadOptions(const OptionReader& reader, HandheldOptions* options);
void ReadOptions(const OptionReader& reader, CrowdOptions* options);
void ReadOptions(const OptionReader& reader, DepthNoiseOptions* options);
void ReadOptions(const OptionReader& reader, OdometryNoiseOptions* options);
void ReadOptions(const OptionReader& reader, DriveOptions* options);
void ReadOptions(const OptionReader& reader, ScannerOptions* options);
// `reader` is the `sim:` section: seed, num_frames, ..., camera: {fx_px, ...}, room: {...}, ...
void ReadOptions(const OptionReader& reader, SimOptions* options);

// Loads the `sim:` section of a scenario file; throws LoadError (also for any other top-level
// key).
SimOptions LoadSimOptions(const std::string& path);

}  // namespace sim
}  // namespace icgm
