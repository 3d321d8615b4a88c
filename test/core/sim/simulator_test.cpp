// The rendered frames agree with the simulator's own ground truth: static geometry is
// consistent between frames under the true camera motion, the dynamic mask is exactly where
// pedestrians change the depth, depth noise follows the configured model, and output is a
// deterministic function of the seed.
#include "core/sim/simulator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/sim/depth_noise.h"

namespace icgm::sim {
namespace {

SimOptions SmallScenario(int pedestrians) {
  SimOptions o;
  o.seed = 3;
  o.num_frames = 40;
  o.frame_rate_hz = 10.0;
  o.room.num_tables = 12;
  o.room.num_shelves = 6;
  o.route.speed_mps = 0.5;
  o.route.acceleration_mps2 = 1.0;
  // Start shortly before the first corner, so the frames contain translation and rotation.
  o.route.start_offset_m = 4.5;
  o.crowd.num_pedestrians = pedestrians;
  o.crowd.crossing_fraction = 0.7;
  return o;
}

// Depth at a sub-pixel position by bilinear interpolation of inverse depth (exact on planes);
// false near image borders, invalid pixels or depth edges.
bool InterpolateDepth(const cv::Mat& depth, double u, double v, double* z) {
  const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
  if (u0 < 0 || v0 < 0 || u0 + 1 >= depth.cols || v0 + 1 >= depth.rows) return false;
  const float q[4] = {depth.at<float>(v0, u0), depth.at<float>(v0, u0 + 1),
                      depth.at<float>(v0 + 1, u0), depth.at<float>(v0 + 1, u0 + 1)};
  float lo = q[0], hi = q[0];
  for (float x : q) {
    if (!(x > 0.0f)) return false;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  if (hi > 1.02f * lo) return false;
  const double a = u - u0, b = v - v0;
  const double inv =
      (1 - a) * (1 - b) / q[0] + a * (1 - b) / q[1] + (1 - a) * b / q[2] + a * b / q[3];
  *z = 1.0 / inv;
  return true;
}

struct Consistency {
  int tested = 0;
  int agreeing = 0;
  double Fraction() const { return tested ? static_cast<double>(agreeing) / tested : 0.0; }
};

// Moves every 3rd pixel of frame a into frame b with the true relative pose and compares the
// predicted depth with b's depth; `tolerance(z)` is the allowed difference.
template <typename Tolerance>
Consistency CheckStaticConsistency(const Simulator& sim, const SimFrame& a, const SimFrame& b,
                                   Tolerance tolerance) {
  const CameraIntrinsics& K = sim.intrinsics();
  const Pose3 T_b_a = Between(b.T_world_camera, a.T_world_camera);
  Consistency c;
  for (int v = 0; v < a.depth_m.rows; v += 3) {
    for (int u = 0; u < a.depth_m.cols; u += 3) {
      const float z = a.depth_m.at<float>(v, u);
      if (!(z > 0.0f)) continue;
      const Eigen::Vector3d p_b = T_b_a * K.BackProject(u, v, z);
      if (p_b.z() < 0.1) continue;
      const Eigen::Vector2d uv = K.Project(p_b);
      double z_b;
      if (!InterpolateDepth(b.depth_m, uv.x(), uv.y(), &z_b)) continue;
      ++c.tested;
      if (std::abs(z_b - p_b.z()) < tolerance(p_b.z())) ++c.agreeing;
    }
  }
  return c;
}

TEST(SimulatorTest, CameraMountFollowsFrameConventions) {
  CameraMountOptions m;
  m.height_m = 1.0;
  m.forward_m = 0.1;
  m.pitch_down_deg = 0.0;
  m.yaw_left_deg = 0.0;
  const Pose3 T = CameraMountPose(m);
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY()));
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(0.1, 0.0, 1.0)));
  m.pitch_down_deg = 10.0;
  m.yaw_left_deg = 30.0;
  const Eigen::Vector3d axis = CameraMountPose(m).linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(axis.z(), -std::sin(10.0 * M_PI / 180.0), 1e-12);             // looks down
  EXPECT_NEAR(std::atan2(axis.y(), axis.x()), 30.0 * M_PI / 180.0, 1e-12);  // and left
}

