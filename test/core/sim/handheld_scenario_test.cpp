// The handheld crowd scenario (config/sim/handheld_crowd.yaml) reproduces what defeats visual
// odometry in the real Bonn "crowd" sequence: a handheld camera without wheels, an office with
// the real excerpt's texture and quantized depth, people who do not yield covering a large part
// of the image for seconds, and motion blur.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/pose.h"
#include "core/sim/sim_export.h"
#include "core/sim/simulator.h"

namespace icgm::sim {
namespace {

SimOptions Scenario(const std::string& name) {
  return LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/" + name + ".yaml");
}

double Coverage(const SimFrame& f) {
  return cv::countNonZero(f.dynamic_mask) / static_cast<double>(f.dynamic_mask.total());
}

// FAST corners on the static scene (pedestrians not rendered) with valid depth.
int StaticCorners(const Simulator& sim, size_t i) {
  RenderFlags flags;
  flags.pedestrians = false;
  const SimFrame f = sim.Render(i, flags);
  cv::Mat grey;
  cv::cvtColor(f.bgr, grey, cv::COLOR_BGR2GRAY);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(grey, corners, 20, true);
  return static_cast<int>(std::count_if(corners.begin(), corners.end(), [&](const auto& k) {
    const float z = f.depth_m.at<float>(cvRound(k.pt.y), cvRound(k.pt.x));
    return z == z;
  }));
}

// Mean absolute Laplacian of the grey image: high for sharp images.
double Sharpness(const cv::Mat& bgr) {
  cv::Mat grey, lap;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  cv::Laplacian(grey, lap, CV_32F);
  return cv::mean(cv::abs(lap))[0];
}

TEST(HandheldScenarioTest, HandheldCameraHasNoWheelsNoExtrinsicAndAHandsHeight) {
  const Simulator sim(Scenario("handheld_crowd"));
  EXPECT_FALSE(sim.has_wheel_odometry());
  EXPECT_FALSE(sim.base_to_camera().has_value());
  EXPECT_TRUE(WheelOdometryTrajectory(sim).empty());
  EXPECT_EQ(CameraGroundTruth(sim).size(), sim.size());
  EXPECT_DOUBLE_EQ(sim.options().frame_rate_hz, 30.0);
  EXPECT_GE(sim.size(), 300u);
  double path = 0.0;
  for (size_t i = 0; i < sim.size(); ++i) {
    const double z = sim.T_world_camera(i).translation().z();
    EXPECT_GT(z, 1.2);
    EXPECT_LT(z, 1.6);
    if (i > 0) {
      path += (sim.T_world_camera(i).translation() - sim.T_world_camera(i - 1).translation())
                  .norm();
    }
  }
  const double duration = (sim.size() - 1) / sim.options().frame_rate_hz;
  EXPECT_GT(path / duration, 0.04);  // a slow drift, 4-20 cm/s
  EXPECT_LT(path / duration, 0.2);
  // A wheeled scenario still has both.
  SimOptions wheeled = Scenario("static_short");
  wheeled.num_frames = 3;
  const Simulator robot(wheeled);
  EXPECT_TRUE(robot.has_wheel_odometry());
  EXPECT_TRUE(robot.base_to_camera().has_value());
  EXPECT_EQ(WheelOdometryTrajectory(robot).size(), 3u);
}

// The hand's motion per frame over scenario seeds 1-5: rms pan (about the camera's vertical
// axis) in degrees and mean step length in millimetres.
struct HandMotion {
  double pan_rms_deg = 0.0, step_mm = 0.0;
};
HandMotion MeanHandMotion(const std::string& name) {
  HandMotion mean;
  for (int seed = 1; seed <= 5; ++seed) {
    SimOptions options = Scenario(name);
    options.seed = seed;
    const Simulator sim(options);
    double pan_sq = 0.0, step = 0.0;
    for (size_t i = 1; i < sim.size(); ++i) {
      const Pose3 d = sim.T_world_camera(i - 1).inverse() * sim.T_world_camera(i);
      const Eigen::AngleAxisd aa(d.linear());
      const double pan_deg = aa.angle() * aa.axis().y() * 180.0 / M_PI;
      pan_sq += pan_deg * pan_deg;
      step += 1000.0 * d.translation().norm();
    }
    mean.pan_rms_deg += std::sqrt(pan_sq / (sim.size() - 1)) / 5.0;
    mean.step_mm += step / (sim.size() - 1) / 5.0;
  }
  return mean;
}

TEST(HandheldScenarioTest, HandTurnsAndStepsLikeTheRealExcerptsHand) {
  // The real excerpt's ground truth: pan 0.30 deg per frame rms, mean step 1.77 mm. The earlier
  // scenario (handheld_crowd_deep.yaml) turned half as much and stepped further, which made it
  // harder than the real data without walkers (README).
  const HandMotion matched = MeanHandMotion("handheld_crowd");
  const HandMotion deep = MeanHandMotion("handheld_crowd_deep");
  std::printf("pan rms %.3f / %.3f deg per frame, mean step %.2f / %.2f mm (matched / deep)\n",
              matched.pan_rms_deg, deep.pan_rms_deg, matched.step_mm, deep.step_mm);
  // Measured: 0.26 / 0.13 deg, 1.75 / 2.07 mm.
  EXPECT_GT(matched.pan_rms_deg, 0.2);
  EXPECT_LT(matched.pan_rms_deg, 0.4);
  EXPECT_GT(matched.step_mm, 1.5);
  EXPECT_LT(matched.step_mm, 2.0);
  EXPECT_LT(deep.pan_rms_deg, 0.2);
  EXPECT_GT(deep.step_mm, 2.0);
}

TEST(HandheldScenarioTest, PeopleCoverThirtyToEightyPercentOfTheImageForSecondsAtATime) {
  const Simulator sim(Scenario("handheld_crowd"));
  ASSERT_GE(sim.crowd().num_pedestrians(), 3u);
  RenderFlags ideal;
  ideal.sensor_effects = false;
  const size_t step = 3;  // 10 samples per second
  int in_band = 0, samples = 0, run = 0, longest_run = 0;
  for (size_t i = 0; i < sim.size(); i += step) {
    const double c = Coverage(sim.Render(i, ideal));
    const bool crowded = c >= 0.3 && c <= 0.8;
    in_band += crowded;
    run = crowded ? run + 1 : 0;
    longest_run = std::max(longest_run, run);
    ++samples;
  }
  EXPECT_GE(in_band, samples / 4) << in_band << " of " << samples << " samples";
  // At least a second in a row (samples 0.1 s apart).
  EXPECT_GE(longest_run * step / sim.options().frame_rate_hz, 1.0);
}

TEST(HandheldScenarioTest, StaticTextureAndDepthMatchTheRealExcerpt) {
  // Figures measured on the real Bonn crowd excerpt with icgm_rgbd_scene_stats (the front end's
  // 1000 ORB keypoints; beyond 2.5 m, where the room is, as people stand nearer): 608 keypoints
  // per frame with depth beyond 2.5 m (10th-90th percentile over frames 357-807), 80% of
  // horizontally neighbouring pixels 2.5-4.5 m away of equal depth (disparity quantization).
  const Simulator plain(Scenario("handheld_crowd"));
  const Simulator cafeteria(Scenario("static_short"));
  auto orb = cv::ORB::create(1000);
  int static_keypoints = 0, plain_corners = 0, cafeteria_corners = 0;
  size_t pairs = 0, equal = 0;
  for (int k = 0; k < 3; ++k) {
    const SimFrame f = plain.Render(k * plain.size() / 3);
    std::vector<cv::KeyPoint> keypoints;
    orb->detect(f.bgr, keypoints);
    for (const cv::KeyPoint& p : keypoints) {
      const int u = cvRound(p.pt.x), v = cvRound(p.pt.y);
      const float z = f.depth_m.at<float>(v, u);
      static_keypoints += z == z && f.dynamic_mask.at<uint8_t>(v, u) == 0;
    }
    for (int v = 0; v < f.depth_m.rows; ++v) {
      for (int u = 0; u + 1 < f.depth_m.cols; ++u) {
        const float a = f.depth_m.at<float>(v, u), b = f.depth_m.at<float>(v, u + 1);
        if (!(a >= 2.5f && a <= 4.5f) || !(std::abs(a - b) < 0.1f)) continue;
        ++pairs;
        equal += a == b;
      }
    }
    plain_corners += StaticCorners(plain, k * plain.size() / 3);
    cafeteria_corners += StaticCorners(cafeteria, k * cafeteria.size() / 3);
  }
  EXPECT_GT(static_keypoints / 3, 450);
  EXPECT_LT(static_keypoints / 3, 800);
  ASSERT_GT(pairs, 10000u);
  EXPECT_GT(static_cast<double>(equal) / pairs, 0.6);
  // Still an office, not the poster-covered cafeteria.
  EXPECT_LT(plain_corners * 2, cafeteria_corners) << plain_corners << " vs " << cafeteria_corners;
}

TEST(HandheldScenarioTest, MotionBlurSoftensTheColourImageOnly) {
  SimOptions options = Scenario("handheld_crowd");
  options.num_frames = 40;
  const Simulator blurred(options);
  options.exposure_s = 0.0;
  const Simulator sharp(options);
  RenderFlags static_only;
  static_only.pedestrians = false;
  double ratio_sum = 0.0;
  for (size_t i = 5; i < 40; i += 10) {
    const SimFrame a = blurred.Render(i, static_only), b = sharp.Render(i, static_only);
    ratio_sum += Sharpness(a.bgr) / Sharpness(b.bgr);
    EXPECT_GT(cv::norm(a.bgr, b.bgr, cv::NORM_L1), 0.0);
    // Depth and mask are not blurred.
    EXPECT_EQ(cv::norm(a.dynamic_mask, b.dynamic_mask, cv::NORM_INF), 0.0);
  }
  EXPECT_LT(ratio_sum / 4, 0.95);
}

TEST(HandheldScenarioTest, NonYieldingPedestriansComeCloserThanTheClearance) {
  const Simulator sim(Scenario("handheld_crowd"));
  const CrowdOptions& crowd = sim.options().crowd;
  ASSERT_EQ(crowd.non_yielding_fraction, 1.0);
  double closest = 1e9;
  for (size_t i = 0; i < sim.size(); ++i) {
    std::vector<CylinderPrimitive> parts;
    sim.crowd().AppendBodyParts(i, &parts);
    const PlanarPose& camera = sim.planar_pose(i);
    for (const CylinderPrimitive& p : parts) {
      closest = std::min(closest, std::hypot(p.x_m - camera.x_m, p.y_m - camera.y_m) - p.radius_m);
    }
  }
  EXPECT_LT(closest, crowd.robot_clearance_m);
  // Yet nobody walks into the camera.
  EXPECT_GT(closest, 0.5 * crowd.personal_space_m);
}

TEST(HandheldScenarioTest, NonYieldingFractionSparesTheOthers) {
  SimOptions o = Scenario("crowded");
  o.num_frames = 100;
  o.crowd.non_yielding_fraction = 0.5;
  const Simulator sim(o);
  const size_t n = sim.crowd().num_pedestrians();
  std::vector<double> closest(n, 1e9);
  for (size_t i = 0; i < sim.size(); ++i) {
    const PlanarPose& robot = sim.planar_pose(i);
    for (size_t k = 0; k < n; ++k) {
      const PedestrianState& s = sim.crowd().state(i, k);
      closest[k] = std::min(closest[k], std::hypot(s.x_m - robot.x_m, s.y_m - robot.y_m));
    }
  }
  // Walkers 0, 2, 4, ... yield (body radius below 0.4 m); some of 1, 3, 5, ... come closer.
  int closer = 0;
  for (size_t k = 0; k < n; ++k) {
    if (k % 2 == 0) {
      EXPECT_GT(closest[k], o.crowd.robot_clearance_m) << "walker " << k;
    } else {
      closer += closest[k] < o.crowd.robot_clearance_m;
    }
  }
  EXPECT_GT(closer, 0);
}

}  // namespace
}  // namespace icgm::sim
