// The front end on a REAL crowd: the Bonn RGB-D Dynamic "crowd" excerpt in ../shared (hand-held
// Xtion, people walking 0.5-2 m from the camera, no wheels). Skipped, loudly, without the data.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/trajectory.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/features/feature_extractor.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

const std::string kBonnDir = std::string(ICGM_SHARED_DATA_DIR) + "/bonn_crowd_excerpt";

FrontendOptions Options(const std::string& odometry_yaml) {
  FrontendOptions o;
  ReadFrontendOptions(
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/" + odometry_yaml),
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/icgm.yaml"), &o);
  return o;
}

// A shipped simulated scenario (config/sim/NAME) with its scene seed (-1: the file's own).
sim::SimOptions Scenario(const std::string& sim_yaml, int seed = -1) {
  sim::SimOptions scenario =
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/" + sim_yaml);
  if (seed >= 0) scenario.seed = seed;
  return scenario;
}

// ATE rmse (SE(3) alignment) of the front end over the whole excerpt.
double AteOnBonn(const TumDataset& data, const FrontendOptions& options) {
  RgbdFrontend frontend(options, data.intrinsics());
  Trajectory estimate;
  for (size_t i = 0; i < data.size(); ++i) {
    const FrontendFrameResult r =
        frontend.ProcessFrame(data.frame(i).stamp, data.LoadBgr(i), data.LoadDepthM(i),
                             data.frame(i).depth_stamp);
    EXPECT_TRUE(r.status.ok()) << r.status.reason();
    estimate.push_back({r.stamp, r.odom_camera});
  }
  TrajectoryEvaluation eval;
  EXPECT_TRUE(EvaluateTrajectory(data.groundtruth(), estimate, {}, &eval).ok());
  EXPECT_GT(eval.num_associated(), data.size() * 9 / 10);
  return eval.ate.rmse;
}

// The real excerpt with the Xtion's calibration (config/camera/bonn_xtion.yaml); every test of
// the suite is skipped, loudly, without it.
class BonnCrowdFrontendTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kBonnDir + "/rgb.txt")) {
      GTEST_SKIP() << "SKIPPED: real Bonn crowd excerpt not found in " << kBonnDir;
    }
    data_ = TumDataset::Open(kBonnDir, LoadCameraIntrinsics(std::string(ICGM_SOURCE_DIR) +
                                                            "/config/camera/bonn_xtion.yaml"));
    ASSERT_GE(data_->size(), 290u);
    ASSERT_TRUE(data_->has_groundtruth());
  }
  // ATE rmse of the front end with `options` over the whole excerpt.
  double Ate(const FrontendOptions& options) const { return AteOnBonn(*data_, options); }
  const TumDataset& data() const { return *data_; }
  // The motion from frame 1 to frame `last`, estimated by the front end with `options` and true
  // (frame 0 has no ground truth); nullopt when either frame has none.
  struct MotionFromFrame1 {
    Pose3 estimate, truth;
  };
  std::optional<MotionFromFrame1> MotionFromFrame1To(const FrontendOptions& options,
                                                     size_t last) const {
    RgbdFrontend frontend(options, data().intrinsics());
    std::optional<Pose3> estimate_1, truth_1;
    std::optional<MotionFromFrame1> motion;
    for (size_t i = 0; i <= last; ++i) {
      const FrontendFrameResult r =
          frontend.ProcessFrame(data().frame(i).stamp, data().LoadBgr(i), data().LoadDepthM(i),
                                data().frame(i).depth_stamp);
      const std::optional<Pose3> truth = PoseAt(data().groundtruth(), r.stamp);
      if (i == 1) {
        estimate_1 = r.odom_camera;
        truth_1 = truth;
      }
      if (i == last && truth && truth_1) {
        motion = MotionFromFrame1{Between(*estimate_1, r.odom_camera), Between(*truth_1, *truth)};
      }
    }
    return motion;
  }

  // Translation error of the motion from frame 1 to frame `last` against the ground truth
  // (frame 0 has none); NaN when either frame lacks ground truth.
  double DriftFromFrame1M(const FrontendOptions& options, size_t last) const {
    const auto motion = MotionFromFrame1To(options, last);
    return motion ? TranslationNorm(Between(motion->truth, motion->estimate)) : NAN;
  }

 private:
  std::optional<TumDataset> data_;
};

TEST_F(BonnCrowdFrontendTest, HandheldCrowdProfileHalvesTheErrorOnTheRealBonnCrowd) {
  const double plain = Ate(Options("odometry.yaml"));
  // The profile's result moves by up to 3x with the RANSAC seed: judged as the mean over three.
  const auto mean_over_seeds = [&](FrontendOptions options, const char* name) {
    double mean = 0.0;
    for (const uint64_t seed : {7u, 1u, 2u}) {
      options.registration.rng_seed = seed;
      const double ate = Ate(options);
      std::printf("Bonn crowd excerpt, %s, RANSAC seed %u: ATE %.4f m\n", name,
                  static_cast<unsigned>(seed), ate);
      mean += ate / 3.0;
    }
    return mean;
  };
  const FrontendOptions profile = Options("odometry_handheld_crowd.yaml");
  const double crowd = mean_over_seeds(profile, "crowd profile");
  // The same without velocity_from_vision: the velocity prior follows the poses the motion
  // prior already pulled towards it.
  FrontendOptions fused_velocity = profile;
  fused_velocity.velocity_from_vision = false;
  const double fused = mean_over_seeds(fused_velocity, "profile, velocity from fused poses");
  std::printf("Bonn crowd excerpt: plain %.4f m, crowd profile mean over seeds 7/1/2 %.4f m, "
              "velocity from fused poses %.4f m\n",
              plain, crowd, fused);
  // Measured (icgm_slam_offline, same front end): 0.45 m plain; crowd profile seeds 7/1/2
  // 0.037 / 0.032 / 0.034 m (mean 0.034 m; without static_inlier_refit 0.033 / 0.042 / 0.041 m);
  // velocity from fused poses 0.060 / 0.106 / 0.060 m (mean 0.075 m): the velocity prior keeps a
  // wrong early velocity when the motion prior feeds it its own output.
  EXPECT_LT(crowd, 0.04);
  EXPECT_LT(crowd, 0.5 * plain);
  EXPECT_LT(crowd, 0.8 * fused);
}