TEST(SimulatorTest, StaticGeometryIsConsistentUnderTrueMotionExactly) {
  const Simulator sim(SmallScenario(0));
  RenderFlags ideal;
  ideal.sensor_effects = false;
  for (size_t i : {5u, 20u, 30u}) {
    const SimFrame a = sim.Render(i, ideal);
    const SimFrame b = sim.Render(i + 4, ideal);
    ASSERT_GT(TranslationNorm(Between(a.T_world_camera, b.T_world_camera)), 0.05);
    const Consistency c =
        CheckStaticConsistency(sim, a, b, [](double z) { return 1e-4 * z + 1e-5; });
    EXPECT_GT(c.tested, 15000) << "frame " << i;
    // Only pixels that become occluded (or disoccluded) may disagree.
    EXPECT_GT(c.Fraction(), 0.97) << "frame " << i;
  }
}

TEST(SimulatorTest, StaticGeometryIsConsistentWithinDepthNoise) {
  const Simulator sim(SmallScenario(0));
  const SimFrame a = sim.Render(20);
  const SimFrame b = sim.Render(22);
  const DepthNoiseOptions& noise = sim.options().depth_noise;
  const Consistency c = CheckStaticConsistency(
      sim, a, b, [&](double z) { return 5.0 * DepthNoiseSigma(noise, z) + 1e-3; });
  EXPECT_GT(c.tested, 10000);
  EXPECT_GT(c.Fraction(), 0.95);
  // A wrong pose must break the agreement (the check has teeth).
  SimFrame shifted = b;
  shifted.T_world_camera = b.T_world_camera * Eigen::Translation3d(0.02, 0.0, 0.2);
  const Consistency wrong = CheckStaticConsistency(
      sim, a, shifted, [&](double z) { return 5.0 * DepthNoiseSigma(noise, z) + 1e-3; });
  EXPECT_LT(wrong.Fraction(), 0.2);
}

TEST(SimulatorTest, DepthNoiseRangeAndDropoutFollowTheModel) {
  const Simulator sim(SmallScenario(0));
  RenderFlags ideal_flags;
  ideal_flags.sensor_effects = false;
  const SimFrame ideal = sim.Render(15, ideal_flags);
  const SimFrame noisy = sim.Render(15);
  const DepthNoiseOptions& o = sim.options().depth_noise;
  double sum_sq = 0.0, sigma_sq = 0.0;
  int band = 0, in_range = 0, dropped = 0;
  for (int v = 1; v + 1 < ideal.depth_m.rows; ++v) {
    for (int u = 1; u + 1 < ideal.depth_m.cols; ++u) {
      const float z = ideal.depth_m.at<float>(v, u);
      const float n = noisy.depth_m.at<float>(v, u);
      if (z < o.min_range_m || z > o.max_range_m) {
        EXPECT_TRUE(std::isnan(n)) << "out of range depth must be invalid: " << z;
        continue;
      }
      ++in_range;
      if (std::isnan(n)) {
        ++dropped;
        continue;
      }
      if (z > 2.0f && z < 4.5f) {
        sum_sq += (n - z) * (n - z);
        sigma_sq += DepthNoiseSigma(o, z) * DepthNoiseSigma(o, z);
        ++band;
      }
    }
  }
  ASSERT_GT(band, 5000);
  EXPECT_NEAR(std::sqrt(sum_sq / band), std::sqrt(sigma_sq / band),
              0.1 * std::sqrt(sigma_sq / band));
  // Holes: random dropout everywhere plus edge holes, so at least the dropout rate.
  const double hole_rate = static_cast<double>(dropped) / in_range;
  EXPECT_GT(hole_rate, 0.8 * o.dropout_probability);
  EXPECT_LT(hole_rate, o.dropout_probability + 0.1);
}

