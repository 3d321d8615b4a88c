#include "core/sim/sim_options.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "core/dataset/camera_options.h"

namespace icgm::sim {
namespace {

void RejectUnknownKeys(const OptionReader& reader) {
  const auto unused = reader.UnusedKeys();
  if (!unused.empty()) throw LoadError("unknown option '" + unused.front() + "'");
}

}  // namespace

void ReadOptions(const OptionReader& reader, RoomOptions* o) {
  reader.Read("width_m", &o->width_m, 4.0, 200.0);
  reader.Read("length_m", &o->length_m, 4.0, 200.0);
  reader.Read("height_m", &o->height_m, 2.2, 20.0);
  reader.Read("num_tables", &o->num_tables, 0, 500);
  reader.Read("num_shelves", &o->num_shelves, 0, 200);
  reader.Read("num_pillars", &o->num_pillars, 0, 100);
  reader.Read("poster_coverage", &o->poster_coverage, 0.0, 1.0);
  reader.Read("texel_size_m", &o->texel_size_m, 0.002, 0.1);
  reader.Read("wall_contrast", &o->wall_contrast, 0.0, 1.0);
  reader.Read("floor_contrast", &o->floor_contrast, 0.0, 1.0);
  reader.Read("furniture_contrast", &o->furniture_contrast, 0.0, 1.0);
  reader.Read("num_desks", &o->num_desks, 0, 200);
  reader.Read("num_chairs", &o->num_chairs, 0, 500);
  RejectUnknownKeys(reader);
}

void ReadOptions(const OptionReader& reader, RouteOptions* o) {
  reader.Read("inset_m", &o->inset_m, 0.5, 100.0);
  reader.Read("corner_radius_m", &o->corner_radius_m, 0.2, 50.0);
  reader.Read("speed_mps", &o->speed_mps, 0.01, 3.0);
  reader.Read("acceleration_mps2", &o->acceleration_mps2, 0.01, 10.0);
  reader.Read("laps", &o->laps, 0.0, 100.0);
  reader.Read("start_offset_m", &o->start_offset_m, 0.0, 1e4);
  RejectUnknownKeys(reader);
}

void ReadOptions(const OptionReader& reader, CameraMountOptions* o) {
  reader.Read("height_m", &o->height_m, 0.1, 2.0);
  reader.Read("forward_m", &o->forward_m, -1.0, 1.0);
  reader.Read("pitch_down_deg", &o->pitch_down_deg, -45.0, 45.0);
  reader.Read("yaw_left_deg", &o->yaw_left_deg, -90.0, 90.0);
  RejectUnknownKeys(reader);
}

void ReadOptions(const OptionReader& reader, CrowdOptions* o) {
  reader.Read("num_pedestrians", &o->num_pedestrians, 0, 1000);
  reader.Read("speed_mps", &o->speed_mps, 0.0, 3.0);
  reader.Read("speed_stddev_mps", &o->speed_stddev_mps, 0.0, 1.0);
  reader.Read("crossing_fraction", &o->crossing_fraction, 0.0, 1.0);
  reader.Read("robot_clearance_m", &o->robot_clearance_m, 0.5, 5.0);
  reader.Read("non_yielding_fraction", &o->non_yielding_fraction, 0.0, 1.0);
  reader.Read("personal_space_m", &o->personal_space_m, 0.1, 5.0);
  reader.Read("crossing_min_ahead_m", &o->crossing_min_ahead_m, 0.0, 50.0);
  reader.Read("crossing_max_ahead_m", &o->crossing_max_ahead_m, 0.1, 50.0);
  reader.Read("crossing_min_side_m", &o->crossing_min_side_m, 0.0, 50.0);
  reader.Read("crossing_max_side_m", &o->crossing_max_side_m, 0.1, 50.0);
  RejectUnknownKeys(reader);
  if (o->crossing_max_ahead_m <= o->crossing_min_ahead_m ||
      o->crossing_max_side_m <= o->crossing_min_side_m) {
    throw LoadError(reader.path() + ": crossing_max_*_m must exceed crossing_min_*_m");
  }
}

void ReadOptions(const OptionReader& reader, HandheldOptions* o) {
  reader.Read("x_m", &o->x_m, 0.0, 200.0);
  reader.Read("y_m", &o->y_m, 0.0, 200.0);
  reader.Read("height_m", &o->height_m, 0.3, 2.5);
  reader.Read("yaw_deg", &o->yaw_deg, -360.0, 360.0);
  reader.Read("pitch_down_deg", &o->pitch_down_deg, -60.0, 60.0);
  reader.Read("drift_speed_mps", &o->drift_speed_mps, 0.0, 2.0);
  reader.Read("drift_period_s", &o->drift_period_s, 0.5, 600.0);
  reader.Read("pan_amplitude_deg", &o->pan_amplitude_deg, 0.0, 90.0);
  reader.Read("tilt_amplitude_deg", &o->tilt_amplitude_deg, 0.0, 45.0);
  reader.Read("roll_amplitude_deg", &o->roll_amplitude_deg, 0.0, 45.0);
  reader.Read("pan_period_s", &o->pan_period_s, 0.5, 600.0);
  reader.Read("jitter_m", &o->jitter_m, 0.0, 0.1);
  reader.Read("jitter_deg", &o->jitter_deg, 0.0, 10.0);
  reader.Read("walk_speed_mps", &o->walk_speed_mps, 0.0, 3.0);
  reader.Read("walk_bob_m", &o->walk_bob_m, 0.0, 0.2);
  reader.Read("walk_step_hz", &o->walk_step_hz, 0.1, 5.0);
  reader.Read("recorded_trajectory", &o->recorded_trajectory);
  reader.Read("recorded_start_s", &o->recorded_start_s, 0.0, 1e6);
  RejectUnknownKeys(reader);
}

void ReadOptions(const OptionReader& reader, DepthNoiseOptions* o) {
  reader.Read("min_range_m", &o->min_range_m, 0.0, 10.0);
  reader.Read("max_range_m", &o->max_range_m, 0.1, 100.0);
  reader.Read("sigma_base_m", &o->sigma_base_m, 0.0, 0.5);
  reader.Read("sigma_quadratic_per_m", &o->sigma_quadratic_per_m, 0.0, 0.5);
  reader.Read("sigma_offset_m", &o->sigma_offset_m, 0.0, 10.0);
  reader.Read("dropout_probability", &o->dropout_probability, 0.0, 1.0);
  reader.Read("edge_jump_fraction", &o->edge_jump_fraction, 0.001, 10.0);
  reader.Read("edge_hole_probability", &o->edge_hole_probability, 0.0, 1.0);
  reader.Read("disparity_focal_baseline_px_m", &o->disparity_focal_baseline_px_m, 0.0, 1000.0);
  reader.Read("disparity_step_px", &o->disparity_step_px, 0.001, 10.0);
  reader.Read("disparity_sigma_px", &o->disparity_sigma_px, 0.0, 10.0);
  reader.Read("shadow_band_px", &o->shadow_band_px, 0, 100);
  reader.Read("hole_block_px", &o->hole_block_px, 1, 200);
  reader.Read("hole_probability", &o->hole_probability, 0.0, 1.0);
  reader.Read("far_hole_start_m", &o->far_hole_start_m, 0.0, 100.0);
  reader.Read("far_hole_probability", &o->far_hole_probability, 0.0, 1.0);
  reader.Read("border_band_px", &o->border_band_px, 0, 200);
  RejectUnknownKeys(reader);
  if (o->max_range_m <= o->min_range_m) {
    throw LoadError(reader.path() + ": max_range_m must exceed min_range_m");
  }
}

void ReadOptions(const OptionReader& reader, OdometryNoiseOptions* o) {
  reader.Read("scale_error", &o->scale_error, -0.5, 0.5);
  reader.Read("heading_bias_rad_per_m", &o->heading_bias_rad_per_m, -0.5, 0.5);
  reader.Read("distance_noise_m_per_sqrt_m", &o->distance_noise_m_per_sqrt_m, 0.0, 1.0);
  reader.Read("heading_noise_rad_per_sqrt_m", &o->heading_noise_rad_per_sqrt_m, 0.0, 1.0);
  RejectUnknownKeys(reader);
}

void ReadOptions(const OptionReader& reader, DriveOptions* o) {
  reader.Read("max_linear_mps", &o->max_linear_mps, 0.01, 5.0);
  reader.Read("max_angular_radps", &o->max_angular_radps, 0.01, 10.0);
  reader.Read("max_linear_accel_mps2", &o->max_linear_accel_mps2, 0.01, 20.0);
  reader.Read("max_angular_accel_radps2", &o->max_angular_accel_radps2, 0.01, 50.0);
  reader.Read("linear_noise_fraction", &o->linear_noise_fraction, 0.0, 0.5);
  reader.Read("angular_noise_fraction", &o->angular_noise_fraction, 0.0, 0.5);
  reader.Read("robot_radius_m", &o->robot_radius_m, 0.05, 2.0);
  RejectUnknownKeys(reader);
}

void ReadOptions(const OptionReader& reader, ScannerOptions* o) {
  reader.Read("enabled", &o->enabled);
  reader.Read("height_m", &o->height_m, 0.0, 5.0);
  reader.Read("forward_m", &o->forward_m, -2.0, 2.0);
  reader.Read("fov_deg", &o->fov_deg, 1.0, 360.0);
  reader.Read("beams", &o->beams, 2, 100000);
  reader.Read("min_range_m", &o->min_range_m, 0.0, 10.0);
  reader.Read("max_range_m", &o->max_range_m, 0.1, 100.0);
  reader.Read("range_noise_m", &o->range_noise_m, 0.0, 1.0);
  RejectUnknownKeys(reader);
  if (o->max_range_m <= o->min_range_m) {
    throw LoadError(reader.path() + ": max_range_m must exceed min_range_m");
  }
}

void ReadOptions(const OptionReader& reader, SimOptions* o) {
  reader.ReadEnum("camera_motion", &o->camera_motion);
  reader.Read("seed", &o->seed, 0, 2147483647);
  reader.Read("crowd_seed", &o->crowd_seed, -1, 2147483647);
  reader.Read("num_frames", &o->num_frames, 1, 1000000);
  reader.Read("frame_rate_hz", &o->frame_rate_hz, 0.1, 1000.0);
  reader.Read("start_time_s", &o->start_time_s, 1.0, 4e9);
  reader.Read("image_noise_sigma", &o->image_noise_sigma, 0.0, 50.0);
  reader.Read("exposure_s", &o->exposure_s, 0.0, 0.2);
  const OptionReader camera = reader.Section("camera");
  icgm::ReadOptions(camera, &o->intrinsics);  // same keys as config/camera/*.yaml
  RejectUnknownKeys(camera);
  ReadOptions(reader.Section("room"), &o->room);
  ReadOptions(reader.Section("route"), &o->route);
  ReadOptions(reader.Section("camera_mount"), &o->camera_mount);
  ReadOptions(reader.Section("handheld"), &o->handheld);
  ReadOptions(reader.Section("crowd"), &o->crowd);
  ReadOptions(reader.Section("depth_noise"), &o->depth_noise);
  ReadOptions(reader.Section("odometry"), &o->odometry);
  ReadOptions(reader.Section("drive"), &o->drive);
  ReadOptions(reader.Section("scanner"), &o->scanner);
  RejectUnknownKeys(reader);
  if (o->handheld_camera()) {
    // The route, the camera mount and the wheel odometry do not apply to a handheld camera.
    const double margin = 0.3;
    const auto inside = [&](double x, double y) {
      return x >= margin && x <= o->room.width_m - margin && y >= margin &&
             y <= o->room.length_m - margin;
    };
    const HandheldOptions& h = o->handheld;
    const double walk_m = h.walk_speed_mps * (o->num_frames - 1) / o->frame_rate_hz;
    const double yaw_rad = h.yaw_deg * M_PI / 180.0;
    if (!inside(h.x_m, h.y_m) || h.height_m > o->room.height_m - margin ||
        !inside(h.x_m + walk_m * std::cos(yaw_rad), h.y_m + walk_m * std::sin(yaw_rad))) {
      throw LoadError(reader.path() + ": handheld camera start and walk must be inside the room, " +
                      std::to_string(margin) + " m from its walls and ceiling");
    }
    return;
  }
  const double half_min = 0.5 * std::min(o->room.width_m, o->room.length_m);
  if (o->route.inset_m + o->route.corner_radius_m >= half_min) {
    throw LoadError(reader.path() + ": route.inset_m + route.corner_radius_m must be below " +
                    std::to_string(half_min) + " (half the smaller room side)");
  }
}

SimOptions LoadSimOptions(const std::string& path) {
  const OptionReader root = OptionReader::FromFile(path);
  if (!root.Has("sim")) throw LoadError("config file '" + path + "' has no 'sim:' section");
  SimOptions options;
  ReadOptions(root.Section("sim"), &options);
  RejectUnknownKeys(root);
  std::string& recorded = options.handheld.recorded_trajectory;
  if (!recorded.empty() && std::filesystem::path(recorded).is_relative()) {
    recorded = (std::filesystem::path(path).parent_path() / recorded).lexically_normal().string();
  }
  return options;
}

}  // namespace icgm::sim