// The map hypothesis with persistence (map_hypothesis.h) on the real excerpt: the frame located
// among the static points of the last 8 keyframes that the window's keyframes saw in place in at
// least 3 keyframes over half a second, offered to the evidence choice. Judged on RANSAC seeds 3
// and 5, the two where the profile errs most (all six seeds: README).
TEST_F(BonnCrowdFrontendTest, MapHypothesisWithPersistenceOnTheRealBonnCrowd) {
  FrontendOptions profile = Options("odometry_handheld_crowd.yaml");
  FrontendOptions with_map = profile;
  with_map.map_hypothesis.keyframes = 8;
  with_map.map_hypothesis.persistence_keyframes = 3;
  with_map.map_hypothesis.persistence_span_s = 0.5;
  with_map.map_hypothesis.persistence_radius_m = 0.1;
  double off = 0.0, on = 0.0;
  for (const uint64_t seed : {3u, 5u}) {
    profile.registration.rng_seed = seed;
    with_map.registration.rng_seed = seed;
    const double a = Ate(profile), b = Ate(with_map);
    std::printf("Bonn crowd excerpt, RANSAC seed %u: profile %.4f m, map hypothesis %.4f m\n",
                static_cast<unsigned>(seed), a, b);
    off += a / 2.0;
    on += b / 2.0;
  }
  // Measured (icgm_slam_offline): seeds 3 / 5 profile 0.0343 / 0.0380 m, with the map
  // hypothesis 0.0278 / 0.0296 m.
  EXPECT_LT(on, 0.9 * off);
  EXPECT_LT(on, 0.032);
}

// motion_prior_sigma_by_steps: while the velocity history holds fewer steps than it spans, the
// prior from the first registered steps is widened. Over frames 1-10 (registered to the first
// keyframes with 150-280 inliers, the same for every RANSAC seed) the profile's pose runs about
// 5 mm per frame ahead of the truth, carried by the first step's velocity; widened, it drifts
// less. Left off: over the whole excerpt the six-seed mean is worse (README).
TEST_F(BonnCrowdFrontendTest, MotionPriorWidenedWhileTheHistoryIsShortDriftsLessAtTheStart) {
  const auto drift_m = [&](const FrontendOptions& options) {
    return DriftFromFrame1M(options, 10);
  };
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  off.motion_prior_sigma_by_steps = false;
  FrontendOptions on = off;
  on.motion_prior_sigma_by_steps = true;
  // The square root of the ratio widens less; exponent 0 leaves the prior as it is.
  FrontendOptions root = on;
  root.motion_prior_sigma_by_steps_exponent = 0.5;
  FrontendOptions none = on;
  none.motion_prior_sigma_by_steps_exponent = 0.0;
  const double without = drift_m(off), with = drift_m(on), with_root = drift_m(root);
  std::printf(
      "Bonn crowd excerpt, frames 1-10: drift %.1f mm with the profile's prior, %.1f mm "
      "widened while the velocity history is short, %.1f mm by the square root\n",
      1000.0 * without, 1000.0 * with, 1000.0 * with_root);
  // Measured (icgm_slam_offline, every seed): 48-51 mm without, 32-34 mm with.
  ASSERT_TRUE(std::isfinite(without) && std::isfinite(with)) << "frames 1 and 10 need ground truth";
  EXPECT_GT(without, 0.04);
  EXPECT_LT(with, 0.8 * without);
  EXPECT_LT(with_root, without);
  EXPECT_EQ(drift_m(none), without);
}

// motion_prior_start_frames: frames 1-7 of the excerpt are registered to the first keyframe
// (frame 0, the run's origin; the same for every RANSAC seed). With the prior, the pose follows
// the prediction within a millimetre, whose velocity the first registered step set (9.5 mm
// where the hand moved 1.6 mm); kept as registered, the pose carries only that frame's own
// registration error. Left off: the later frames drift far more (README).
TEST_F(BonnCrowdFrontendTest, StartFramesKeptAsRegisteredToTheFirstKeyframeDriftLess) {
  const auto drift_m = [&](const FrontendOptions& options) {
    return DriftFromFrame1M(options, 4);
  };
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  ASSERT_EQ(off.motion_prior_start_frames, 0) << "off in the profile";
  FrontendOptions on = off;
  on.motion_prior_start_frames = 30;
  FrontendOptions none = on;  // only frame 0, never registered, lies before it
  none.motion_prior_start_frames = 1;
  const double without = drift_m(off), with = drift_m(on);
  std::printf(
      "Bonn crowd excerpt, frames 1-4: drift %.1f mm with the profile's prior, %.1f mm kept as "
      "registered to the first keyframe\n",
      1000.0 * without, 1000.0 * with);
  // Measured: 22.6 / 7.5 mm (icgm_slam_offline, RANSAC seeds 7/1/2: 22.3-22.5 / 7.5-8.8 mm).
  ASSERT_TRUE(std::isfinite(without) && std::isfinite(with)) << "frames 1 and 4 need ground truth";
  EXPECT_GT(without, 0.015);
  EXPECT_LT(with, 0.5 * without);
  EXPECT_EQ(drift_m(none), without);
}