TEST(SimulatorTest, XtionHolesFollowTheModelAndAreOffByDefault) {
  SimOptions options = SmallScenario(3);
  const Simulator plain(options);
  RenderFlags ideal_flags;
  ideal_flags.sensor_effects = false;
  const SimFrame ideal = plain.Render(15, ideal_flags);
  const SimFrame today = plain.Render(15);
  // Off by default: no change to the depth and no draw from the generator.
  {
    cv::Mat depth = today.depth_m.clone();
    cv::RNG rng(7), reference(7);
    ApplyDepthHoles(DepthNoiseOptions(), ideal.depth_m, rng, &depth);
    EXPECT_EQ(rng.next(), reference.next());
    EXPECT_EQ(cv::countNonZero(depth != today.depth_m),
              cv::countNonZero(today.depth_m != today.depth_m));
  }
  options.depth_noise.shadow_band_px = 3;
  options.depth_noise.hole_probability = 0.1;
  options.depth_noise.far_hole_start_m = 3.0;
  options.depth_noise.far_hole_probability = 0.5;
  const SimFrame holed = Simulator(options).Render(15);
  const DepthNoiseOptions& o = options.depth_noise;
  cv::Mat nearest;
  cv::erode(ideal.depth_m, nearest, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(7, 7)));
  int shadow = 0, near = 0, near_holes = 0, far = 0, far_holes = 0;
  double far_expected = 0.0;
  for (int v = 0; v < ideal.depth_m.rows; ++v) {
    for (int u = 0; u < ideal.depth_m.cols; ++u) {
      const float z = ideal.depth_m.at<float>(v, u);
      const bool hole = std::isnan(holed.depth_m.at<float>(v, u));
      if (std::isnan(today.depth_m.at<float>(v, u))) {
        EXPECT_TRUE(hole) << "holes only add to today's";
        continue;
      }
      if (z > (1.0f + o.edge_jump_fraction) * nearest.at<float>(v, u)) {
        ++shadow;
        EXPECT_TRUE(hole) << "a pixel in a nearer surface's shadow band keeps depth";
        continue;
      }
      if (z < o.far_hole_start_m) {
        ++near;
        near_holes += hole;
      } else {
        ++far;
        far_holes += hole;
        far_expected +=
            o.hole_probability +
            o.far_hole_probability *
                std::min(1.0, (z - o.far_hole_start_m) / (o.max_range_m - o.far_hole_start_m));
      }
    }
  }
  ASSERT_GT(shadow, 500) << "the scene has depth edges";
  ASSERT_GT(near, 20000);
  ASSERT_GT(far, 20000);
  // Holes come in 8 px blocks (4800 in the image), so the shares are close to the model's.
  EXPECT_NEAR(static_cast<double>(near_holes) / near, o.hole_probability, 0.03);
  EXPECT_NEAR(static_cast<double>(far_holes) / far, far_expected / far, 0.05);
  EXPECT_GT(static_cast<double>(far_holes) / far, 2.0 * o.hole_probability);
}

TEST(SimulatorTest, BorderBandLeavesNoDepthAlongTheImageBorderOnly) {
  // The Xtion's depth registered to the colour camera has none within 16-17 px of the left,
  // right and bottom border on the Bonn crowd excerpt; border_band_px blanks such a band and
  // nothing else, without a draw from the generator.
  const cv::Mat ideal(48, 64, CV_32FC1, cv::Scalar(2.0f));
  DepthNoiseOptions o;
  o.border_band_px = 5;
  cv::Mat depth = ideal.clone();
  cv::RNG rng(3), reference(3);
  ApplyDepthHoles(o, ideal, rng, &depth);
  EXPECT_EQ(rng.next(), reference.next());
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      const bool band = u < 5 || v < 5 || u >= depth.cols - 5 || v >= depth.rows - 5;
      EXPECT_EQ(std::isnan(depth.at<float>(v, u)), band) << u << ", " << v;
    }
  }
  EXPECT_EQ(cv::countNonZero(depth == depth), (64 - 10) * (48 - 10));
}

