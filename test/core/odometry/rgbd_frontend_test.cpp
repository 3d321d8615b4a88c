#include "core/odometry/rgbd_frontend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/trajectory.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

const std::string kTumDir = std::string(ICGM_SHARED_DATA_DIR) + "/tum_fr1_xyz";
constexpr size_t kFrames = 60;

std::optional<TumDataset> OpenTum() {
  if (!std::filesystem::exists(kTumDir + "/rgb.txt")) return std::nullopt;
  const CameraIntrinsics k =
      LoadCameraIntrinsics(std::string(ICGM_SOURCE_DIR) + "/config/camera/tum_fr1.yaml");
  return TumDataset::Open(kTumDir, k);
}

FrontendOptions ShippedOptions() {
  FrontendOptions o;
  ReadFrontendOptions(
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/odometry.yaml"),
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/icgm.yaml"), &o);
  return o;
}

// Largest position error of the estimate after expressing both trajectories relative to their
// first pose (no fitting): what a caller starting at a known pose would see.
double MaxRelativeError(const TumDataset& data, const Trajectory& est) {
  const std::optional<Pose3> gt0 = PoseAt(data.groundtruth(), est.front().stamp);
  EXPECT_TRUE(gt0.has_value());
  double worst = 0.0;
  for (const StampedPose& e : est) {
    const std::optional<Pose3> gt = PoseAt(data.groundtruth(), e.stamp);
    EXPECT_TRUE(gt.has_value());
    if (!gt || !gt0) continue;
    const Pose3 gt_rel = Between(*gt0, *gt);
    const Pose3 est_rel = Between(est.front().pose, e.pose);
    worst = std::max(worst, (gt_rel.translation() - est_rel.translation()).norm());
  }
  return worst;
}

double GroundTruthPathLength(const TumDataset& data, size_t frames) {
  double length = 0.0;
  for (size_t i = 1; i < frames; ++i) {
    const auto a = PoseAt(data.groundtruth(), data.frame(i - 1).stamp);
    const auto b = PoseAt(data.groundtruth(), data.frame(i).stamp);
    if (a && b) length += (b->translation() - a->translation()).norm();
  }
  return length;
}

TEST(RgbdFrontendTest, FollowsGroundTruthOnTumFr1Xyz) {
  const std::optional<TumDataset> data = OpenTum();
  if (!data) GTEST_SKIP() << "TUM fr1/xyz not found in " << kTumDir;
  ASSERT_GE(data->size(), kFrames);
  FrontendOptions options = ShippedOptions();
  RgbdFrontend frontend(options, data->intrinsics());
  size_t keyframes_seen = 0;
  frontend.SetKeyframeCallback([&](const KeyframePtr& kf) {
    EXPECT_EQ(kf->id, keyframes_seen);
    EXPECT_EQ(kf->points_m.size(), kf->features.size());
    EXPECT_EQ(kf->robust.size(), kf->features.size());
    EXPECT_FALSE(kf->depth_m.empty());
    // A registration covariance exactly when vision placed the keyframe.
    EXPECT_EQ(kf->covariance.has_value(), kf->relative_source == MotionSource::kVision);
    if (kf->covariance) {
      EXPECT_GT(kf->covariance->diagonal().minCoeff(), 0.0);
    }
    ++keyframes_seen;
  });
  Trajectory est;
  for (size_t i = 0; i < kFrames; ++i) {
    const FrontendFrameResult r =
        frontend.ProcessFrame(data->frame(i).stamp, data->LoadBgr(i), data->LoadDepthM(i));
    ASSERT_TRUE(r.status.ok()) << r.status.reason();
    if (i > 0) {
      EXPECT_EQ(r.source, MotionSource::kVision)
          << "frame " << i << ": " << r.registration.status.reason();
      EXPECT_GT(r.registration.inliers, 30u);
    }
    est.push_back({r.stamp, r.odom_camera});
  }
  // The camera travels about 0.3 m over these 2 s. Absolute trajectory error after Horn
  // alignment (TUM benchmark); measured about 0.01 m, the bounds are loose on purpose.
  EXPECT_GT(GroundTruthPathLength(*data, kFrames), 0.15);
  TrajectoryEvaluation ev;
  const Status s = EvaluateTrajectory(data->groundtruth(), est, TrajectoryEvalOptions(), &ev);
  ASSERT_TRUE(s.ok()) << s.reason();
  EXPECT_EQ(ev.num_associated(), kFrames);
  EXPECT_LT(ev.ate.rmse, 0.03);
  EXPECT_LT(ev.ate.max, 0.06);
  // Without alignment the start-up is included; still well below the distance travelled.
  EXPECT_LT(MaxRelativeError(*data, est), 0.08);
  EXPECT_GE(keyframes_seen, 1u);
  EXPECT_EQ(keyframes_seen, frontend.num_keyframes());
  EXPECT_DOUBLE_EQ(frontend.fusion_stats().VisionShareByFrames(), 1.0);
}

// Front end ATE (Horn-aligned) over the first `frames` frames of fr1/xyz with `intrinsics`.
double TumAteM(const TumDataset& data, const CameraIntrinsics& intrinsics, size_t frames) {
  RgbdFrontend frontend(ShippedOptions(), intrinsics);
  Trajectory est;
  for (size_t i = 0; i < frames; ++i) {
    const FrontendFrameResult r = frontend.ProcessFrame(data.frame(i).stamp, data.LoadBgr(i),
                                                        data.LoadDepthM(i),
                                                        data.frame(i).depth_stamp);
    EXPECT_TRUE(r.status.ok()) << r.status.reason();
    est.push_back({r.stamp, r.odom_camera});
  }
  TrajectoryEvaluation ev;
  const Status s = EvaluateTrajectory(data.groundtruth(), est, TrajectoryEvalOptions(), &ev);
  EXPECT_TRUE(s.ok()) << s.reason();
  return ev.ate.rmse;
}

TEST(RgbdFrontendTest, RollingShutterCompensationLowersTheErrorOnTumFr1Xyz) {
  const std::optional<TumDataset> data = OpenTum();
  if (!data) GTEST_SKIP() << "TUM fr1/xyz not found in " << kTumDir;
  constexpr size_t kRollingFrames = 100;
  ASSERT_GE(data->size(), kRollingFrames);
  const CameraIntrinsics rolling = data->intrinsics();
  ASSERT_GT(rolling.readout_s, 0.0);  // the shipped fr1 camera has a rolling shutter
  CameraIntrinsics global = rolling;
  global.readout_s = 0.0;
  global.first_row_offset_s = 0.0;
  const double rolling_ate_m = TumAteM(*data, rolling, kRollingFrames);
  const double global_ate_m = TumAteM(*data, global, kRollingFrames);
  std::printf("fr1/xyz, %zu frames: ATE %.4f m with rolling-shutter compensation, %.4f m as a "
              "global shutter\n",
              kRollingFrames, rolling_ate_m, global_ate_m);
  // Measured 0.0111 vs 0.0141 m (200 frames: 0.0107 vs 0.0127, 300: 0.0111 vs 0.0138).
  EXPECT_LT(rolling_ate_m, 0.9 * global_ate_m);
}

TEST(RgbdFrontendTest, FallsBackToWheelOdometryWithoutDepth) {
  const std::optional<TumDataset> data = OpenTum();
  if (!data) GTEST_SKIP() << "TUM fr1/xyz not found in " << kTumDir;
  // Wheel odometry = the ground-truth camera motion (identity extrinsic), depth all invalid.
  FrontendOptions options = ShippedOptions();
  options.fusion.base_to_camera = Pose3::Identity();
  options.wheel.max_speed_mps = 10.0;
  options.wheel.max_yaw_rate_dps = 3600.0;
  RgbdFrontend frontend(options, data->intrinsics());
  const Trajectory& gt = data->groundtruth();
  size_t next_gt = 0;
  const size_t frames = 20;
  const cv::Mat no_depth(data->intrinsics().height_px, data->intrinsics().width_px, CV_32FC1,
                         cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  Trajectory est;
  for (size_t i = 0; i < frames; ++i) {
    const Time t = data->frame(i).stamp;
    while (next_gt < gt.size() && gt[next_gt].stamp.nanoseconds() <= t.nanoseconds() + 20000000) {
      ASSERT_TRUE(frontend.AddWheelOdometry(gt[next_gt].stamp, gt[next_gt].pose).ok());
      ++next_gt;
    }
    const FrontendFrameResult r = frontend.ProcessFrame(t, data->LoadBgr(i), no_depth);
    if (i > 0) {
      EXPECT_EQ(r.source, MotionSource::kWheel) << r.wheel_status.reason();
      EXPECT_NE(r.registration.status.reason().find("too few 3D matches"), std::string::npos)
          << r.registration.status.reason();
      EXPECT_GT(r.registration.depth_rejects.missing, 0u);
    }
    est.push_back({t, r.odom_camera});
  }
  // Starts at the wheel pose and follows it (interpolation error only).
  const std::optional<Pose3> gt0 = PoseAt(gt, est.front().stamp);
  ASSERT_TRUE(gt0.has_value());
  EXPECT_LT((est.front().pose.translation() - gt0->translation()).norm(), 0.005);
  EXPECT_LT(MaxRelativeError(*data, est), 0.005);
  EXPECT_EQ(frontend.fusion_stats().VisionShareByFrames(), 0.0);
}

TEST(RgbdFrontendTest, BadInputDoesNotCrash) {
  CameraIntrinsics k;
  RgbdFrontend frontend(FrontendOptions(), k);
  const FrontendFrameResult a = frontend.ProcessFrame(Time::FromSeconds(1.0), cv::Mat(), cv::Mat());
  EXPECT_FALSE(a.status.ok());
  const cv::Mat gray(480, 640, CV_8UC1, cv::Scalar(128));
  const cv::Mat depth16(480, 640, CV_16UC1, cv::Scalar(1000));
  const FrontendFrameResult b = frontend.ProcessFrame(Time::FromSeconds(1.1), gray, depth16);
  EXPECT_NE(b.status.reason().find("CV_32FC1"), std::string::npos) << b.status.reason();
  const FrontendFrameResult c = frontend.ProcessFrame(Time::FromSeconds(1.05), gray, cv::Mat());
  EXPECT_NE(c.status.reason().find("not after"), std::string::npos) << c.status.reason();
  EXPECT_TRUE(c.odom_camera.matrix().allFinite());
  // Depth of another size than the camera's (camera_info): refused, not registered.
  const cv::Mat small_depth(240, 320, CV_32FC1, cv::Scalar(1.0f));
  const FrontendFrameResult d = frontend.ProcessFrame(Time::FromSeconds(1.2), gray, small_depth);
  EXPECT_NE(d.status.reason().find("320x240 differs from the camera's 640x480"), std::string::npos)
      << d.status.reason();
}

TEST(RgbdFrontendTest, RecoversFromAFrameStampedFarInTheFuture) {
  const auto data = OpenTum();
  if (!data) GTEST_SKIP() << "TUM fr1/xyz not found in " << kTumDir;
  RgbdFrontend frontend(ShippedOptions(), data->intrinsics());
  const auto process = [&](size_t i, double shift_s) {
    const Time t = Time::FromNanoseconds(data->frame(i).stamp.nanoseconds() +
                                         static_cast<int64_t>(shift_s * 1e9));
    return frontend.ProcessFrame(t, data->LoadBgr(i), data->LoadDepthM(i), t);
  };
  for (size_t i = 0; i < 5; ++i) ASSERT_TRUE(process(i, 0.0).status.ok());
  // One frame stamped an hour ahead: ignored, with the reason.
  const FrontendFrameResult future = process(5, 3600.0);
  EXPECT_NE(future.status.reason().find("jumps"), std::string::npos) << future.status.reason();
  // The following frames, stamped normally, are registered again.
  for (size_t i = 6; i < 12; ++i) {
    const FrontendFrameResult r = process(i, 0.0);
    EXPECT_TRUE(r.status.ok()) << i << ": " << r.status.reason();
    EXPECT_EQ(r.source, MotionSource::kVision) << i;
  }
  // A real gap: two frames in a row well ahead are believed from the second on.
  EXPECT_FALSE(process(12, 60.0).status.ok());
  EXPECT_TRUE(process(13, 60.0).status.ok());
}

// One pass of the front end with wheel odometry over frames [first, last) of a simulated
// sequence, against the simulator's ground truth: RMS error of the frame-to-frame camera
// motion, error of the motion from the first to the last frame, and the share of the matches
// given to registration that lie on pedestrians (the simulator's dynamic mask).
struct SimRun {
  double step_rms_m = 0.0;
  double end_error_m = 0.0;
  double pedestrian_match_share = 0.0;
};

// depth_reading scales the rendered depth (a sensor whose depth reads short or long);
// depth_correction is the camera's calibrated correction for it.
SimRun RunOnSim(const sim::Simulator& sim, size_t first, size_t last, FrontendOptions options,
                double depth_reading = 1.0, double depth_correction = 1.0) {
  options.fusion.base_to_camera = sim.T_base_camera();
  CameraIntrinsics intrinsics = sim.intrinsics();
  intrinsics.depth_correction = depth_correction;
  RgbdFrontend frontend(options, intrinsics);
  std::vector<Pose3> estimate;
  size_t matches = 0;
  size_t on_pedestrians = 0;
  for (size_t i = first; i < last; ++i) {
    EXPECT_TRUE(frontend.AddWheelOdometry(sim.stamp(i), sim.odometry(i).T_odom_base).ok());
    const sim::SimFrame f = sim.Render(i);
    const cv::Mat depth_m = depth_reading == 1.0 ? f.depth_m : cv::Mat(f.depth_m * depth_reading);
    const FrontendFrameResult r = frontend.ProcessFrame(f.stamp, f.bgr, depth_m);
    estimate.push_back(r.odom_camera);
    for (const cv::Point2f& p : r.registered_px) {
      const int x = std::clamp(static_cast<int>(std::lround(p.x)), 0, f.dynamic_mask.cols - 1);
      const int y = std::clamp(static_cast<int>(std::lround(p.y)), 0, f.dynamic_mask.rows - 1);
      on_pedestrians += f.dynamic_mask.at<uint8_t>(y, x) != 0;
      ++matches;
    }
  }
  SimRun run;
  double sum_sq = 0.0;
  for (size_t i = first + 1; i < last; ++i) {
    const Pose3 truth = Between(sim.T_world_camera(i - 1), sim.T_world_camera(i));
    const Pose3 est = Between(estimate[i - 1 - first], estimate[i - first]);
    sum_sq += (truth.translation() - est.translation()).squaredNorm();
  }
  run.step_rms_m = std::sqrt(sum_sq / static_cast<double>(last - first - 1));
  const Pose3 truth = Between(sim.T_world_camera(first), sim.T_world_camera(last - 1));
  const Pose3 est = Between(estimate.front(), estimate.back());
  run.end_error_m = (truth.translation() - est.translation()).norm();
  run.pedestrian_match_share = matches ? static_cast<double>(on_pedestrians) / matches : 0.0;
  return run;
}

TEST(RgbdFrontendTest, IcgmMotionPriorKeepsWalkersOutOfTheRegistration) {
  // The crowded scenario where walkers cross close in front of the robot.
  const sim::Simulator sim(
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/crowded.yaml"));
  constexpr size_t kFirst = 55;
  constexpr size_t kLast = 115;
  ASSERT_LE(kLast, sim.size());
  FrontendOptions with_prior = ShippedOptions();
  ASSERT_TRUE(with_prior.use_icgm);
  ASSERT_TRUE(with_prior.icgm.motion_prior) << "the shipped odometry config uses the prior";
  FrontendOptions without_prior = with_prior;
  without_prior.icgm.motion_prior = false;
  const SimRun on = RunOnSim(sim, kFirst, kLast, with_prior);
  const SimRun off = RunOnSim(sim, kFirst, kLast, without_prior);
  std::printf(
      "frames %zu-%zu, with / without the motion prior: step error %.4f / %.4f m rms, "
      "end error %.4f / %.4f m, matches on pedestrians %.2f%% / %.2f%%\n",
      kFirst, kLast, on.step_rms_m, off.step_rms_m, on.end_error_m, off.end_error_m,
      100.0 * on.pedestrian_match_share, 100.0 * off.pedestrian_match_share);
  EXPECT_GT(off.pedestrian_match_share, 0.05) << "the segment must be crowded";
  // Measured: 4.3% vs 7.0% of the matches, 6.8 vs 10.2 mm per frame, 3.4 vs 7.4 cm end error.
  EXPECT_LT(on.pedestrian_match_share, 0.8 * off.pedestrian_match_share);
  EXPECT_LT(on.step_rms_m, 0.8 * off.step_rms_m);
  EXPECT_LT(on.end_error_m, 0.7 * off.end_error_m);
}

TEST(RgbdFrontendTest, OdometryConfigOverridesIcgmSection) {
  FrontendOptions o;
  ReadFrontendOptions(OptionReader::FromString("frontend: {use_icgm: false, keyframe_window: 5}\n"
                                               "registration: {min_inliers: 33}\n"
                                               "icgm: {auto_threshold: true}\n"),
                      OptionReader::FromString("icgm: {auto_threshold: false, threshold: 0.1}\n"
                                               "features: {max_features: 500}\n"),
                      &o);
  EXPECT_FALSE(o.use_icgm);
  EXPECT_EQ(o.keyframe_window, 5);
  EXPECT_EQ(o.registration.min_inliers, 33);
  EXPECT_TRUE(o.icgm.auto_threshold);
  EXPECT_DOUBLE_EQ(o.icgm.threshold, 0.1);
  EXPECT_EQ(o.features.max_features, 500);
  EXPECT_THROW(ReadFrontendOptions(OptionReader::FromString("frontend: {keyframe_window: -1}"),
                                   OptionReader::FromString("{}"), &o),
               LoadError);
  // The shipped files load.
  ShippedOptions();
}

TEST(RgbdFrontendTest, DepthCorrectionUndoesTheSensorsDepthScaleError) {
  const sim::Simulator sim(
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml"));
  const size_t last = std::min<size_t>(sim.size(), 80);
  const double travel_m =
      TranslationNorm(Between(sim.T_world_camera(0), sim.T_world_camera(last - 1)));
  ASSERT_GT(travel_m, 1.0);
  // The sensor's depth reads 6% short, as a mis-scaled Kinect would.
  constexpr double kReading = 1.0 / 1.06;
  const FrontendOptions options = ShippedOptions();
  const SimRun exact = RunOnSim(sim, 0, last, options);
  const SimRun biased = RunOnSim(sim, 0, last, options, kReading, 1.0);
  const SimRun corrected = RunOnSim(sim, 0, last, options, kReading, 1.06);
  std::printf("travel %.2f m; end error exact depth %.4f m, short depth %.4f m, corrected %.4f m\n",
              travel_m, exact.end_error_m, biased.end_error_m, corrected.end_error_m);
  // Short depth shrinks every registered motion: the end error approaches 6% of the travel.
  EXPECT_GT(biased.end_error_m, 0.03 * travel_m);
  EXPECT_LT(corrected.end_error_m, 0.3 * biased.end_error_m);
  EXPECT_NEAR(corrected.end_error_m, exact.end_error_m, 0.01 * travel_m);
}

TEST(RgbdFrontendTest, KeyframesCarryTheWheelsMotionSinceThePreviousKeyframe) {
  const sim::Simulator sim(
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml"));
  const size_t last = std::min<size_t>(sim.size(), 50);
  FrontendOptions options = ShippedOptions();
  options.fusion.base_to_camera = sim.T_base_camera();
  for (const bool wheels : {true, false}) {
    RgbdFrontend frontend(options, sim.intrinsics());
    std::vector<KeyframePtr> keyframes;
    frontend.SetKeyframeCallback([&](const KeyframePtr& kf) { keyframes.push_back(kf); });
    for (size_t i = 0; i < last; ++i) {
      if (wheels) {
        ASSERT_TRUE(frontend.AddWheelOdometry(sim.stamp(i), sim.odometry(i).T_odom_base).ok());
      }
      const sim::SimFrame f = sim.Render(i);
      frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    }
    ASSERT_GE(keyframes.size(), 3u);
    EXPECT_FALSE(keyframes.front()->wheel_camera_motion) << "the first keyframe has no previous";
    for (size_t k = 1; k < keyframes.size(); ++k) {
      const size_t from = keyframes[k - 1]->frame_index, to = keyframes[k]->frame_index;
      if (!wheels) {
        EXPECT_FALSE(keyframes[k]->wheel_camera_motion) << "keyframe " << k;
        continue;
      }
      ASSERT_TRUE(keyframes[k]->wheel_camera_motion) << "keyframe " << k;
      // What the wheels measured between the two frames, seen from the camera...
      const Pose3& b = sim.T_base_camera();
      const Pose3 measured =
          b.inverse() * Between(sim.odometry(from).T_odom_base, sim.odometry(to).T_odom_base) * b;
      EXPECT_LT((keyframes[k]->wheel_camera_motion->matrix() - measured.matrix()).norm(), 1e-9);
      // ...which is the camera's true motion up to the wheels' drift.
      const Pose3 truth = Between(sim.T_world_camera(from), sim.T_world_camera(to));
      EXPECT_LT(TranslationNorm(Between(truth, *keyframes[k]->wheel_camera_motion)),
                0.05 * TranslationNorm(truth) + 0.005);
    }
  }
}

}  // namespace
}  // namespace icgm