// velocity_prior_skip_origin: frames 1-7 are registered to frame 0 and share much of one offset
// (about 7 mm left and 7 mm up, a pan mistaken for a slide). Measured from the exact origin,
// the velocity carries that offset as motion, and the fused pose, which follows the prediction,
// runs about 5 mm per frame ahead; without the origin the offset cancels between the frames'
// poses. Left off: over the whole excerpt the estimate then drifts later instead (README).
TEST_F(BonnCrowdFrontendTest, VelocityWithoutTheOriginDriftsLessAtTheStart) {
  const auto drift_m = [&](const FrontendOptions& options) {
    return DriftFromFrame1M(options, 10);
  };
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  ASSERT_FALSE(off.velocity_prior_skip_origin) << "off in the profile";
  FrontendOptions on = off;
  on.velocity_prior_skip_origin = true;
  const double without = drift_m(off), with = drift_m(on);
  std::printf(
      "Bonn crowd excerpt, frames 1-10: drift %.1f mm with the velocity from the origin, %.1f mm "
      "without it\n",
      1000.0 * without, 1000.0 * with);
  // Measured: 49.7 / 12.0 mm (icgm_slam_offline, seed 7: 49.5 / 12.0 mm).
  ASSERT_TRUE(std::isfinite(without) && std::isfinite(with)) << "frames 1 and 10 need ground truth";
  EXPECT_GT(without, 0.04);
  EXPECT_LT(with, 0.5 * without);
}

TEST_F(BonnCrowdFrontendTest, SmallestRotationNearTheBestEvidenceTurnsLessAtTheStart) {
  // Rotation from frame 1 to frame 31 (deg), estimated and true (frame 0 has no ground truth).
  const auto pan_deg = [&](const FrontendOptions& options) {
    const auto motion = MotionFromFrame1To(options, 31);
    if (!motion) return std::pair<double, double>{NAN, NAN};
    return std::pair<double, double>{RotationAngleRad(motion->estimate) * 180.0 / M_PI,
                                     RotationAngleRad(motion->truth) * 180.0 / M_PI};
  };
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  off.evidence_rotation_margin = 0.0;
  FrontendOptions on = off;
  on.evidence_rotation_margin = 0.1;
  on.evidence_rotation_margin_frames = 45;
  FrontendOptions before = on;  // the choice ends before the frames measured
  before.evidence_rotation_margin_frames = 1;
  const auto [without, truth] = pan_deg(off);
  const double with = pan_deg(on).first;
  std::printf(
      "Bonn crowd excerpt, frames 1-31: turned %.1f deg with the profile, %.1f deg with the "
      "smallest rotation within 10%% of the best evidence, ground truth %.1f deg\n",
      without, with, truth);
  // Measured (icgm_slam_offline, 17 runs): means 17.8 deg without, 13.0 deg with, truth 9.0 deg;
  // the ATE over the whole excerpt is worse all the same (README).
  ASSERT_TRUE(std::isfinite(without) && std::isfinite(truth))
      << "frames 1 and 31 need ground truth";
  EXPECT_GT(without, truth + 5.0);
  EXPECT_LT(std::abs(with - truth), std::abs(without - truth) - 2.0);
  EXPECT_EQ(pan_deg(before).first, without);
}

// Anchor keyframes (anchor_keyframes.h): the first keyframe, made on the clean static room of
// frames 0-7, is kept and every later frame is also registered to it; with at least 20 inliers
// the pose and the window's keyframes move a tenth of the way to that estimate. The chain's
// start-up drift (16-25 cm from frame 1 by frame 45 on every seed, README) is pulled back, but
// the whole excerpt's ATE rises: the anchor acts only once walkers stop hiding it (few links in
// frames 13-30), and its own registrations err by centimetres later, so a drift that SE(3)
// alignment absorbed becomes an error that varies along the path (README).
TEST_F(BonnCrowdFrontendTest, AnchorKeyframePullsBackTheStartUpDriftOnTheRealBonnCrowd) {
  const auto drift_m = [&](const FrontendOptions& options) {
    return DriftFromFrame1M(options, 110);
  };
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  off.anchor.keyframes = 0;
  FrontendOptions on = off;
  on.anchor.keyframes = 1;
  on.anchor.min_inliers = 20;
  on.anchor.gain = 0.1;
  on.anchor.moves_chain = true;
  const double without = drift_m(off), with = drift_m(on);
  const double ate_without = Ate(off), ate_with = Ate(on);
  std::printf(
      "Bonn crowd excerpt, RANSAC seed 7: drift from frame 1 to frame 110 %.1f mm with the "
      "profile, %.1f mm with the first keyframe as anchor; ATE %.4f / %.4f m\n",
      1000.0 * without, 1000.0 * with, ate_without, ate_with);
  // Measured (icgm_slam_offline, seed 7): drift 187 / 30 mm, ATE 0.0372 / 0.0677 m.
  ASSERT_TRUE(std::isfinite(without) && std::isfinite(with))
      << "frames 1 and 110 need ground truth";
  EXPECT_GT(without, 0.15);
  EXPECT_LT(with, 0.5 * without);
  EXPECT_GT(ate_with, ate_without);
}