TEST(SimulatorTest, QuantizedDepthStepsLikeAStructuredLightSensor) {
  DepthNoiseOptions o;
  o.disparity_focal_baseline_px_m = 40.7;
  o.disparity_step_px = 0.125;
  // Every reported depth is f*b over a whole number of disparity steps, within half a step of
  // the true disparity; the step between levels at 3 m is z^2 * step / (f*b) = 27.6 mm.
  for (double z = 0.6; z < 5.0; z += 0.037) {
    const double q = QuantizeDepth(o, z, 0.0);
    const double steps = o.disparity_focal_baseline_px_m / q / o.disparity_step_px;
    EXPECT_NEAR(steps, std::round(steps), 1e-6) << z;
    EXPECT_LE(std::abs(o.disparity_focal_baseline_px_m / q - o.disparity_focal_baseline_px_m / z),
              0.5 * o.disparity_step_px + 1e-9)
        << z;
  }
  const double level = QuantizeDepth(o, 3.0, 0.0);
  const double next = QuantizeDepth(o, level + 0.03, 0.0);
  EXPECT_NEAR(next - level, 0.0276, 0.0015);
  EXPECT_DOUBLE_EQ(QuantizeDepth(DepthNoiseOptions(), 3.0, 0.4), 3.0) << "off by default";

  // Rendered: on the far surfaces most horizontal neighbours share one depth (the real Xtion
  // sequences show about 80%), which white Gaussian noise never gives.
  SimOptions options = SmallScenario(0);
  options.depth_noise.sigma_base_m = 0.0;
  options.depth_noise.sigma_quadratic_per_m = 0.0;
  options.depth_noise.disparity_focal_baseline_px_m = 40.7;
  options.depth_noise.disparity_sigma_px = 0.02;
  const Simulator sim(options);
  RenderFlags ideal_flags;
  ideal_flags.sensor_effects = false;
  const SimFrame ideal = sim.Render(15, ideal_flags);
  const SimFrame noisy = sim.Render(15);
  int pairs = 0, equal = 0, far = 0;
  double sum_sq = 0.0;
  for (int v = 0; v < noisy.depth_m.rows; ++v) {
    for (int u = 0; u + 1 < noisy.depth_m.cols; ++u) {
      const float a = noisy.depth_m.at<float>(v, u), b = noisy.depth_m.at<float>(v, u + 1);
      const float z = ideal.depth_m.at<float>(v, u);
      if (std::isnan(a) || std::isnan(b) || z < 2.5f || z > 4.5f) continue;
      ++far;
      sum_sq += (a - z) * (a - z);
      if (std::abs(a - b) > 0.1f) continue;
      ++pairs;
      equal += a == b;
    }
  }
  ASSERT_GT(pairs, 5000);
  EXPECT_GT(static_cast<double>(equal) / pairs, 0.6);
  // The error is about a uniform spread over one step (28-60 mm at 3-4.5 m): rms 8-17 mm.
  const double rms = std::sqrt(sum_sq / far);
  EXPECT_GT(rms, 0.005);
  EXPECT_LT(rms, 0.02);
}

TEST(SimulatorTest, DynamicMaskIsExactlyWherePedestriansChangeTheView) {
  const Simulator sim(SmallScenario(40));
  RenderFlags with, without;
  with.sensor_effects = without.sensor_effects = false;
  without.pedestrians = false;
  int frames_with_people = 0;
  for (size_t i = 0; i < sim.size(); i += 3) {
    const SimFrame a = sim.Render(i, with);
    const SimFrame b = sim.Render(i, without);
    EXPECT_EQ(cv::countNonZero(b.dynamic_mask), 0);
    cv::Mat depth_changed = cv::abs(a.depth_m - b.depth_m) > 1e-6;
    cv::Mat differ;
    cv::compare(depth_changed, a.dynamic_mask, differ, cv::CMP_NE);
    EXPECT_EQ(cv::countNonZero(differ), 0) << "frame " << i;
    // Pedestrians only occlude: nothing gets farther, colours change only under the mask.
    cv::Mat farther = a.depth_m > b.depth_m + 1e-6f;
    EXPECT_EQ(cv::countNonZero(farther), 0);
    cv::Mat colour_changed;
    cv::compare(a.bgr, b.bgr, colour_changed, cv::CMP_NE);
    cv::cvtColor(colour_changed, colour_changed, cv::COLOR_BGR2GRAY);
    cv::Mat changed_outside_mask = colour_changed & (a.dynamic_mask == 0);
    EXPECT_EQ(cv::countNonZero(changed_outside_mask), 0);
    if (cv::countNonZero(a.dynamic_mask) > 0.05 * a.dynamic_mask.total()) ++frames_with_people;
  }
  EXPECT_GT(frames_with_people, 2);
}

TEST(SimulatorTest, PedestriansKeepClearOfTheRobot) {
  const Simulator sim(SmallScenario(60));
  const double clearance = sim.options().crowd.robot_clearance_m;
  for (size_t i = 0; i < sim.size(); ++i) {
    std::vector<CylinderPrimitive> parts;
    sim.crowd().AppendBodyParts(i, &parts);
    const PlanarPose& robot = sim.planar_pose(i);
    for (const CylinderPrimitive& p : parts) {
      const double d = std::hypot(p.x_m - robot.x_m, p.y_m - robot.y_m) - p.radius_m;
      ASSERT_GE(d, clearance - 1e-3) << "frame " << i;
    }
  }
}

TEST(SimulatorTest, WheelOdometryScaleAndHeadingBiasOnTheFirstStraight) {
  SimOptions o;
  o.num_frames = 120;
  o.route.speed_mps = 0.5;
  o.odometry.scale_error = 0.05;
  o.odometry.heading_bias_rad_per_m = 0.01;
  o.odometry.distance_noise_m_per_sqrt_m = 0.0;
  o.odometry.heading_noise_rad_per_sqrt_m = 0.0;
  const Simulator sim(o);
  // The loop starts in the middle of the south side: the first half side is straight.
  const double straight_m = 0.5 * o.room.width_m - o.route.inset_m - o.route.corner_radius_m - 0.05;
  size_t last = 0;
  while (last + 1 < sim.size() &&
         TranslationNorm(Between(sim.T_world_base(0), sim.T_world_base(last + 1))) < straight_m) {
    ++last;
  }
  ASSERT_GT(last, 20u);
  double odom_path = 0.0;
  for (size_t i = 1; i <= last; ++i) {
    odom_path +=
        TranslationNorm(Between(sim.odometry(i - 1).T_odom_base, sim.odometry(i).T_odom_base));
  }
  const double true_path = TranslationNorm(Between(sim.T_world_base(0), sim.T_world_base(last)));
  EXPECT_NEAR(odom_path / true_path, 1.05, 1e-6);
  const double yaw = Eigen::AngleAxisd(sim.odometry(last).T_odom_base.linear()).angle();
  EXPECT_NEAR(yaw, 0.01 * true_path, 1e-6);
}

bool SameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

TEST(SimulatorTest, OutputIsADeterministicFunctionOfTheSeed) {
  SimOptions o = SmallScenario(20);
  o.num_frames = 12;
  const Simulator first(o), second(o);
  o.seed += 1;
  const Simulator other(o);
  const SimFrame a = first.Render(10), b = second.Render(10), c = other.Render(10);
  EXPECT_TRUE(SameBytes(a.bgr, b.bgr));
  EXPECT_TRUE(SameBytes(a.depth_m, b.depth_m));  // NaN payloads included
  EXPECT_TRUE(SameBytes(a.dynamic_mask, b.dynamic_mask));
  EXPECT_TRUE(a.odometry.T_odom_base.isApprox(b.odometry.T_odom_base, 0.0));
  EXPECT_FALSE(SameBytes(a.bgr, c.bgr));
  EXPECT_FALSE(a.odometry.T_odom_base.isApprox(c.odometry.T_odom_base, 1e-12));
  // Rendering order does not matter.
  const SimFrame earlier = first.Render(3);
  (void)earlier;
  EXPECT_TRUE(SameBytes(first.Render(10).depth_m, a.depth_m));
}

TEST(SimulatorTest, TwoLapTrajectoryIsSmoothAndCloses) {
  SimOptions o;
  o.frame_rate_hz = 7.0;
  o.route.laps = 2.0;
  o.route.speed_mps = 0.5;
  const Simulator sim(o);
  const double dt = 1.0 / o.frame_rate_hz;
  for (size_t i = 1; i < sim.size(); ++i) {
    const Pose3 rel = Between(sim.T_world_camera(i - 1), sim.T_world_camera(i));
    // The camera sits ahead of base_link, so it moves slightly faster than the base in turns.
    ASSERT_LE(TranslationNorm(rel), 1.1 * o.route.speed_mps * dt) << i;
    ASSERT_LE(RotationAngleRad(rel), 3.0 * M_PI / 180.0) << i;
    ASSERT_NEAR(DurationSeconds(sim.stamp(i), sim.stamp(i - 1)), dt, 1e-6);
  }
  const Pose3 loop = Between(sim.T_world_camera(0), sim.T_world_camera(sim.size() - 1));
  EXPECT_LT(TranslationNorm(loop), 1e-6);
  EXPECT_LT(RotationAngleRad(loop), 1e-6);
  // The camera stays at its mount height and odometry drifts away from the truth.
  EXPECT_NEAR(sim.T_world_camera(100).translation().z(), o.camera_mount.height_m, 1e-9);
  const Pose3 odom_loop = sim.odometry(sim.size() - 1).T_odom_base;
  EXPECT_GT(TranslationNorm(odom_loop), 0.05);
}

}  // namespace
}  // namespace icgm::sim