// Registration agreement (registration_agreement.h): each frame is registered to its reference
// keyframe and to one nearby keyframe (frame_extra_references); where the two lie within 1 cm /
// 0.5 deg of their mean the motion prior weighs them by their own spread. Judged against the
// ground truth, is their agreement honest? The reference registration of frames whose
// registrations agree errs less than that of frames whose registrations part.
TEST_F(BonnCrowdFrontendTest, RegistrationsThatAgreeErrLessThanThoseThatPart) {
  FrontendOptions options = Options("odometry_handheld_crowd.yaml");
  ASSERT_FALSE(options.registration_agreement.on()) << "off in the profile";
  options.registration_agreement.covariance_scale = 1.0;
  RgbdFrontend frontend(options, data().intrinsics());
  std::vector<Time> stamps;
  std::vector<double> agreeing_m, parted_m;
  size_t agreed = 0;
  for (size_t i = 0; i < data().size(); ++i) {
    const FrontendFrameResult r =
        frontend.ProcessFrame(data().frame(i).stamp, data().LoadBgr(i), data().LoadDepthM(i),
                              data().frame(i).depth_stamp);
    stamps.push_back(r.stamp);
    agreed += r.registrations_agreed;
    if (!std::isfinite(r.registration_spread_m) || !r.registration.status.ok() ||
        r.registered_to_previous || !r.reference_index || *r.reference_index >= i) {
      continue;
    }
    const std::optional<Pose3> ref = PoseAt(data().groundtruth(), stamps[*r.reference_index]);
    const std::optional<Pose3> cur = PoseAt(data().groundtruth(), r.stamp);
    if (!ref || !cur) continue;
    const double error_m =
        TranslationNorm(Between(Between(*ref, *cur), r.registration.relative_pose));
    (r.registrations_agreed ? agreeing_m : parted_m).push_back(error_m);
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  ASSERT_GE(agreeing_m.size(), 10u);
  ASSERT_GE(parted_m.size(), 10u);
  const double agreeing = median(agreeing_m), parted = median(parted_m);
  std::printf(
      "Bonn crowd excerpt, RANSAC seed 7: %zu frames registered twice, %zu agreeing (%zu with "
      "ground truth), reference registration error median %.1f mm agreeing, %.1f mm parted\n",
      agreeing_m.size() + parted_m.size(), agreed, agreeing_m.size(), 1000.0 * agreeing,
      1000.0 * parted);
  // Measured: 162 frames registered twice, 28 agreeing; medians 7.7 mm against 11.9 mm.
  EXPECT_LT(agreeing, 0.8 * parted);
}

TEST_F(BonnCrowdFrontendTest, FurtherRansacSeedsFindOtherSetsThatWinTheEvidence) {
  // Poses of frames 0-45 (the walkers fill the view from about frame 15).
  const auto poses = [&](const FrontendOptions& options) {
    RgbdFrontend frontend(options, data().intrinsics());
    std::vector<Pose3> out;
    for (size_t i = 0; i <= 45; ++i) {
      out.push_back(frontend
                        .ProcessFrame(data().frame(i).stamp, data().LoadBgr(i),
                                      data().LoadDepthM(i), data().frame(i).depth_stamp)
                        .odom_camera);
    }
    return out;
  };
  FrontendOptions one = Options("odometry_handheld_crowd.yaml");
  one.evidence_ransac_runs = 1;
  FrontendOptions three = one;
  three.evidence_ransac_runs = 3;
  const std::vector<Pose3> a = poses(one), b = poses(three);
  size_t first_different = a.size();
  for (size_t i = 0; i < a.size(); ++i) {
    if (!a[i].isApprox(b[i], 0.0)) {
      first_different = i;
      break;
    }
  }
  std::printf(
      "Bonn crowd excerpt, frames 0-45: with 3 RANSAC runs the first pose that differs "
      "from one run's is frame %zu (%.1f mm apart at frame 45)\n",
      first_different, 1000.0 * TranslationNorm(Between(a.back(), b.back())));
  // Frame 1's registration (to frame 0, about 200 inliers on the room) comes out the same from
  // every seed; from frame 4 on (measured), where a pan and a sideways slide find consistent sets
  // of similar size, the further seeds find other sets and some win the evidence.
  EXPECT_GE(first_different, 2u);
  EXPECT_LT(first_different, a.size());
}

// The Xtion's rolling shutter (left out of config/camera/bonn_xtion.yaml): a 22.5 ms readout,
// stamped at the middle row, chosen without ground truth (the pixel rms of a fixed set of
// registration inliers; README: the Xtion's sensor timing). The plain configuration, whose
// registration alone carries the path, gains from it (icgm_slam_offline, RANSAC seeds 7/1/2:
// 0.449 / 0.296 / 0.374 m -> 0.221 / 0.231 / 0.214 m); the crowd profile does not (twelve
// seeds 0.0355 -> 0.0380 m), so the camera file keeps a global shutter.
TEST_F(BonnCrowdFrontendTest, XtionReadoutLowersThePlainConfigurationsError) {
  CameraIntrinsics rolling = data().intrinsics();
  ASSERT_EQ(rolling.readout_s, 0.0);
  rolling.readout_s = 0.0225;
  rolling.first_row_offset_s = -0.5 * rolling.readout_s;
  const TumDataset with_readout = TumDataset::Open(kBonnDir, rolling);
  const FrontendOptions plain = Options("odometry.yaml");
  const double global_shutter = Ate(plain);
  const double readout = AteOnBonn(with_readout, plain);
  std::printf("Bonn crowd excerpt, plain configuration: ATE %.4f m global shutter, %.4f m with "
              "a 22.5 ms readout\n",
              global_shutter, readout);
  EXPECT_LT(readout, 0.7 * global_shutter);
}

struct HandheldRun {
  double ate_m = 0.0;                 // after SE(3) alignment
  double pedestrian_inlier_share = 0.0;  // registration inliers on walkers (simulator's masks)
  double mean_coverage = 0.0;         // share of the image on walkers
  size_t crowded_frames = 0;          // frames whose walkers cover at least min_coverage
  // The same share over the registrations that placed their frame (the prior gate's set-aside
  // ones left out), and how many were set aside.
  double placing_pedestrian_inlier_share = 0.0;
  size_t prior_gated = 0;
  double gated_pedestrian_inlier_share = 0.0;  // over the set-aside registrations' inliers
  size_t keyframes = 0, velocity_rebased = 0;  // new keyframes, and those that rebased (all frames)
  size_t local_map_set_aside = 0;  // local-map refinements set aside (all frames)
  // Frames the velocity gate kept out of the history, and those whose prior it dropped; frames
  // whose prior was reset (all frames).
  size_t velocity_gate_rejected = 0, velocity_gate_dropped_prior = 0, prior_reset = 0;
};

// Frames [first, first + frames) of the scenario; inliers are counted only in frames whose
// walkers cover at least `min_coverage` of the image.
HandheldRun RunHandheld(const sim::Simulator& sim, size_t frames, const FrontendOptions& options,
                        size_t first = 0, double min_coverage = 0.0) {
  RgbdFrontend frontend(options, sim.intrinsics());
  Trajectory estimate, truth;
  size_t inliers = 0, on_walkers = 0, crowded = 0, placing = 0, placing_on_walkers = 0, gated = 0;
  size_t keyframes = 0, rebased = 0, set_aside = 0;
  HandheldRun run;
  double coverage = 0.0;
  for (size_t i = first; i < first + frames; ++i) {
    const sim::SimFrame f = sim.Render(i);
    const FrontendFrameResult r = frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    estimate.push_back({f.stamp, r.odom_camera});
    truth.push_back({f.stamp, f.T_world_camera});
    keyframes += r.new_keyframe;
    rebased += r.velocity_rebased;
    set_aside += r.local_map_set_aside;
    run.velocity_gate_rejected += r.velocity_gate_rejected;
    run.velocity_gate_dropped_prior += r.velocity_gate_dropped_prior;
    run.prior_reset += r.prior_reset;
    const double covered =
        static_cast<double>(cv::countNonZero(f.dynamic_mask)) / f.dynamic_mask.total();
    coverage += covered;
    if (covered < min_coverage) continue;
    ++crowded;
    if (!r.registration.status.ok()) continue;
    gated += r.prior_gated;
    for (const int k : r.registration.inlier_indices) {
      const cv::Point2f& p = r.registered_px[k];
      const int x = std::clamp(static_cast<int>(std::lround(p.x)), 0, f.dynamic_mask.cols - 1);
      const int y = std::clamp(static_cast<int>(std::lround(p.y)), 0, f.dynamic_mask.rows - 1);
      const bool on_walker = f.dynamic_mask.at<uint8_t>(y, x) != 0;
      on_walkers += on_walker;
      ++inliers;
      if (!r.prior_gated) {
        placing_on_walkers += on_walker;
        ++placing;
      }
    }
  }
  TrajectoryEvaluation eval;
  EXPECT_TRUE(EvaluateTrajectory(truth, estimate, {}, &eval).ok());
  run.ate_m = eval.ate.rmse;
  run.pedestrian_inlier_share = inliers ? static_cast<double>(on_walkers) / inliers : 0.0;
  run.mean_coverage = coverage / frames;
  run.crowded_frames = crowded;
  run.placing_pedestrian_inlier_share =
      placing ? static_cast<double>(placing_on_walkers) / placing : 0.0;
  run.prior_gated = gated;
  const size_t gated_inliers = inliers - placing;
  run.gated_pedestrian_inlier_share =
      gated_inliers ? static_cast<double>(on_walkers - placing_on_walkers) / gated_inliers : 0.0;
  run.keyframes = keyframes;
  run.velocity_rebased = rebased;
  run.local_map_set_aside = set_aside;
  return run;
}

TEST(CrowdFrontendTest, HandheldCrowdProfileKeepsWalkersOutOfTheRegistrationInARenderedCrowd) {
  // config/sim/handheld_crowd.yaml: hand-held camera (no wheels), blur, an office, three
  // walkers 0.5-2 m away covering a large part of the view.
  const sim::Simulator sim(Scenario("handheld_crowd.yaml"));
  ASSERT_FALSE(sim.has_wheel_odometry());
  constexpr size_t kFrames = 150;
  ASSERT_LE(kFrames, sim.size());
  const HandheldRun plain = RunHandheld(sim, kFrames, Options("odometry.yaml"));
  const HandheldRun crowd = RunHandheld(sim, kFrames, Options("odometry_handheld_crowd.yaml"));
  std::printf("handheld crowd, %zu frames, walkers cover %.0f%% of the view: ATE %.3f / %.3f m, "
              "registration inliers on walkers %.1f%% / %.1f%% (plain / crowd profile)\n",
              kFrames, 100.0 * plain.mean_coverage, plain.ate_m, crowd.ate_m,
              100.0 * plain.pedestrian_inlier_share, 100.0 * crowd.pedestrian_inlier_share);
  EXPECT_GT(plain.mean_coverage, 0.3) << "the clip must be crowded";
  // The ATE over these first 150 frames moves with the RANSAC seed by a factor of two or more
  // (whole-clip figures over several seeds: README), so only the walkers' share is asserted.
  // Measured on the scenario matched to the real excerpt: walkers cover 46% of the view, ATE
  // 0.144 / 0.020 m, inliers on walkers 20.8% / 12.0% (plain / crowd profile).
  EXPECT_LT(crowd.pedestrian_inlier_share, 0.7 * plain.pedestrian_inlier_share);
  EXPECT_GT(plain.pedestrian_inlier_share, 0.15) << "walkers must take a large share";
}


TEST(CrowdFrontendTest, WalkersFillingTheViewInARenderedCrowd) {
  // config/sim/handheld_crowd_close.yaml: five walkers 0.6-1.6 m in front of the hand-held
  // camera; in frames 48-107 they cover 60-80% of the view. Inliers are counted (simulator's
  // masks) in the frames where they cover at least 60%.
  const sim::Simulator sim(Scenario("handheld_crowd_close.yaml"));
  constexpr size_t kFirst = 48, kFrames = 60;
  constexpr double kCrowded = 0.6;
  ASSERT_LE(kFirst + kFrames, sim.size());
  const HandheldRun plain =
      RunHandheld(sim, kFrames, Options("odometry.yaml"), kFirst, kCrowded);
  const HandheldRun crowd =
      RunHandheld(sim, kFrames, Options("odometry_handheld_crowd.yaml"), kFirst, kCrowded);
  // The profile without its static refit (inliers on what the chosen motion's depth residuals
  // mark as moved dropped before a second registration).
  FrontendOptions no_refit_options = Options("odometry_handheld_crowd.yaml");
  no_refit_options.static_inlier_refit = false;
  const HandheldRun no_refit = RunHandheld(sim, kFrames, no_refit_options, kFirst, kCrowded);
  std::printf("handheld crowd close, frames %zu-%zu, walkers cover %.0f%% of the view, >= %.0f%% "
              "in %zu frames: ATE %.3f / %.3f / %.3f m, static registration inliers in those "
              "frames %.1f%% / %.1f%% / %.1f%% (plain / crowd profile / profile without the "
              "static refit)\n",
              kFirst, kFirst + kFrames - 1, 100.0 * crowd.mean_coverage, 100.0 * kCrowded,
              crowd.crowded_frames, plain.ate_m, crowd.ate_m, no_refit.ate_m,
              100.0 * (1.0 - plain.pedestrian_inlier_share),
              100.0 * (1.0 - crowd.pedestrian_inlier_share),
              100.0 * (1.0 - no_refit.pedestrian_inlier_share));
  std::printf(
      "  crowd profile: %zu registrations set aside by the prior gate; static share of the "
      "inliers of the registrations that placed their frame %.1f%% (without the refit "
      "%.1f%%)\n",
      crowd.prior_gated, 100.0 * (1.0 - crowd.placing_pedestrian_inlier_share),
      100.0 * (1.0 - no_refit.placing_pedestrian_inlier_share));
  EXPECT_GE(crowd.crowded_frames, kFrames * 9 / 10) << "the walkers must fill the view";
  EXPECT_GT(1.0 - crowd.pedestrian_inlier_share, 1.0 - plain.pedestrian_inlier_share + 0.15);
  // Measured: static share of the inliers 31.9% plain, 58.1% with the crowd profile, 54.8%
  // without its static refit; ATE 0.161 / 0.288 / 0.290 m. The profile keeps more of the
  // walkers out of the registration but, started among them, loses more of the path; the aim
  // of >= 95% static inliers with a bounded pose error is NOT reached (README): where the
  // chosen motion follows a walker, its residuals mark the room as moved, not the walker.
  EXPECT_GT(1.0 - crowd.pedestrian_inlier_share, 1.0 - no_refit.pedestrian_inlier_share + 0.02);
}

TEST(CrowdFrontendTest, DepthOrderPrefersTheRoomsSetWhereAWalkerFillsTheView) {
  // config/sim/handheld_crowd.yaml, scenario seed 3: in frames 100-135 a walker fills much of the
  // view and the set it forms wins the evidence choice by a few percent of the score (frame 131:
  // 142 inliers, all on the walker, against the ICGM set's 56), after which the
  // constant-velocity prior carries its motion on (measured with icgm_slam_offline --report).
  const sim::Simulator sim(Scenario("handheld_crowd.yaml", 3));
  constexpr size_t kFrames = 160;
  ASSERT_LE(kFrames, sim.size());
  const FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  ASSERT_EQ(off.evidence_depth_order_margin, 0.0) << "off in the profile";
  FrontendOptions on = off;
  on.evidence_depth_order_margin = 0.2;
  const HandheldRun without = RunHandheld(sim, kFrames, off);
  const HandheldRun with = RunHandheld(sim, kFrames, on);
  std::printf(
      "handheld crowd, seed 3, frames 0-%zu: ATE %.4f / %.4f m, registration inliers on walkers "
      "%.1f%% / %.1f%% (profile / depth order within 20%% of the best score)\n",
      kFrames - 1, without.ate_m, with.ate_m, 100.0 * without.pedestrian_inlier_share,
      100.0 * with.pedestrian_inlier_share);
  // Measured: inliers on walkers 5.9% -> 4.2%, ATE 0.144 -> 0.111 m (whole clip with
  // icgm_slam_offline: 0.204 -> 0.143 m). On the real Bonn crowd the same setting is worse
  // (README), so it stays off.
  EXPECT_LT(with.pedestrian_inlier_share, 0.85 * without.pedestrian_inlier_share);
  EXPECT_LT(with.ate_m, 0.9 * without.ate_m);
}

TEST(CrowdFrontendTest, PriorGateSetsAsideAWalkerFillingTheView) {
  // config/sim/handheld_crowd_deep.yaml with scenario seed 2: from frame 265 on a walker passes
  // close in front of the camera and fills most of the view for several frames; the crowd
  // profile's registration then follows the walker (every inlier on it), turning the camera by
  // 2-5 deg per frame where the hand turns it by about 0.1 deg, and the constant-velocity
  // prior keeps that motion for the rest of the clip (measured with icgm_slam_offline).
  const sim::Simulator sim(Scenario("handheld_crowd_deep.yaml", 2));
  constexpr size_t kFirst = 220, kFrames = 80;
  ASSERT_LE(kFirst + kFrames, sim.size());
  // The crowd profile with and without the gate at 2 deg (its measured setting).
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  off.prior_gate_deg = 0.0;
  FrontendOptions on = off;
  on.prior_gate_deg = 2.0;
  const HandheldRun without = RunHandheld(sim, kFrames, off, kFirst);
  EXPECT_EQ(without.prior_gated, 0u) << "the gate is off";
  const HandheldRun with = RunHandheld(sim, kFrames, on, kFirst);
  // The registrations the gate set aside, judged by the simulator's walker masks.
  std::printf(
      "handheld crowd, seed 2, frames %zu-%zu: ATE %.4f m without the prior gate, "
      "%.4f m with it; %zu registrations set aside, %.1f%% of their inliers on "
      "walkers\n",
      kFirst, kFirst + kFrames - 1, without.ate_m, with.ate_m, with.prior_gated,
      100.0 * with.gated_pedestrian_inlier_share);
  // What the gate sets aside are the walker's registrations, and the path keeps its shape.
  // Measured: ATE 0.183 m without the gate, 0.062 m with it; 4 registrations set aside, all
  // their inliers on walkers (whole clip, icgm_slam_offline --sim-seed 2: 0.152 -> 0.074 m).
  EXPECT_GE(with.prior_gated, 2u);
  EXPECT_GT(with.gated_pedestrian_inlier_share, 0.8);
  EXPECT_LT(with.ate_m, 0.6 * without.ate_m);
}

TEST(CrowdFrontendTest, NearSetGateKeepsAWalkerCaptureOutOfTheKeyframesAndThePrior) {
  // config/sim/handheld_crowd.yaml with scenario seed 3: from frame 103 on walkers pass
  // 0.6-1 m in front of the camera; the chosen sets of frames 105-134 that lie nearer than 1 m
  // (median inlier depth 0.55-0.95 m) are 80-100% on walkers and 45-93 mm off the true motion,
  // the room's sets (2.2-3.4 m) about 5 mm. With the profile the keyframes of frames 132 and
  // 134 keep 60 and 42 mm of the walker's motion, the velocity history carries it, and the
  // next keyframes, placed at the fused pose, add 12-59 mm each while their registrations are
  // right to 3-8 mm (icgm_slam_offline --report against the ground truth; 0.204 m over the clip).
  const sim::Simulator sim(Scenario("handheld_crowd.yaml", 3));
  constexpr size_t kFrames = 200;
  ASSERT_LE(kFrames, sim.size());
  const FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  ASSERT_EQ(off.prior_gate_near_m, 0.0) << "off in the profile";
  ASSERT_EQ(off.prior_gate_deg, 0.0);
  // Sets nearer than 0.9 m: the real crowd's walkers' sets lie at 1.0-1.5 m, where the motion
  // prior absorbs their error and gating them costs (README).
  FrontendOptions on = off;
  on.prior_gate_near_m = 0.9;
  const HandheldRun without = RunHandheld(sim, kFrames, off);
  EXPECT_EQ(without.prior_gated, 0u) << "the gate is off";
  const HandheldRun with = RunHandheld(sim, kFrames, on);
  std::printf(
      "handheld crowd, seed 3, frames 0-%zu: ATE %.4f m without the near-set gate, %.4f m "
      "with it; %zu registrations set aside, %.1f%% of their inliers on walkers\n",
      kFrames - 1, without.ate_m, with.ate_m, with.prior_gated,
      100.0 * with.gated_pedestrian_inlier_share);
  // What the gate sets aside are the walkers' registrations, and the capture no longer carries
  // the path (whole clip, icgm_slam_offline --sim-seed 3: 0.204 -> 0.075 m, 5 set aside).
  EXPECT_GE(with.prior_gated, 2u);
  EXPECT_GT(with.gated_pedestrian_inlier_share, 0.8);
  EXPECT_LT(with.ate_m, 0.7 * without.ate_m);
}

TEST(CrowdFrontendTest, VelocityRebaseBreaksTheKeyframeDriftLoop) {
  // config/sim/handheld_crowd_deep.yaml with scenario seed 5: walkers pull the registrations
  // sideways from frame 39 on, the fused pose falls centimetres behind the pose registered to the
  // reference keyframe, and each new keyframe (which takes the fused pose) hands that gap to
  // the velocity history as motion, so the prediction keeps the drift going with the room alone
  // in view (measured with icgm_slam_offline: 0.166 m over the clip).
  const sim::Simulator sim(Scenario("handheld_crowd_deep.yaml", 5));
  constexpr size_t kFrames = 130;
  ASSERT_LE(kFrames, sim.size());
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  off.velocity_rebase_at_keyframe = 0.0;
  off.velocity_rebase_by_covariance = false;
  off.velocity_rebase_persistent_deg = 0.0;
  off.velocity_rebase_max_m_per_frame = 0.0;
  // The measured setting: the whole offset, scaled by the covariances, under 6 mm per frame.
  FrontendOptions on = off;
  on.velocity_rebase_at_keyframe = 1.0;
  on.velocity_rebase_by_covariance = true;
  on.velocity_rebase_max_m_per_frame = 0.006;
  const HandheldRun without = RunHandheld(sim, kFrames, off);
  EXPECT_EQ(without.velocity_rebased, 0u) << "the rebase is off";
  const HandheldRun with = RunHandheld(sim, kFrames, on);
  std::printf(
      "handheld crowd, seed 5, frames 0-%zu: ATE %.4f m without the velocity rebase, %.4f m "
      "with it (rebased at %zu of %zu new keyframes)\n",
      kFrames - 1, without.ate_m, with.ate_m, with.velocity_rebased, with.keyframes);
  // The rebase breaks the loop, and the limit per frame leaves some keyframes alone.
  // Measured: 0.156 -> 0.107 m, rebased at 17 of 30 new keyframes (whole clip,
  // icgm_slam_offline --sim-seed 5: 0.166 -> 0.093 m).
  EXPECT_LT(with.ate_m, 0.8 * without.ate_m);
  EXPECT_GT(with.velocity_rebased, 0u);
  EXPECT_LT(with.velocity_rebased, with.keyframes);
}

TEST(CrowdFrontendTest, VelocityGateKeepsAWalkersFirstStepOutOfThePrior) {
  // config/sim/handheld_crowd.yaml with scenario seed 6: frame 1 registers on a walker (every
  // inlier on it), a 13-16 cm step where the hand moved the camera 1 mm, about 4 m/s; the
  // constant-velocity prior then carries that velocity for 30-50 frames (measured with
  // icgm_slam_offline --sim-seed 6 and ground truth: 0.494 m over the clip).
  const sim::Simulator sim(Scenario("handheld_crowd.yaml", 6));
  constexpr size_t kFrames = 120;
  ASSERT_LE(kFrames, sim.size());
  const FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  ASSERT_EQ(off.velocity_gate.max_speed_mps, 0.0) << "off in the profile";
  // A hand moves the camera at 0.05-0.15 m/s (the scenario: 1.7 mm per frame on average); the
  // limit leaves room for the registrations' noise (1.5 m/s: 5 cm per frame).
  FrontendOptions on = off;
  on.velocity_gate.max_speed_mps = 1.5;
  const HandheldRun without = RunHandheld(sim, kFrames, off);
  EXPECT_EQ(without.velocity_gate_rejected + without.velocity_gate_dropped_prior, 0u);
  const HandheldRun with = RunHandheld(sim, kFrames, on);
  std::printf(
      "handheld crowd, seed 6, frames 0-%zu: ATE %.4f m without the velocity gate, %.4f m with "
      "it (%zu registered steps set aside, %zu predictions dropped)\n",
      kFrames - 1, without.ate_m, with.ate_m, with.velocity_gate_rejected,
      with.velocity_gate_dropped_prior);
  // Measured: 0.630 -> 0.013 m, the first step set aside (whole clip, icgm_slam_offline
  // --sim-seed 6: 0.494 -> 0.028 m).
  EXPECT_GE(with.velocity_gate_rejected, 1u);
  EXPECT_LT(with.ate_m, 0.5 * without.ate_m);
}

TEST(CrowdFrontendTest, LocalMapRefinementsAwayFromThePredictionSetAsideInAWalkerCapture) {
  // config/sim/handheld_crowd.yaml with scenario seed 3: from about frame 100 on a walker holds
  // most of the kept matches and the registration follows it (icgm_slam_offline --sim-seed 3,
  // the profile with the keyframe interval at 10: 135 mm and 2-4 deg of drift per 20 frames
  // over frames 100-180). Keyframes made then hold the walker's points as static, and the local
  // map (4 keyframes) refined against them pulls further along: 167-207 mm per 20 frames.
  const sim::Simulator sim(Scenario("handheld_crowd.yaml", 3));
  constexpr size_t kFrames = 190;
  ASSERT_LE(kFrames, sim.size());
  FrontendOptions off = Options("odometry_handheld_crowd.yaml");
  off.max_keyframe_interval_phi = 10;
  off.local_map.keyframes = 4;
  FrontendOptions on = off;
  on.local_map.toward_prediction = true;
  const HandheldRun without = RunHandheld(sim, kFrames, off);
  EXPECT_EQ(without.local_map_set_aside, 0u) << "the rule is off";
  const HandheldRun with = RunHandheld(sim, kFrames, on);
  std::printf(
      "handheld crowd, seed 3, frames 0-%zu: ATE %.4f m with the local map, %.4f m with its "
      "refinements away from the prediction set aside (%zu of %zu frames)\n",
      kFrames - 1, without.ate_m, with.ate_m, with.local_map_set_aside, kFrames);
  // Measured: 0.227 -> 0.189 m, 81 of 190 refinements set aside (whole clip, icgm_slam_offline
  // --sim-seed 3: 0.244 -> 0.190 m; over seeds 1-10 and the real Bonn excerpt it is not better,
  // README).
  EXPECT_GT(with.local_map_set_aside, 0u);
  EXPECT_LT(with.local_map_set_aside, kFrames);
  EXPECT_LT(with.ate_m, 0.9 * without.ate_m);
}

TEST(CrowdFrontendTest, SpreadKeypointsWidenTheRoomsDepthRangeBehindTheWalkers) {
  // config/sim/handheld_crowd_deep.yaml, scenario seed 5, frames 30-59: the walkers cover half of
  // the view and take about their share of the 1000 ORB keypoints, so the room keeps about half.
  // With the walkers' depth blanked (icgm_slam_offline --oracle-static) the room's keypoints
  // alone register, and the error follows how well they tell a pan from a sideways slide, i.e.
  // how many they are and how far their inverse depths spread: 0.100 m with 1000 keypoints,
  // 0.034 m with 2000, 0.046 m with 1000 spread over 80 px cells (features.spread_cell_px,
  // off: with the walkers 0.166 -> 0.138 m, but the real Bonn excerpt is worse with it).
  const sim::Simulator sim(Scenario("handheld_crowd_deep.yaml", 5));
  ASSERT_GE(sim.size(), 60u);
  FeatureOptions plain;
  ReadOptions(OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/icgm.yaml")
                  .Section("features"),
              &plain);
  ASSERT_EQ(plain.spread_cell_px, 0) << "spread is off in the shipped configuration";
  FeatureOptions spread = plain;
  spread.spread_cell_px = 80;
  const auto plain_extractor = FeatureExtractor::Create(plain);
  const auto spread_extractor = FeatureExtractor::Create(spread);
  // Room keypoints (off the walkers' mask, with depth): count and inverse depths.
  struct Room {
    size_t keypoints = 0, on_walkers = 0, all = 0;
    double sum = 0.0, sum_sq = 0.0;
    double InverseDepthSd() const {
      const double mean = sum / keypoints;
      return std::sqrt(std::max(0.0, sum_sq / keypoints - mean * mean));
    }
  };
  Room plain_room, spread_room;
  double coverage = 0.0;
  constexpr size_t kFirst = 30, kFrames = 30;
  for (size_t i = kFirst; i < kFirst + kFrames; ++i) {
    const sim::SimFrame f = sim.Render(i);
    coverage += static_cast<double>(cv::countNonZero(f.dynamic_mask)) / f.dynamic_mask.total();
    const auto count = [&](const FeatureSet& set, Room* room) {
      ASSERT_LE(set.size(), static_cast<size_t>(plain.max_features));
      ASSERT_EQ(set.descriptors.rows, static_cast<int>(set.size()));
      for (const cv::KeyPoint& k : set.keypoints) {
        const int x = std::clamp(static_cast<int>(std::lround(k.pt.x)), 0, f.bgr.cols - 1);
        const int y = std::clamp(static_cast<int>(std::lround(k.pt.y)), 0, f.bgr.rows - 1);
        ++room->all;
        if (f.dynamic_mask.at<uint8_t>(y, x) != 0) {
          ++room->on_walkers;
          continue;
        }
        const float z = f.depth_m.at<float>(y, x);
        if (!(z > 0.0f)) continue;
        ++room->keypoints;
        room->sum += 1.0 / z;
        room->sum_sq += 1.0 / (double(z) * z);
      }
    };
    count(plain_extractor->Extract(f.bgr), &plain_room);
    count(spread_extractor->Extract(f.bgr), &spread_room);
  }
  coverage /= kFrames;
  const double walker_share = static_cast<double>(plain_room.on_walkers) / plain_room.all;
  std::printf(
      "handheld crowd, seed 5, frames 30-59: walkers cover %.1f%% of the image and take %.1f%% "
      "of the keypoints; room keypoints with depth per frame %.0f (spread: %.0f), sd of their "
      "inverse depth %.4f / m (spread: %.4f / m)\n",
      100.0 * coverage, 100.0 * walker_share, double(plain_room.keypoints) / kFrames,
      double(spread_room.keypoints) / kFrames, plain_room.InverseDepthSd(),
      spread_room.InverseDepthSd());
  // The budget is shared about in proportion to the image: the walkers leave the room about
  // half of it (the room alone, with the walkers' pixels flat, keeps about 870).
  EXPECT_GT(coverage, 0.4);
  EXPECT_NEAR(walker_share, coverage, 0.1);
  // Spread, the room's keypoints reach nearer surfaces (floor, desks) and the sides.
  EXPECT_GT(spread_room.InverseDepthSd(), 1.15 * plain_room.InverseDepthSd());
}

}  // namespace
}  // namespace icgm
