// Monocular odometry on a short clip rendered by the simulator (colour only; depth ignored):
// the trajectory must match the ground truth up to a similarity (Sim(3) ATE bound), the wheel
// odometry must give the metric scale, and blank frames must make it lose track, drop the map,
// initialize again and carry on.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/dataset/trajectory.h"
#include "core/mono/mono_evaluation.h"
#include "core/mono/mono_odometry.h"
#include "core/sim/sim_export.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

constexpr size_t kFrames = 90;

// A clip rendered once per scenario: its first kFrames frames, without pedestrians.
struct Clip {
  std::unique_ptr<sim::Simulator> sim;
  std::vector<sim::SimFrame> frames;
};

// `seed`: the scenario's world seed instead of its own.
Clip Render(const std::string& scenario, bool pedestrians = false, size_t frames = kFrames,
            std::optional<int> seed = std::nullopt) {
  Clip c;
  sim::SimOptions options =
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/" + scenario);
  if (seed) options.seed = *seed;
  c.sim = std::make_unique<sim::Simulator>(options);
  sim::RenderFlags flags;
  flags.pedestrians = pedestrians;
  for (size_t i = 0; i < frames && i < c.sim->size(); ++i) {
    c.frames.push_back(c.sim->Render(i, flags));
  }
  return c;
}

// A hand-held camera drifting and panning in an office (config/sim/handheld_crowd_deep.yaml).
const Clip& HandheldClip() {
  static const Clip clip = Render("handheld_crowd_deep.yaml");
  return clip;
}

// A robot driving straight along the cafeteria, with wheel odometry
// (config/sim/static_short.yaml).
const Clip& WheeledClip() {
  static const Clip clip = Render("static_short.yaml");
  return clip;
}

struct ClipRun {
  Trajectory estimate;
  std::vector<MonoFrameResult> results;
  size_t resets = 0;

  // One frame's result: its pose (and the reference's, on initialization) into the estimate.
  void Add(const MonoFrameResult& r) {
    if (r.initialized) estimate.push_back({r.reference_stamp, r.reference_world_camera});
    if (r.has_pose) estimate.push_back({r.stamp, r.world_camera});
    resets += r.reset;
    results.push_back(r);
  }
};

// `blank`: frames [blank_from, blank_to) replaced by black images (blurred with `blur`).
ClipRun RunClip(const Clip& clip, bool wheels, size_t blank_from = 0, size_t blank_to = 0,
                const MonoOptions& options = MonoOptions(), bool blur = false) {
  MonoOdometry vo(options, clip.sim->intrinsics());
  if (wheels) vo.SetBaseToCamera(*clip.sim->base_to_camera());
  ClipRun run;
  for (const sim::SimFrame& f : clip.frames) {
    if (wheels) {
      EXPECT_TRUE(vo.AddWheelOdometry(f.stamp, f.odometry.T_odom_base).ok());
    }
    const bool blank = f.index >= blank_from && f.index < blank_to;
    cv::Mat image = f.bgr;
    if (blank && blur) {
      // Horizontal motion blur over 13 px, as a quick pan smears the image (into a new image:
      // the clip's frames are shared by the runs and stay sharp).
      image = cv::Mat();
      cv::filter2D(f.bgr, image, -1, cv::Mat(1, 13, CV_32F, cv::Scalar(1.0 / 13.0)));
    } else if (blank) {
      image = cv::Mat(f.bgr.size(), CV_8UC3, cv::Scalar::all(0));
    }
    run.Add(vo.ProcessFrame(f.stamp, image));
  }
  SortByStamp(&run.estimate);
  return run;
}

// Two runs give the same poses, frame for frame (an option that must not act on this input).
void ExpectSamePoses(const ClipRun& a, const ClipRun& b) {
  ASSERT_EQ(a.estimate.size(), b.estimate.size());
  ASSERT_GT(a.estimate.size(), kFrames / 2);
  for (size_t i = 0; i < a.estimate.size(); ++i) {
    EXPECT_EQ(a.estimate[i].pose.matrix(), b.estimate[i].pose.matrix()) << i;
  }
}

// An ICGM-stage option set in `on` acts only with ICGM and only where the moving-point checks
// do: without ICGM it gives the plain-matching run pose for pose, with wheels the default
// wheeled run.
void ExpectIcgmStageOnlyWithoutWheels(const MonoOptions& on) {
  MonoOptions plain;
  plain.vo.use_icgm = false;
  MonoOptions plain_on = on;
  plain_on.vo.use_icgm = false;
  ExpectSamePoses(RunClip(HandheldClip(), false, 0, 0, plain_on),
                  RunClip(HandheldClip(), false, 0, 0, plain));
  ExpectSamePoses(RunClip(WheeledClip(), true, 0, 0, on), RunClip(WheeledClip(), true));
}

// The options with the moving-point checks off (cull_outlier_frames, new_point_confirm_px; on
// by default for inputs without wheels).
MonoOptions WithoutMovingPointChecks() {
  MonoOptions o;
  o.vo.cull_outlier_frames = 0;
  o.vo.new_point_confirm_px = 0.0;
  return o;
}

Trajectory Truth(const Clip& clip) {
  Trajectory t;
  for (const sim::SimFrame& f : clip.frames) t.push_back({f.stamp, f.T_world_camera});
  return t;
}

TEST(MonoOdometryTest, TracksRenderedClipWithinSim3Bound) {
  const ClipRun run = RunClip(HandheldClip(), false);
  size_t tracked = 0;
  for (const auto& r : run.results) tracked += r.has_pose;
  // Initialization waits for parallax (the hand drifts 6 cm/s), then every frame is tracked.
  EXPECT_GT(tracked, 0.6 * kFrames);
  EXPECT_EQ(run.resets, 0u);
  for (const auto& r : run.results) EXPECT_FALSE(r.scale_known);
  MonoEvaluation eval;
  {
    const Status s = EvaluateMonoTrajectory(Truth(HandheldClip()), run.estimate, 0.01, &eval);
    ASSERT_TRUE(s.ok()) << s.reason();
  }
  std::printf(
      "rendered clip, no wheels: %zu/%zu frames tracked, Sim(3) ATE %.4f m over %.2f m "
      "(%.2f%%)\n",
      tracked, kFrames, eval.evaluation.ate.rmse, eval.distance_m, eval.error_percent);
  // Measured 0.014 m over 0.18 m of drift while panning, walls 2-4 m away.
  EXPECT_GT(eval.distance_m, 0.1);
  EXPECT_LT(eval.evaluation.ate.rmse, 0.025);
}

TEST(MonoOdometryTest, WheelOdometryGivesTheMetricScale) {
  const Clip& clip = WheeledClip();
  const ClipRun run = RunClip(clip, true);
  ASSERT_FALSE(run.results.empty());
  EXPECT_TRUE(run.results.back().scale_known);
  EXPECT_EQ(run.resets, 0u);
  ASSERT_GE(run.estimate.size(), kFrames / 2);
  // The straight drive cannot be Sim(3)-aligned (collinear): compare the distance covered
  // between the first and the last pose with the truth's.
  const auto truth_at = [&](Time t) {
    for (const auto& f : clip.frames) {
      if (f.stamp == t) return f.T_world_camera;
    }
    ADD_FAILURE() << "no frame at the stamp";
    return Pose3::Identity();
  };
  const double estimated =
      (run.estimate.back().pose.translation() - run.estimate.front().pose.translation()).norm();
  const double truth = (truth_at(run.estimate.back().stamp).translation() -
                        truth_at(run.estimate.front().stamp).translation())
                           .norm();
  std::printf("rendered drive with wheels: %.3f m estimated, %.3f m true\n", estimated, truth);
  ASSERT_GT(truth, 1.0);
  EXPECT_NEAR(estimated / truth, 1.0, 0.1);
}

// Distance between the first and the last pose of `poses`, estimated and true.
std::pair<double, double> Covered(const Clip& clip, const Trajectory& poses) {
  const auto truth_at = [&](Time t) {
    for (const auto& f : clip.frames) {
      if (f.stamp == t) return f.T_world_camera;
    }
    ADD_FAILURE() << "no frame at the stamp";
    return Pose3::Identity();
  };
  return {(poses.back().pose.translation() - poses.front().pose.translation()).norm(),
          (truth_at(poses.back().stamp).translation() - truth_at(poses.front().stamp).translation())
              .norm()};
}

TEST(MonoOdometryTest, BlankFramesLoseTrackAndReinitialize) {
  // The wheeled clip without its wheels: the scale is arbitrary, and carried over the loss.
  const Clip& clip = WheeledClip();
  const size_t from = 40, to = 52;
  const ClipRun run = RunClip(clip, false, from, to);
  EXPECT_EQ(run.resets, 1u);
  for (size_t i = from; i < to; ++i) {
    EXPECT_FALSE(run.results[i].has_pose) << i;
    EXPECT_FALSE(run.results[i].status.ok()) << i;
  }
  EXPECT_EQ(run.results[to - 1].state, MonoState::kInitializing);
  // Initialized again within a second of images, and tracking to the end.
  size_t reinit = 0;
  for (size_t i = to; i < kFrames; ++i) {
    if (run.results[i].initialized) reinit = i;
  }
  ASSERT_GT(reinit, 0u) << "never re-initialized";
  EXPECT_LT(reinit, to + 30);
  EXPECT_EQ(run.results.back().state, MonoState::kTracking);
  for (const auto& r : run.results) EXPECT_FALSE(r.scale_known);
  // Map units per metre before and after the loss agree (the speed before the loss sets the
  // new map's scale).
  Trajectory before, after;
  for (const auto& p : run.estimate) {
    (p.stamp < run.results[from].stamp ? before : after).push_back(p);
  }
  ASSERT_GE(before.size(), 10u);
  ASSERT_GE(after.size(), 10u);
  const auto [est_before, true_before] = Covered(clip, before);
  const auto [est_after, true_after] = Covered(clip, after);
  const double scale_before = est_before / true_before, scale_after = est_after / true_after;
  std::printf(
      "blank frames %zu-%zu: re-initialized at frame %zu; map units per metre %.3f "
      "before, %.3f after\n",
      from, to - 1, reinit, scale_before, scale_after);
  EXPECT_NEAR(scale_after / scale_before, 1.0, 0.25);
}

// reset_bridge_max_s: the wheeled clip without its wheels drives on at a steady speed through
// blank frames; the new map's reference frame is carried on at the last map's constant velocity,
// so the new map continues from about where the camera is, not from where the last map lost it.
// (The run is a straight line: a Sim(3) alignment of it is degenerate, so the join is measured
// against the true distance.)
TEST(MonoOdometryTest, BridgeOverAResetCarriesTheLastVelocity) {
  const Clip& clip = WheeledClip();
  const size_t from = 40, to = 52;
  MonoOptions on;
  on.vo.reset_bridge_max_s = 2.0;
  const MonoOptions off;
  ASSERT_EQ(off.vo.reset_bridge_max_s, 0.0);  // the default
  // The distance (m) from the last tracked pose before the loss to the new map's reference
  // frame: estimated (map units over the map's units per metre before the loss) and true.
  struct Join {
    double estimated_m = 0.0, true_m = 0.0;
  };
  const auto join = [&](const MonoOptions& options) -> std::optional<Join> {
    const ClipRun run = RunClip(clip, false, from, to, options);
    EXPECT_EQ(run.resets, 1u);
    Trajectory before;
    std::optional<size_t> last;
    for (size_t i = 0; i < from; ++i) {
      if (!run.results[i].has_pose) continue;
      last = i;
      before.push_back({run.results[i].stamp, run.results[i].world_camera});
    }
    if (!last || before.size() < 10) return std::nullopt;
    const auto [est_before, true_before] = Covered(clip, before);
    for (size_t i = to; i < run.results.size(); ++i) {
      const MonoFrameResult& r = run.results[i];
      if (!r.initialized) continue;
      for (size_t k = *last; k < i; ++k) {
        if (clip.frames[k].stamp != r.reference_stamp) continue;
        Join j;
        j.estimated_m =
            (r.reference_world_camera.translation() - run.results[*last].world_camera.translation())
                .norm() /
            (est_before / true_before);
        j.true_m = (clip.frames[k].T_world_camera.translation() -
                    clip.frames[*last].T_world_camera.translation())
                       .norm();
        return j;
      }
    }
    return std::nullopt;
  };
  const auto with = join(on), without = join(off);
  ASSERT_TRUE(with && without) << "never re-initialized";
  std::printf(
      "blank frames %zu-%zu: the new map's reference frame %.3f m from the last tracked pose with "
      "the bridge (true %.3f m), %.3f m without (true %.3f m)\n",
      from, to - 1, with->estimated_m, with->true_m, without->estimated_m, without->true_m);
  ASSERT_GT(with->true_m, 0.1);  // the robot drove on during the loss
  EXPECT_LT(without->estimated_m, 1e-6);
  EXPECT_NEAR(with->estimated_m, with->true_m, 0.25 * with->true_m);
}

// relocalize_good_keyframe_points: a large occluder (a walker in front of the hand-held
// camera) hides all but a strip of the view for frames [from, to); the frames made keyframes
// meanwhile carry few map points. A frame that tracking and the relocalization against the
// newest keyframes cannot place is matched by ICGM to the last keyframe that carried enough
// points, and the essential matrix of that consistent set predicts its pose for the
// projection search. The frames placed so must lie where the rest of the run puts them.
TEST(MonoOdometryTest, LostFramesRelocalizeOnTheLastGoodKeyframe) {
  const Clip& clip = HandheldClip();
  const size_t from = 48, to = 60;
  const auto run_with = [&](const MonoOptions& options) {
    MonoOdometry vo(options, clip.sim->intrinsics());
    ClipRun run;
    for (const sim::SimFrame& f : clip.frames) {
      cv::Mat image = f.bgr;
      if (f.index >= from && f.index < to) {
        image = f.bgr.clone();
        // Covers all but the left 15% of the view.
        const int left = image.cols * 15 / 100;
        image(cv::Rect(left, 0, image.cols - left, image.rows)).setTo(cv::Scalar(60, 50, 40));
      }
      run.Add(vo.ProcessFrame(f.stamp, image));
    }
    SortByStamp(&run.estimate);
    return run;
  };
  MonoOptions on;
  on.vo.relocalize_good_keyframe_points = 100;
  const MonoOptions off;
  ASSERT_EQ(off.vo.relocalize_good_keyframe_points, 0);  // the default
  const ClipRun with = run_with(on), without = run_with(off);
  size_t good = 0, posed_with = 0, posed_without = 0;
  for (size_t i = 0; i < with.results.size(); ++i) {
    good += with.results[i].relocalized_on_good_keyframe;
    posed_with += with.results[i].has_pose;
    posed_without += without.results[i].has_pose;
    EXPECT_FALSE(without.results[i].relocalized_on_good_keyframe);
  }
  MonoEvaluation e_with, e_without;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), with.estimate, 0.01, &e_with).ok());
  const bool aligned_without =
      EvaluateMonoTrajectory(Truth(clip), without.estimate, 0.01, &e_without).ok();
  std::printf(
      "occluded frames %zu-%zu: %zu frames placed on the last good keyframe; %zu posed, %zu "
      "resets, Sim(3) ATE %.4f m with the option; %zu posed, %zu resets, %.4f m without\n",
      from, to - 1, good, posed_with, with.resets, e_with.evaluation.ate.rmse, posed_without,
      without.resets, aligned_without ? e_without.evaluation.ate.rmse : -1.0);
  EXPECT_GT(good, 0u);
  EXPECT_GE(posed_with, posed_without);
  EXPECT_LE(with.resets, without.resets);
  // Each frame placed on the good keyframe lies within 3 cm of the truth once the run is
  // aligned (the clip's Sim(3) ATE bound is 2.5 cm).
  for (size_t k = 0; k < e_with.evaluation.num_associated(); ++k) {
    for (const MonoFrameResult& r : with.results) {
      if (r.relocalized_on_good_keyframe && r.stamp == e_with.evaluation.stamps[k]) {
        EXPECT_LT(e_with.evaluation.ate_m[k], 0.03) << r.frame_index;
      }
    }
  }
  EXPECT_LT(e_with.evaluation.ate.rmse, 0.025);
}

// Blurred frames keep few ratio-test matches: the relocalization against the local map (the
// map's points projected with the predicted pose) tracks them; without it they get no pose.
// The blurred frames must not become keyframes (keyframe_min_feature_ratio): with the
// moving-point checks (the default without wheels) the map keeps fewer points before the blur,
// and when blurred frames become keyframes the frames after the blur fail to track against
// them and the map is lost (measured: 1 reset).
TEST(MonoOdometryTest, BlurredFramesRelocalizeAgainstTheLocalMap) {
  const Clip& clip = HandheldClip();
  const size_t from = 50, to = 56;
  const ClipRun with = RunClip(clip, false, from, to, MonoOptions(), true);
  MonoOptions off;
  off.vo.relocalize = false;
  const ClipRun without = RunClip(clip, false, from, to, off, true);
  MonoOptions any_keyframe;
  any_keyframe.vo.keyframe_min_feature_ratio = 0.0;
  const ClipRun blurred_keyframes = RunClip(clip, false, from, to, any_keyframe, true);
  size_t relocalized = 0, tracked_with = 0, tracked_without = 0;
  for (size_t i = from; i < to; ++i) {
    relocalized += with.results[i].relocalized;
    tracked_with += with.results[i].has_pose;
    tracked_without += without.results[i].has_pose;
  }
  std::printf(
      "blurred frames %zu-%zu: with relocalization %zu tracked (%zu relocalized), %zu "
      "resets; without %zu tracked, %zu resets\n",
      from, to - 1, tracked_with, relocalized, with.resets, tracked_without, without.resets);
  std::printf("blurred frames as keyframes: %zu resets\n", blurred_keyframes.resets);
  EXPECT_EQ(with.resets, 0u);
  EXPECT_GT(blurred_keyframes.resets, 0u);
  EXPECT_GT(relocalized, 0u);
  EXPECT_GT(tracked_with, tracked_without);
  MonoEvaluation eval;
  const Status s = EvaluateMonoTrajectory(Truth(clip), with.estimate, 0.01, &eval);
  ASSERT_TRUE(s.ok()) << s.reason();
  // Measured 0.023 m (0.015 m without the blur): one map over the whole clip.
  std::printf("Sim(3) ATE with the blurred frames %.4f m\n", eval.evaluation.ate.rmse);
  EXPECT_LT(eval.evaluation.ate.rmse, 0.035);
}

// Share of the matches given to the geometry that lie on a walker (the rendered dynamic mask),
// over the tracked frames of a run.
struct WalkerShare {
  size_t on_walkers = 0;
  size_t total = 0;
  double share() const { return total ? static_cast<double>(on_walkers) / total : 0.0; }
};

WalkerShare CountWalkerMatches(const Clip& clip, const ClipRun& run) {
  WalkerShare w;
  for (size_t i = 0; i < run.results.size(); ++i) {
    const MonoFrameResult& r = run.results[i];
    if (r.state != MonoState::kTracking || r.initialized) continue;
    const cv::Mat& mask = clip.frames[i].dynamic_mask;
    for (const Eigen::Vector2d& px : r.robust_pixels) {
      const int u = static_cast<int>(std::lround(px.x()));
      const int v = static_cast<int>(std::lround(px.y()));
      if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
      w.on_walkers += mask.at<uint8_t>(v, u) != 0;
      ++w.total;
    }
  }
  return w;
}

// The ICGM motion prior in tracking on a robot among walkers (crowded.yaml with its wheels and
// pedestrians): with the wheel prediction, the matches to map points are compared with where
// those points reproject if static, so fewer matches on walkers reach the geometry than with
// plain ICGM, while the static matches stay enough to track every frame plain ICGM tracks.
// At Thr 0.01 (wheel_prior_threshold). The default 0.02 keeps more static matches over whole
// runs (crowded.yaml, ten seeds: 5.21% of the distance against 6.70% at 0.01) but on this clip
// also more walker matches than plain ICGM: 186 of 6173 (3.01%) against 167 of 6782 (2.46%).
TEST(MonoOdometryTest, MotionPriorRemovesWalkerMatchesThatPlainIcgmKeeps) {
  static const Clip clip = Render("crowded.yaml", true);
  MonoOptions with_prior;
  ASSERT_TRUE(with_prior.icgm.motion_prior);  // the default
  with_prior.vo.wheel_prior_threshold = 0.01;
  MonoOptions plain = with_prior;
  plain.icgm.motion_prior = false;
  const ClipRun prior_run = RunClip(clip, true, 0, 0, with_prior);
  const ClipRun plain_run = RunClip(clip, true, 0, 0, plain);
  const WalkerShare prior = CountWalkerMatches(clip, prior_run);
  const WalkerShare without = CountWalkerMatches(clip, plain_run);
  size_t tracked_prior = 0, tracked_plain = 0;
  for (const auto& r : prior_run.results) tracked_prior += r.has_pose;
  for (const auto& r : plain_run.results) tracked_plain += r.has_pose;
  std::printf(
      "matches on walkers: plain ICGM %zu of %zu (%.2f%%), with the motion prior %zu of %zu "
      "(%.2f%%); frames tracked %zu vs %zu\n",
      without.on_walkers, without.total, 100 * without.share(), prior.on_walkers, prior.total,
      100 * prior.share(), tracked_plain, tracked_prior);
  ASSERT_GT(without.on_walkers, 20u) << "the clip must put walker matches in front of ICGM";
  // Measured: 167 matches on walkers with plain ICGM, 134 with the prior (0.80x). Before each
  // map point was matched at most once per frame after a relocalization, 168 and 119 (0.71x),
  // asserted below 0.8x; the prior run's relocalized frames no longer count points twice, and
  // the bound is now 0.9x.
  EXPECT_LT(prior.on_walkers, 0.9 * without.on_walkers);
  EXPECT_LT(prior.share(), without.share());
  EXPECT_GE(tracked_prior, tracked_plain);
}

// Without wheels the prior's Thr follows the constant-velocity prediction's error: a jerk of
// the hand (here: four frames of the clip skipped while the stamps go on at the frame rate, so
// the camera moves five times as far as predicted) raises it on the next frame, steady motion
// keeps it near prior_threshold_min, and the clip stays tracked.
TEST(MonoOdometryTest, PriorThresholdFollowsThePredictionError) {
  const Clip& clip = HandheldClip();
  MonoOptions options;
  options.vo.prior_from_prediction_error = true;
  MonoOdometry vo(options, clip.sim->intrinsics());
  constexpr size_t kJerk = 60, kSkipped = 4;
  std::vector<MonoFrameResult> results;
  for (size_t i = 0; i + kSkipped < clip.frames.size(); ++i) {
    const size_t image = i < kJerk ? i : i + kSkipped;
    results.push_back(vo.ProcessFrame(clip.frames[i].stamp, clip.frames[image].bgr));
  }
  std::vector<double> steady;
  size_t tracked = 0;
  for (size_t i = 0; i < results.size(); ++i) {
    tracked += results[i].has_pose;
    if (i + 10 < kJerk && results[i].has_pose && results[i].prior_threshold > 0.0) {
      steady.push_back(results[i].prior_threshold);
    }
    if (results[i].prior_threshold > 0.0) {
      EXPECT_GE(results[i].prior_threshold, options.vo.prior_threshold_min - 1e-12) << i;
      EXPECT_LE(results[i].prior_threshold, options.vo.prior_threshold_max + 1e-12) << i;
    }
  }
  ASSERT_GE(steady.size(), 10u);
  std::sort(steady.begin(), steady.end());
  const double steady_median = steady[steady.size() / 2];
  const MonoFrameResult& at_jerk = results[kJerk];
  const MonoFrameResult& after = results[kJerk + 1];
  std::printf(
      "prior Thr: steady median %.3f, at the jerk %.3f, after it %.3f; %zu of %zu "
      "frames tracked\n",
      steady_median, at_jerk.prior_threshold, after.prior_threshold, tracked, results.size());
  EXPECT_LT(steady_median, 0.5 * (options.vo.prior_threshold_min + options.vo.prior_threshold_max));
  EXPECT_TRUE(at_jerk.has_pose);
  EXPECT_TRUE(after.has_pose);
  EXPECT_GT(after.prior_threshold, 1.5 * steady_median);
  EXPECT_EQ(vo.num_resets(), 0u);

  // The fixed prior (option off) uses icgm.motion_prior_threshold on every tracked frame.
  MonoOdometry fixed(MonoOptions(), clip.sim->intrinsics());
  for (size_t i = 0; i < 40; ++i) {
    const MonoFrameResult r = fixed.ProcessFrame(clip.frames[i].stamp, clip.frames[i].bgr);
    if (r.prior_threshold > 0.0) {
      EXPECT_DOUBLE_EQ(r.prior_threshold, MonoOptions().icgm.motion_prior_threshold);
    }
  }
}

// New points only from the ICGM group grown from the PnP inliers: the map keeps growing at
// keyframes (the group holds the static structure) and the clip stays within the Sim(3) bound.
TEST(MonoOdometryTest, NewPointsFromTheMapGroupKeepTheMapGrowing) {
  MonoOptions options;
  options.vo.new_points_from_map_group = true;
  const ClipRun group = RunClip(HandheldClip(), false, 0, 0, options);
  const ClipRun plain = RunClip(HandheldClip(), false);
  size_t tracked = 0, keyframes = 0;
  for (const auto& r : group.results) {
    tracked += r.has_pose;
    keyframes += r.new_keyframe;
  }
  MonoEvaluation eval;
  {
    const Status s = EvaluateMonoTrajectory(Truth(HandheldClip()), group.estimate, 0.01, &eval);
    ASSERT_TRUE(s.ok()) << s.reason();
  }
  const size_t points_group = group.results.back().map_points;
  const size_t points_plain = plain.results.back().map_points;
  std::printf(
      "map group: %zu/%zu frames tracked, %zu keyframes, %zu map points (plain ICGM "
      "%zu), Sim(3) ATE %.4f m\n",
      tracked, kFrames, keyframes, points_group, points_plain, eval.evaluation.ate.rmse);
  EXPECT_GT(tracked, 0.6 * kFrames);
  EXPECT_EQ(group.resets, 0u);
  // Beyond the initialization's two keyframes the map grew at least once more (how many more
  // depends on the bundle adjustment's time caps, i.e. on the machine's load).
  EXPECT_GE(keyframes, 3u);
  // The static scene is one group: most of the points plain ICGM would add are added.
  EXPECT_GT(points_group, 0.7 * points_plain);
  EXPECT_LT(eval.evaluation.ate.rmse, 0.025);
}

// Without a wall-clock cap on the bundle adjustment (the default), the same input gives the
// same poses, however loaded the machine is.
TEST(MonoOdometryTest, SameInputGivesTheSamePoses) {
  ASSERT_EQ(MonoOptions().bundle_adjustment.max_solver_time_s, 0.0);
  const ClipRun a = RunClip(HandheldClip(), false);
  const ClipRun b = RunClip(HandheldClip(), false);
  ASSERT_EQ(a.estimate.size(), b.estimate.size());
  ASSERT_GT(a.estimate.size(), kFrames / 2);
  for (size_t i = 0; i < a.estimate.size(); ++i) {
    EXPECT_EQ(a.estimate[i].stamp, b.estimate[i].stamp);
    EXPECT_EQ(a.estimate[i].pose.matrix(), b.estimate[i].pose.matrix()) << i;
  }
}

// RANSAC fed its matches in a drawn order (mono.ransac_order_seed): without ICGM the run is
// otherwise deterministic, and another seed gives another draw of it: other poses, tracked as
// well (the bound of TracksRenderedClipWithinSim3Bound).
TEST(MonoOdometryTest, DrawnRansacOrderIsAnotherDrawOfTheRunWithoutIcgm) {
  MonoOptions plain;
  plain.vo.use_icgm = false;
  MonoOptions drawn = plain;
  drawn.vo.ransac_order_seed = 5;
  const ClipRun a = RunClip(HandheldClip(), false, 0, 0, plain);
  const ClipRun b = RunClip(HandheldClip(), false, 0, 0, drawn);
  size_t differ = 0;
  for (size_t i = 0; i < a.estimate.size() && i < b.estimate.size(); ++i) {
    differ += a.estimate[i].pose.matrix() != b.estimate[i].pose.matrix();
  }
  EXPECT_GT(differ, kFrames / 4);
  for (const ClipRun* run : {&a, &b}) {
    MonoEvaluation eval;
    const Status s = EvaluateMonoTrajectory(Truth(HandheldClip()), run->estimate, 0.01, &eval);
    ASSERT_TRUE(s.ok()) << s.reason();
    EXPECT_GT(run->estimate.size(), kFrames / 2);
    EXPECT_LT(eval.evaluation.ate.rmse, 0.025);
  }
}

// Share of pixels on the rendered walkers, over the tracked frames of a run: the tracked
// poses' inliers and the new map points.
struct WalkerPixels {
  WalkerShare inliers, new_points;
  WalkerShare culled_points, rejected_points;  // pixels of the deleted and the not added points
  // The correspondences given to PnP, and those track_icgm_baseline_frames held back.
  WalkerShare robust, long_baseline_dropped;
  size_t culled = 0, rejected = 0, tracked = 0;
};

WalkerPixels CountWalkerPixels(const Clip& clip, const ClipRun& run) {
  WalkerPixels w;
  const auto count = [](const cv::Mat& mask, const std::vector<Eigen::Vector2d>& pixels,
                        WalkerShare* share) {
    for (const Eigen::Vector2d& px : pixels) {
      const int u = static_cast<int>(std::lround(px.x()));
      const int v = static_cast<int>(std::lround(px.y()));
      if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
      share->on_walkers += mask.at<uint8_t>(v, u) != 0;
      ++share->total;
    }
  };
  for (size_t i = 0; i < run.results.size(); ++i) {
    const MonoFrameResult& r = run.results[i];
    w.tracked += r.has_pose;
    w.culled += r.culled_points;
    w.rejected += r.rejected_new_points;
    count(clip.frames[i].dynamic_mask, r.tracked_pixels, &w.inliers);
    count(clip.frames[i].dynamic_mask, r.new_point_pixels, &w.new_points);
    count(clip.frames[i].dynamic_mask, r.culled_pixels, &w.culled_points);
    count(clip.frames[i].dynamic_mask, r.rejected_new_point_pixels, &w.rejected_points);
    count(clip.frames[i].dynamic_mask, r.robust_pixels, &w.robust);
    count(clip.frames[i].dynamic_mask, r.long_baseline_dropped_pixels, &w.long_baseline_dropped);
  }
  return w;
}

// The hand-held camera among walkers (no wheels): map points that stop fitting the tracked
// pose are deleted (cull_outlier_frames) and a keyframe's new points must sit where an
// earlier view saw them (new_point_confirm_px). Both act more on walkers than on static
// points: the deleted points lie on walkers far more often than the tracked inliers, the
// points not added more often than the ones added, and fewer of the new map points lie on
// walkers than without the checks. Measured on the first 90 frames: deleted 57.9% on walkers
// against 27.2% of the tracked inliers, not added 50.9% against 43.1% of the added; new points
// on walkers 43.1% with the checks, 51.8% without; 59 against 69 frames tracked.
// The share of walkers among the tracked inliers is NOT lower with the checks (27.2% against
// 21.7%), and is no longer asserted. It was (27.2 against 31.6%) while tracking's projection
// search matched map points twice after a relocalization, which only the run without the
// checks did (5 relocalized frames). In the frames both runs track in their first map (21-42)
// the checks give 9.4% against 3.4%: they also reject static points (the map holds 311
// against 745 points at frame 42), so the walker points that get through weigh more, and the
// run with the checks loses that map at frame 43 and re-initializes at 52 amid the walkers.
// The hand-held camera among walkers (config/sim/handheld_crowd_deep.yaml, first kFrames frames).
const Clip& HandheldCrowdClip() {
  static const Clip clip = Render("handheld_crowd_deep.yaml", true);
  return clip;
}

TEST(MonoOdometryTest, MovingPointsAreKeptOutOfTheMap) {
  const Clip& clip = HandheldCrowdClip();
  MonoOptions on;
  on.vo.cull_outlier_frames = 2;
  on.vo.new_point_confirm_px = 3.0;
  const WalkerPixels with = CountWalkerPixels(clip, RunClip(clip, false, 0, 0, on));
  const WalkerPixels without =
      CountWalkerPixels(clip, RunClip(clip, false, 0, 0, WithoutMovingPointChecks()));
  std::printf(
      "on walkers: new map points %zu of %zu (%.1f%%) with the checks, %zu of %zu (%.1f%%) "
      "without; tracked inliers %.1f%% vs %.1f%%; %zu points deleted, %zu not added; "
      "frames tracked %zu vs %zu\n",
      with.new_points.on_walkers, with.new_points.total, 100 * with.new_points.share(),
      without.new_points.on_walkers, without.new_points.total, 100 * without.new_points.share(),
      100 * with.inliers.share(), 100 * without.inliers.share(), with.culled, with.rejected,
      with.tracked, without.tracked);
  std::printf("on walkers: %.1f%% of the deleted points, %.1f%% of the points not added\n",
              100 * with.culled_points.share(), 100 * with.rejected_points.share());
  ASSERT_GT(without.new_points.on_walkers, 20u) << "the clip must put walkers into the map";
  EXPECT_GT(with.culled, 0u);
  EXPECT_GT(with.rejected, 0u);
  EXPECT_LT(with.new_points.share(), without.new_points.share());
  EXPECT_GT(with.culled_points.share(), 1.5 * with.inliers.share());
  EXPECT_GT(with.rejected_points.share(), with.new_points.share());
  EXPECT_GE(with.tracked, 0.8 * without.tracked);
}

// The frames of a run that tried the two-view initialization against a reference frame, before
// and after the run's first reset: how many, and how many gave it every ratio-test match.
struct InitAttempts {
  size_t before = 0, before_all = 0, after = 0, after_all = 0, some_dropped = 0;
  size_t first_reset = 0, tracked = 0;
};

InitAttempts CountInitAttempts(const ClipRun& run) {
  InitAttempts a;
  bool after_reset = false;
  for (size_t i = 0; i < run.results.size(); ++i) {
    const MonoFrameResult& r = run.results[i];
    a.tracked += r.has_pose;
    if (r.reset && !after_reset) a.first_reset = i;
    after_reset |= r.reset;
    const bool attempt =
        r.initialized || (r.num_matches > 0 && r.status.reason().rfind("initialization: ", 0) == 0);
    if (!attempt) continue;
    const bool all = r.num_icgm_kept == r.num_matches;
    (after_reset ? a.after : a.before) += 1;
    (after_reset ? a.after_all : a.before_all) += all;
    a.some_dropped += !all;
  }
  return a;
}

// initialization_matches: "all" gives the two-view initialization every ratio-test match (the
// essential matrix's RANSAC alone sorts them), "all_after_reset" only when initializing again
// after a reset, "icgm" (default) the matches ICGM keeps. The crowd clip loses its first map
// and initializes again among the walkers.
TEST(MonoOdometryTest, InitializationMatchesFollowTheOption) {
  const Clip& clip = HandheldCrowdClip();
  MonoOptions icgm, all, after_reset;
  icgm.vo.initialization_matches = MonoInitMatches::kIcgm;
  all.vo.initialization_matches = MonoInitMatches::kAll;
  after_reset.vo.initialization_matches = MonoInitMatches::kAllAfterReset;
  const ClipRun run_icgm = RunClip(clip, false, 0, 0, icgm);
  const ClipRun run_all = RunClip(clip, false, 0, 0, all);
  const ClipRun run_after = RunClip(clip, false, 0, 0, after_reset);
  const InitAttempts i = CountInitAttempts(run_icgm), a = CountInitAttempts(run_all),
                     r = CountInitAttempts(run_after);
  std::printf(
      "initialization attempts (before / after the first reset) and frames tracked: icgm %zu / "
      "%zu, %zu; all %zu / %zu, %zu; all_after_reset %zu / %zu, %zu\n",
      i.before, i.after, i.tracked, a.before, a.after, a.tracked, r.before, r.after, r.tracked);
  ASSERT_GE(run_icgm.resets, 1u) << "the clip must lose its first map";
  ASSERT_GE(run_after.resets, 1u);
  ASSERT_GT(i.after, 0u);
  EXPECT_GT(i.some_dropped, 0u) << "ICGM drops no initialization match in the crowd";
  EXPECT_GT(a.before, 0u);
  EXPECT_EQ(a.some_dropped, 0u);
  // all_after_reset: the first map as with icgm, frame for frame, then every match.
  EXPECT_EQ(r.first_reset, i.first_reset);
  for (size_t k = 0; k < i.first_reset; ++k) {
    EXPECT_EQ(run_after.results[k].num_icgm_kept, run_icgm.results[k].num_icgm_kept) << k;
    EXPECT_EQ(run_after.results[k].has_pose, run_icgm.results[k].has_pose) << k;
  }
  EXPECT_EQ(r.before_all, i.before_all);
  ASSERT_GT(r.after, 0u);
  EXPECT_EQ(r.after_all, r.after);
}

// Moving regions (dynamic_mask_radius_px): the matches to map points that ICGM's motion prior
// rejected or the tracked pose did not fit, in this frame and the one before, mark where
// something moves; a keyframe adds no new point among them, and the clip stays tracked.
// The regions are not selective on this clip: measured on the first 90 frames, 54.6% of the
// points not added lie on walkers and 54.8% of the added ones (51.8% without the regions).
// Before each map point was matched at most once per frame after a relocalization, the run
// without the regions put 58.6% of its new points on walkers (doubled points), and the test
// asserted that the regions lower that share; that claim does not hold and is not asserted.
TEST(MonoOdometryTest, MovingRegionsHoldNewPointsBackAndKeepTracking) {
  const Clip& clip = HandheldCrowdClip();
  MonoOptions on = WithoutMovingPointChecks();
  on.vo.dynamic_mask_radius_px = 20.0;
  const WalkerPixels with = CountWalkerPixels(clip, RunClip(clip, false, 0, 0, on));
  const WalkerPixels without =
      CountWalkerPixels(clip, RunClip(clip, false, 0, 0, WithoutMovingPointChecks()));
  std::printf(
      "on walkers: new map points %zu of %zu (%.1f%%) with moving regions, %zu of %zu (%.1f%%) "
      "without; %zu not added (%.1f%% on walkers); frames tracked %zu vs %zu\n",
      with.new_points.on_walkers, with.new_points.total, 100 * with.new_points.share(),
      without.new_points.on_walkers, without.new_points.total, 100 * without.new_points.share(),
      with.rejected, 100 * with.rejected_points.share(), with.tracked, without.tracked);
  ASSERT_GT(without.new_points.on_walkers, 20u) << "the clip must put walkers into the map";
  EXPECT_GT(with.rejected, 0u);
  EXPECT_EQ(with.culled, 0u);
  EXPECT_LT(with.new_points.total, without.new_points.total);
  EXPECT_GE(with.tracked, 0.8 * without.tracked);
}

// moving_point_checks_with_wheels: false (the default) keeps the two checks off an input with
// wheel odometry (the run equals the one without the checks pose for pose) and on one without (the
// same clip without its wheels: points are deleted or not added).
TEST(MonoOdometryTest, MovingPointChecksCanBeLimitedToInputsWithoutWheels) {
  const Clip& clip = WheeledClip();
  MonoOptions gated;
  gated.vo.cull_outlier_frames = 2;
  gated.vo.new_point_confirm_px = 3.0;
  gated.vo.moving_point_checks_with_wheels = false;
  MonoOptions always = gated;
  always.vo.moving_point_checks_with_wheels = true;
  const auto checked = [](const ClipRun& run) {
    size_t n = 0;
    for (const auto& r : run.results) n += r.culled_points + r.rejected_new_points;
    return n;
  };
  const ClipRun plain = RunClip(clip, true, 0, 0, WithoutMovingPointChecks());
  const ClipRun gated_wheels = RunClip(clip, true, 0, 0, gated);
  const ClipRun always_wheels = RunClip(clip, true, 0, 0, always);
  const ClipRun gated_hand = RunClip(clip, false, 0, 0, gated);
  std::printf(
      "points deleted or not added: gated with wheels %zu, always with wheels %zu, gated "
      "without wheels %zu\n",
      checked(gated_wheels), checked(always_wheels), checked(gated_hand));
  EXPECT_EQ(checked(gated_wheels), 0u);
  EXPECT_GT(checked(always_wheels), 0u);
  EXPECT_GT(checked(gated_hand), 0u);
  ASSERT_EQ(gated_wheels.estimate.size(), plain.estimate.size());
  ASSERT_GT(plain.estimate.size(), kFrames / 2);
  for (size_t i = 0; i < plain.estimate.size(); ++i) {
    EXPECT_EQ(gated_wheels.estimate[i].pose.matrix(), plain.estimate[i].pose.matrix()) << i;
  }
}

// new_point_icgm_baseline_keyframes: a keyframe's new points must lie in the ICGM group grown
// from the tracked map between an older keyframe and this frame. On the hand-held crowd it
// turns candidates away (more new points not added than without it) and the clip stays
// tracked; it is part of the ICGM stage (the plain-matching run is the same pose for pose) and
// acts where the moving-point checks do (a wheeled run is the same pose for pose). It does not
// pick out walkers here (measured: 1579 vs 1137 new points not added, 47.7% vs 43.1% of the
// new points on walkers, 69 vs 59 frames tracked), so no walker share is asserted.
TEST(MonoOdometryTest, LongBaselineIcgmFiltersNewPointsOnlyWithIcgmAndWithoutWheels) {
  const Clip& crowd = HandheldCrowdClip();
  MonoOptions on;
  on.vo.new_point_icgm_baseline_keyframes = 8;
  const ClipRun with = RunClip(crowd, false, 0, 0, on);
  const ClipRun without = RunClip(crowd, false);
  const WalkerPixels w_with = CountWalkerPixels(crowd, with);
  const WalkerPixels w_without = CountWalkerPixels(crowd, without);
  std::printf(
      "long-baseline ICGM: %zu new points not added (%zu without), new map points on walkers "
      "%.1f%% of %zu (%.1f%% of %zu without), frames tracked %zu vs %zu\n",
      w_with.rejected, w_without.rejected, 100 * w_with.new_points.share(), w_with.new_points.total,
      100 * w_without.new_points.share(), w_without.new_points.total, w_with.tracked,
      w_without.tracked);
  EXPECT_GT(w_with.rejected, w_without.rejected);
  EXPECT_GE(w_with.tracked, 0.8 * w_without.tracked);

  ExpectIcgmStageOnlyWithoutWheels(on);
}

// track_icgm_baseline_frames: keypoints that ICGM puts outside the consistent group of their
// matches with the frame ten frames before (rotation prior) are not given to PnP. Between the
// frame and the newest keyframe a walker stays within Thr of the room; over a third of a second
// it does not. On the hand-held crowd the correspondences held back lie on walkers far more
// often than those given to PnP, and the clip stays tracked. They are few: the walkers' share of
// what PnP gets barely moves, and that of the tracked inliers does not fall (measured: 578 held
// back, 78.9% on walkers; PnP input 21.2% on walkers against 21.1%; tracked inliers 33.0%
// against 27.2%; 57 against 59 frames tracked), so no lower inlier share is asserted. It is part
// of the ICGM stage (the plain-matching run is the same pose for pose) and acts where the
// moving-point checks do (a wheeled run is the same pose for pose).
TEST(MonoOdometryTest, LongBaselineIcgmKeepsWalkersOutOfTracking) {
  const Clip& crowd = HandheldCrowdClip();
  MonoOptions on;
  on.vo.track_icgm_baseline_frames = 10;
  on.vo.track_icgm_baseline_rotation_prior = true;
  const WalkerPixels with = CountWalkerPixels(crowd, RunClip(crowd, false, 0, 0, on));
  const WalkerPixels without = CountWalkerPixels(crowd, RunClip(crowd, false));
  std::printf(
      "long-baseline ICGM in tracking: %zu correspondences held back, %.1f%% on walkers; given "
      "to PnP %.1f%% on walkers (%.1f%% without); tracked inliers on walkers %.1f%% of %zu "
      "(%.1f%% of %zu without), frames tracked %zu vs %zu\n",
      with.long_baseline_dropped.total, 100 * with.long_baseline_dropped.share(),
      100 * with.robust.share(), 100 * without.robust.share(), 100 * with.inliers.share(),
      with.inliers.total, 100 * without.inliers.share(), without.inliers.total, with.tracked,
      without.tracked);
  ASSERT_GT(with.long_baseline_dropped.total, 50u) << "the option must act on the crowd clip";
  ASSERT_GT(without.robust.share(), 0.05) << "the clip must give walker correspondences";
  EXPECT_GT(with.long_baseline_dropped.share(), 2.0 * without.robust.share());
  EXPECT_GE(with.tracked, 0.8 * without.tracked);

  ExpectIcgmStageOnlyWithoutWheels(on);
}

// track_icgm_baseline_max_translation_depth_ratio: the long-baseline check acts only while the
// camera moved less than that fraction of the median depth since the older frame. On the
// hand-held crowd clip a tighter bound skips more frames (measured: 2% skips 30 of 57 tracked
// frames, 0.01% 45 of 59); what the check still holds back at 2% lies mostly on walkers
// (81, 61.7%). At 100% nothing is skipped: the same poses as without the bound. Frames without
// a tracked pose for the older frame (after an initialization) are checked unbounded, so even
// 0.01% holds some back (108), and no count of held-back correspondences is asserted.
TEST(MonoOdometryTest, LongBaselineIcgmGateFollowsTranslationOverDepth) {
  const Clip& crowd = HandheldCrowdClip();
  MonoOptions on;
  on.vo.track_icgm_baseline_frames = 10;
  on.vo.track_icgm_baseline_rotation_prior = true;
  const auto gated_run = [&](double ratio, size_t* gated) {
    MonoOptions o = on;
    o.vo.track_icgm_baseline_max_translation_depth_ratio = ratio;
    ClipRun run = RunClip(crowd, false, 0, 0, o);
    *gated = 0;
    for (const MonoFrameResult& r : run.results) *gated += r.long_baseline_gated;
    return run;
  };
  size_t gated_loose = 0, gated_tight = 0, gated_none = 0;
  const ClipRun loose = gated_run(0.02, &gated_loose);
  const ClipRun tight = gated_run(1e-4, &gated_tight);
  const ClipRun none = gated_run(1.0, &gated_none);
  const WalkerPixels w_loose = CountWalkerPixels(crowd, loose);
  const WalkerPixels w_tight = CountWalkerPixels(crowd, tight);
  const WalkerPixels w_plain = CountWalkerPixels(crowd, RunClip(crowd, false));
  std::printf(
      "long-baseline gate: 2%% skips %zu of %zu tracked frames (%zu held back, %.1f%% on walkers), "
      "0.01%% skips %zu of %zu (%zu held back)\n",
      gated_loose, w_loose.tracked, w_loose.long_baseline_dropped.total,
      100 * w_loose.long_baseline_dropped.share(), gated_tight, w_tight.tracked,
      w_tight.long_baseline_dropped.total);
  EXPECT_EQ(gated_none, 0u);
  ExpectSamePoses(none, RunClip(crowd, false, 0, 0, on));
  ASSERT_GT(gated_loose, 0u) << "the camera must move more than 2% of the depth in 10 frames";
  EXPECT_GT(gated_tight, gated_loose + 5);
  ASSERT_GT(w_loose.long_baseline_dropped.total, 40u);
  EXPECT_GT(w_loose.long_baseline_dropped.share(), 2.0 * w_plain.robust.share());
}

// new_point_min_baseline_depth_ratio: a keyframe triangulates its new points with an older
// keyframe of the local map when the previous one is too close for parallax, and the views in
// between confirm them. On the hand-held crowd fewer of the new map points lie on walkers (the
// rendered masks) and the clip stays tracked; it acts where the moving-point checks do (a
// wheeled run is the same pose for pose).
TEST(MonoOdometryTest, ParallaxReferenceKeepsNewPointsOffWalkers) {
  const Clip& crowd = HandheldCrowdClip();
  MonoOptions on;
  on.vo.new_point_min_baseline_depth_ratio = 0.02;
  MonoOptions off;
  off.vo.new_point_min_baseline_depth_ratio = 0.0;
  const WalkerPixels with = CountWalkerPixels(crowd, RunClip(crowd, false, 0, 0, on));
  const WalkerPixels without = CountWalkerPixels(crowd, RunClip(crowd, false, 0, 0, off));
  std::printf(
      "parallax reference: new map points on walkers %.1f%% of %zu (%.1f%% of %zu without), "
      "tracked inliers on walkers %.1f%% (%.1f%%), frames tracked %zu vs %zu\n",
      100 * with.new_points.share(), with.new_points.total, 100 * without.new_points.share(),
      without.new_points.total, 100 * with.inliers.share(), 100 * without.inliers.share(),
      with.tracked, without.tracked);
  ASSERT_GT(without.new_points.on_walkers, 20u) << "the clip must put walkers into the map";
  EXPECT_LT(with.new_points.share(), 0.75 * without.new_points.share());
  EXPECT_LT(with.inliers.share(), without.inliers.share());
  // Measured: 26.9% of 683 vs 43.1% of 2501, tracked inliers 20.9% vs 27.2%, 51 vs 59 frames
  // tracked (fewer points reach the map, as with the moving-point checks).
  EXPECT_GE(with.tracked, 0.8 * without.tracked);

  ExpectSamePoses(RunClip(WheeledClip(), true, 0, 0, on), RunClip(WheeledClip(), true, 0, 0, off));
}

// relocalize_while_initializing: blank frames longer than lost_frames_before_reset make the
// odometry reset; with the option the lost map is kept, the first sharp frames relocalize
// against it and tracking resumes there without a new initialization, in the same frame and
// scale: the whole run aligns with the truth under one similarity. Without it the map must be
// initialized again from the slow hand's parallax (measured: not before the clip ends, 20
// poses against 50).
TEST(MonoOdometryTest, RelocalizesIntoTheKeptMapAfterAReset) {
  const Clip& clip = HandheldClip();
  const size_t from = 45, to = 60;
  MonoOptions on;
  on.vo.relocalize_while_initializing = true;
  MonoOptions off;
  off.vo.relocalize_while_initializing = false;
  const ClipRun with = RunClip(clip, false, from, to, on);
  const ClipRun without = RunClip(clip, false, from, to, off);
  EXPECT_EQ(with.resets, 1u);
  EXPECT_EQ(without.resets, 1u);
  size_t resumed = 0, reinit_with = 0;
  for (size_t i = to; i < kFrames; ++i) {
    if (!resumed && with.results[i].has_pose) resumed = i;
    reinit_with += with.results[i].initialized;
  }
  ASSERT_GT(resumed, 0u) << "never tracked again";
  EXPECT_TRUE(with.results[resumed].relocalized);
  EXPECT_EQ(reinit_with, 0u);
  EXPECT_LT(resumed, to + 3);
  EXPECT_EQ(with.results.back().state, MonoState::kTracking);
  MonoEvaluation eval_with, eval_without;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), with.estimate, 0.01, &eval_with).ok());
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), without.estimate, 0.01, &eval_without).ok());
  std::printf(
      "blank frames %zu-%zu: tracking resumed at frame %zu in the kept map; Sim(3) ATE %.4f m "
      "(%zu poses), re-initialized instead %.4f m (%zu poses)\n",
      from, to - 1, resumed, eval_with.evaluation.ate.rmse, with.estimate.size(),
      eval_without.evaluation.ate.rmse, without.estimate.size());
  EXPECT_LT(eval_with.evaluation.ate.rmse, 0.025);
  EXPECT_GT(with.estimate.size(), without.estimate.size());
}

// Keyframes of a run (initializations excluded): how many, the true distance (m) between
// consecutive ones of one map, and the new map points they added.
struct KeyframeStats {
  size_t keyframes = 0, new_points = 0, extra_new_points = 0, tracked = 0;
  double baseline_m = 0.0;  // mean over consecutive keyframe pairs
  double points_per_keyframe() const { return keyframes ? double(new_points) / keyframes : 0.0; }
};

KeyframeStats CountKeyframes(const Clip& clip, const ClipRun& run) {
  KeyframeStats s;
  std::optional<size_t> previous;
  double sum = 0.0;
  size_t pairs = 0;
  for (size_t i = 0; i < run.results.size(); ++i) {
    const MonoFrameResult& r = run.results[i];
    s.tracked += r.has_pose;
    if (r.reset || r.initialized) previous.reset();
    if (r.initialized) previous = i;
    if (!r.new_keyframe || r.initialized) continue;
    ++s.keyframes;
    s.new_points += r.new_point_pixels.size();
    s.extra_new_points += r.extra_new_points;
    if (previous) {
      sum += (clip.frames[i].T_world_camera.translation() -
              clip.frames[*previous].T_world_camera.translation())
                 .norm();
      ++pairs;
    }
    previous = i;
  }
  s.baseline_m = pairs ? sum / pairs : 0.0;
  return s;
}

// keyframe_min_baseline_depth_ratio: in the hand-held crowd the tracked points stay few, and
// without the parallax wait nearly every frame becomes a keyframe a few mm from the one before.
// With it the keyframes are fewer and farther apart in truth, and the clip stays tracked; the
// static hand-held clip still tracks within the Sim(3) bound, and a wheeled clip is unchanged.
TEST(MonoOdometryTest, KeyframesWaitForParallax) {
  const Clip& crowd = HandheldCrowdClip();
  MonoOptions on;
  on.vo.keyframe_min_baseline_depth_ratio = 0.02;
  MonoOptions off;
  off.vo.keyframe_min_baseline_depth_ratio = 0.0;
  const KeyframeStats with = CountKeyframes(crowd, RunClip(crowd, false, 0, 0, on));
  const KeyframeStats without = CountKeyframes(crowd, RunClip(crowd, false, 0, 0, off));
  std::printf(
      "parallax wait: %zu keyframes %.4f m apart in truth, %.1f new points each, %zu frames "
      "tracked; without: %zu keyframes %.4f m apart, %.1f new points each, %zu frames tracked\n",
      with.keyframes, with.baseline_m, with.points_per_keyframe(), with.tracked, without.keyframes,
      without.baseline_m, without.points_per_keyframe(), without.tracked);
  ASSERT_GT(without.keyframes, 10u) << "the clip must make keyframes";
  // Measured: 20 keyframes against 28 (0.71x). Before each map point was matched at most once
  // per frame after a relocalization, 19 against 28, asserted below 0.7x; now below 0.75x.
  EXPECT_LT(with.keyframes, 0.75 * without.keyframes);
  EXPECT_GT(with.baseline_m, 1.2 * without.baseline_m);
  EXPECT_GE(with.tracked, 0.9 * without.tracked);

  const ClipRun run = RunClip(HandheldClip(), false, 0, 0, on);
  MonoEvaluation eval;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(HandheldClip()), run.estimate, 0.01, &eval).ok());
  std::printf("static hand-held clip with the parallax wait: Sim(3) ATE %.4f m, %zu poses\n",
              eval.evaluation.ate.rmse, run.estimate.size());
  EXPECT_EQ(run.resets, 0u);
  EXPECT_LT(eval.evaluation.ate.rmse, 0.025);

  // With wheels the rule does not act: the same poses.
  ExpectSamePoses(RunClip(WheeledClip(), true, 0, 0, on), RunClip(WheeledClip(), true, 0, 0, off));
}

// new_point_extra_keyframes: a keyframe also triangulates with older keyframes far enough
// away. Points come from them, the map holds more points while the crowd passes, and the
// clip stays tracked; the static hand-held clip still tracks within the Sim(3) bound.
TEST(MonoOdometryTest, NewPointsFromOlderKeyframes) {
  const Clip& crowd = HandheldCrowdClip();
  MonoOptions on;
  on.vo.new_point_extra_keyframes = 2;
  MonoOptions off;
  off.vo.new_point_extra_keyframes = 0;
  const ClipRun run_with = RunClip(crowd, false, 0, 0, on);
  const ClipRun run_without = RunClip(crowd, false, 0, 0, off);
  const KeyframeStats with = CountKeyframes(crowd, run_with);
  const KeyframeStats without = CountKeyframes(crowd, run_without);
  const auto mean_map = [](const ClipRun& run) {
    double sum = 0.0;
    size_t n = 0;
    for (const auto& r : run.results) {
      if (!r.has_pose) continue;
      sum += r.map_points;
      ++n;
    }
    return n ? sum / n : 0.0;
  };
  std::printf(
      "older keyframes: %zu of %zu new points from them, map %.0f points per tracked frame "
      "(%.0f without), %zu vs %zu frames tracked\n",
      with.extra_new_points, with.new_points, mean_map(run_with), mean_map(run_without),
      with.tracked, without.tracked);
  EXPECT_EQ(without.extra_new_points, 0u);
  EXPECT_GT(with.extra_new_points, 50u);
  EXPECT_GT(mean_map(run_with), mean_map(run_without));
  EXPECT_GE(with.tracked, 0.9 * without.tracked);

  const ClipRun run = RunClip(HandheldClip(), false, 0, 0, on);
  MonoEvaluation eval;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(HandheldClip()), run.estimate, 0.01, &eval).ok());
  std::printf("static hand-held clip with older keyframes: Sim(3) ATE %.4f m, %zu poses\n",
              eval.evaluation.ate.rmse, run.estimate.size());
  EXPECT_EQ(run.resets, 0u);
  EXPECT_LT(eval.evaluation.ate.rmse, 0.025);
}

// After a relocalization, the pose's projection search must not match again a map point that
// the relocalization's projection search already matched (at another keypoint): a point found
// twice could be an inlier once and deleted as moving once, and the next keyframe would keep a
// deleted point. Blurred frames relocalize against the local map, through its projection; no
// map point may appear twice among a tracked pose's correspondences, on the blurred clip and
// on the crowd clip with its relocalizations.
TEST(MonoOdometryTest, EachMapPointIsMatchedOncePerFrame) {
  struct Case {
    const char* name;
    const Clip* clip;
    size_t from, to;
  };
  const Case cases[] = {{"hand-held, blurred 50-55", &HandheldClip(), 50, 56},
                        {"hand-held crowd, blurred 30-35", &HandheldCrowdClip(), 30, 36}};
  size_t would_duplicate = 0;
  for (const Case& c : cases) {
    const ClipRun run = RunClip(*c.clip, false, c.from, c.to, MonoOptions(), true);
    size_t relocalized = 0, frames_skipping = 0, skipped = 0;
    for (const MonoFrameResult& r : run.results) {
      relocalized += r.relocalized;
      frames_skipping += r.duplicate_points_skipped > 0;
      skipped += r.duplicate_points_skipped;
      std::unordered_set<int> seen;
      for (const int id : r.pose_point_ids) {
        EXPECT_TRUE(seen.insert(id).second)
            << c.name << ": frame " << r.frame_index << " matches map point " << id << " twice";
      }
    }
    std::printf(
        "%s: %zu relocalized frames, %zu of them with %zu map points not matched a second "
        "time\n",
        c.name, relocalized, frames_skipping, skipped);
    EXPECT_GT(relocalized, 0u) << c.name;
    would_duplicate += skipped;
  }
  // The clips exercise the case: the pose's projection search would match points again.
  EXPECT_GT(would_duplicate, 0u);
}

// projection_skips_icgm_rejected: the local map's projection search no longer matches again
// the map points whose match ICGM rejected on the frame. On the hand-held crowd clip fewer of
// the tracked inliers and of the new map points lie on walkers and the clip stays tracked;
// without ICGM the option does not act (the same poses). Measured: 143 of 359 rejected points
// matched again without the option, 0 with; walkers 13.2% vs 27.2% of the tracked inliers and
// 29.2% vs 43.1% of the new points; 58 vs 59 frames tracked. (Off by default: over whole runs
// the points it keeps out are mostly static, and fr1/xyz goes from 0.0189 to 0.0236 m.)
TEST(MonoOdometryTest, ProjectionSearchSkipsWhatIcgmRejected) {
  const Clip& clip = HandheldCrowdClip();
  MonoOptions on;
  on.vo.projection_skips_icgm_rejected = true;
  MonoOptions off;
  ASSERT_FALSE(off.vo.projection_skips_icgm_rejected);  // the default
  const ClipRun run_on = RunClip(clip, false, 0, 0, on);
  const ClipRun run_off = RunClip(clip, false, 0, 0, off);
  size_t rejected = 0, readmitted_on = 0, readmitted_off = 0;
  for (const auto& r : run_on.results) readmitted_on += r.icgm_rejected_readmitted_pixels.size();
  for (const auto& r : run_off.results) {
    rejected += r.icgm_rejected_points;
    readmitted_off += r.icgm_rejected_readmitted_pixels.size();
  }
  const WalkerPixels with = CountWalkerPixels(clip, run_on);
  const WalkerPixels without = CountWalkerPixels(clip, run_off);
  std::printf(
      "ICGM rejected %zu map points, %zu matched again without the option (%zu with); on "
      "walkers: tracked inliers %.1f%% vs %.1f%%, new map points %.1f%% vs %.1f%%; frames "
      "tracked %zu vs %zu\n",
      rejected, readmitted_off, readmitted_on, 100 * with.inliers.share(),
      100 * without.inliers.share(), 100 * with.new_points.share(),
      100 * without.new_points.share(), with.tracked, without.tracked);
  ASSERT_GT(readmitted_off, 20u) << "the projection search must bring back rejected points";
  EXPECT_EQ(readmitted_on, 0u);
  EXPECT_LT(with.inliers.share(), without.inliers.share());
  EXPECT_LT(with.new_points.share(), without.new_points.share());
  EXPECT_GE(with.tracked, 0.9 * without.tracked);

  MonoOptions plain_on = on, plain_off = off;
  plain_on.vo.use_icgm = plain_off.vo.use_icgm = false;
  ExpectSamePoses(RunClip(HandheldClip(), false, 0, 0, plain_on),
                  RunClip(HandheldClip(), false, 0, 0, plain_off));
}

// The ICGM-rejected map points of a run and how many of them lie on walkers (simulator masks;
// a clip without walkers has none).
WalkerShare IcgmRejectedOnWalkers(const Clip& clip, const ClipRun& run) {
  WalkerShare share;
  for (size_t i = 0; i < run.results.size(); ++i) {
    const cv::Mat& mask = clip.frames[i].dynamic_mask;
    for (const Eigen::Vector2d& px : run.results[i].icgm_rejected_pixels) {
      const int u = static_cast<int>(std::lround(px.x()));
      const int v = static_cast<int>(std::lround(px.y()));
      ++share.total;
      if (!mask.empty() && u >= 0 && v >= 0 && u < mask.cols && v < mask.rows) {
        share.on_walkers += mask.at<uint8_t>(v, u) != 0;
      }
    }
  }
  return share;
}

// What ICGM's motion prior rejects among the matches to map points (default options). In the
// hand-held crowd the rejected points lie on walkers more often than the tracked inliers do, but
// most of them are static. In a room without walkers every rejected point is static, and the
// projection search matches some of them again as inliers of the tracked pose. Measured:
// crowd 359 rejected, 43.5% on walkers against 27.2% of the tracked inliers; no walkers 48
// rejected, 22 matched again.
TEST(MonoOdometryTest, IcgmRejectedMapPointsAreMostlyStatic) {
  const ClipRun crowd = RunClip(HandheldCrowdClip(), false);
  const WalkerShare rejected = IcgmRejectedOnWalkers(HandheldCrowdClip(), crowd);
  const WalkerPixels tracked = CountWalkerPixels(HandheldCrowdClip(), crowd);
  const ClipRun room = RunClip(HandheldClip(), false);
  const WalkerShare room_rejected = IcgmRejectedOnWalkers(HandheldClip(), room);
  size_t readmitted = 0;
  for (const auto& r : room.results) readmitted += r.icgm_rejected_readmitted_pixels.size();
  std::printf(
      "crowd: %zu rejected map points, %.1f%% on walkers, against %.1f%% of the tracked "
      "inliers; no walkers: %zu rejected, %zu matched again\n",
      rejected.total, 100 * rejected.share(), 100 * tracked.inliers.share(), room_rejected.total,
      readmitted);
  ASSERT_GT(rejected.total, 50u);
  EXPECT_GT(rejected.share(), tracked.inliers.share());
  EXPECT_LT(rejected.share(), 0.5);
  EXPECT_EQ(room_rejected.on_walkers, 0u);
  EXPECT_GT(room_rejected.total, 20u);
  EXPECT_GT(readmitted, 0.25 * room_rejected.total);
}

// Persistent map points (pnp_verified_min_keyframes): a point seen in place by 3 keyframes
// over 0.5 s is verified. On the hand-held crowd clip the verified correspondences given to
// tracking's PnP lie on walkers far less often than all of them (walkers move within seconds,
// the room stays), and the run with the option tracks about as many frames. With wheels the
// option does not act (it follows moving_point_checks_with_wheels): the wheeled clip gives the
// default poses.
TEST(MonoOdometryTest, VerifiedMapPointsRarelyLieOnWalkers) {
  const Clip& clip = HandheldCrowdClip();
  MonoOptions on;
  on.vo.pnp_verified_min_keyframes = 3;
  on.vo.pnp_verified_min_span_s = 0.5;
  const ClipRun run = RunClip(clip, false, 0, 0, on);
  const ClipRun plain = RunClip(clip, false);
  WalkerShare verified, all;
  size_t taken = 0;
  for (size_t i = 0; i < run.results.size(); ++i) {
    const MonoFrameResult& r = run.results[i];
    const cv::Mat& mask = clip.frames[i].dynamic_mask;
    const auto on_walker = [&](const Eigen::Vector2d& px) {
      const int u = static_cast<int>(std::lround(px.x()));
      const int v = static_cast<int>(std::lround(px.y()));
      return u >= 0 && v >= 0 && u < mask.cols && v < mask.rows && mask.at<uint8_t>(v, u) != 0;
    };
    if (r.robust_verified.empty()) continue;
    for (const Eigen::Vector2d& px : r.robust_pixels) {
      ++all.total;
      all.on_walkers += on_walker(px);
    }
    for (const int k : r.robust_verified) {
      ++verified.total;
      verified.on_walkers += on_walker(r.robust_pixels[k]);
    }
    taken += r.pnp_on_verified;
  }
  const WalkerPixels with = CountWalkerPixels(clip, run);
  const WalkerPixels without = CountWalkerPixels(clip, plain);
  std::printf(
      "verified correspondences %zu, %.1f%% on walkers, against %.1f%% of all %zu; their pose "
      "taken in %zu frames; frames tracked %zu (default %zu)\n",
      verified.total, 100 * verified.share(), 100 * all.share(), all.total, taken, with.tracked,
      without.tracked);
  ASSERT_GT(verified.total, 200u) << "the clip must verify map points";
  ASSERT_GT(all.share(), 0.05) << "the clip must give walker correspondences";
  EXPECT_LT(verified.share(), 0.5 * all.share());
  EXPECT_GE(with.tracked, 0.8 * without.tracked);
  ExpectSamePoses(RunClip(WheeledClip(), true, 0, 0, on), RunClip(WheeledClip(), true));
}

TEST(MonoOdometryTest, BadImagesAreErrorsNotExceptions) {
  MonoOdometry vo{MonoOptions(), CameraIntrinsics()};
  EXPECT_FALSE(vo.ProcessFrame(Time::FromSeconds(1.0), cv::Mat()).status.ok());
  EXPECT_FALSE(
      vo.ProcessFrame(Time::FromSeconds(2.0), cv::Mat(480, 640, CV_32FC1, 0.5f)).status.ok());
  EXPECT_EQ(vo.state(), MonoState::kInitializing);
}

// Per map of a run (a re-initialization starts a new one), the map's own scale at each tracked
// frame from the rendered depth (MapScaleFromDepth); the largest ratio of the highest to the
// lowest over the maps with at least 10 such frames, and how many frames had one.
std::pair<double, size_t> LargestScaleSpread(const Clip& clip, const ClipRun& run) {
  std::vector<std::vector<double>> maps;
  size_t frames = 0;
  for (size_t i = 0; i < run.results.size() && i < clip.frames.size(); ++i) {
    const MonoFrameResult& r = run.results[i];
    if (r.initialized) maps.emplace_back();
    const std::optional<double> scale =
        MapScaleFromDepth(clip.frames[i].depth_m, r.tracked_pixels, r.tracked_depths);
    if (!scale || maps.empty()) continue;
    maps.back().push_back(*scale);
    ++frames;
  }
  double spread = 1.0;
  for (const std::vector<double>& m : maps) {
    if (m.size() < 10) continue;
    const auto [low, high] = std::minmax_element(m.begin(), m.end());
    spread = std::max(spread, *high / *low);
  }
  return {spread, frames};
}

// The hand-held camera among walkers, world seed 3 (config/sim/handheld_crowd_deep.yaml with
// --sim-seed 3), first 120 frames: the plain tracker's first map shrinks against the metres
// while walkers hide the room (its scale by depth grows about 140-fold), with the scene-depth
// hold the map keeps its scale within a few times the band.
TEST(MonoOdometryTest, SceneDepthHoldKeepsTheMapScale) {
  static const Clip clip = Render("handheld_crowd_deep.yaml", true, 120, 3);
  ASSERT_FALSE(clip.frames.front().depth_m.empty());
  MonoOptions off;
  ASSERT_EQ(off.vo.scene_depth_band, 0.0);  // the default
  MonoOptions on;
  on.vo.scene_depth_band = 2.0;
  const ClipRun run_off = RunClip(clip, false, 0, 0, off);
  const ClipRun run_on = RunClip(clip, false, 0, 0, on);
  const auto [spread_off, frames_off] = LargestScaleSpread(clip, run_off);
  const auto [spread_on, frames_on] = LargestScaleSpread(clip, run_on);
  size_t holds = 0;
  for (const MonoFrameResult& r : run_on.results) {
    holds += r.scene_depth_scale != 1.0;
    if (r.scene_depth_scale != 1.0) {
      EXPECT_TRUE(r.new_keyframe) << r.frame_index;
    }
  }
  for (const MonoFrameResult& r : run_off.results) EXPECT_EQ(r.scene_depth_scale, 1.0);
  std::printf(
      "map scale by depth, largest spread within a map: %.1fx without the hold (%zu frames), "
      "%.1fx with band 2 (%zu frames, %zu keyframes scaled)\n",
      spread_off, frames_off, spread_on, frames_on, holds);
  ASSERT_GT(frames_off, 60u);
  ASSERT_GT(frames_on, 60u);
  EXPECT_GT(spread_off, 20.0) << "the plain tracker's map must drift on this clip";
  EXPECT_GT(holds, 0u);
  // The band allows 2x either way about the map's first depth; the scene's own depth changes
  // add to it.
  EXPECT_LT(spread_on, 8.0);

  // With wheels the scale is metric: the hold does not act.
  ExpectSamePoses(RunClip(WheeledClip(), true, 0, 0, on), RunClip(WheeledClip(), true));
}

}  // namespace
}  // namespace icgm

namespace icgm {
namespace {

// rotation_only_parallax_deg: on the hand-held clip (no walkers) the frames whose matches to
// the newest keyframe a rotation explains at low parallax take that rotation at the keyframe's
// position. Their orientation relative to the keyframe must be the truth's, and no keyframe is
// made from them; the option is off by default and does not act with wheels.
TEST(MonoOdometryTest, LowParallaxFramesTakeTheRotationAtTheKeyframePosition) {
  const Clip& clip = HandheldClip();
  MonoOptions on;
  on.vo.rotation_only_parallax_deg = 0.2;
  const MonoOptions off;
  ASSERT_EQ(off.vo.rotation_only_parallax_deg, 0.0);  // the default
  const ClipRun with = RunClip(clip, false, 0, 0, on), without = RunClip(clip, false);
  size_t turned = 0, keyframes_with = 0, keyframes_without = 0;
  std::vector<double> errors_deg;
  const MonoFrameResult* keyframe = nullptr;
  std::optional<Eigen::Vector3d> held;
  for (size_t i = 0; i < with.results.size(); ++i) {
    const MonoFrameResult& r = with.results[i];
    keyframes_with += r.new_keyframe;
    keyframes_without += without.results[i].new_keyframe;
    EXPECT_FALSE(without.results[i].rotation_only);
    if (r.rotation_only) {
      ++turned;
      EXPECT_FALSE(r.new_keyframe);
      EXPECT_GT(r.parallax_deg, 0.0);
      EXPECT_LT(r.parallax_deg, 0.2);
      ASSERT_NE(keyframe, nullptr);
      // Held at the newest keyframe's position (as the bundle adjustment left it: every such
      // frame after one keyframe at one point), turned by the truth's rotation since it.
      if (!held) held = r.world_camera.translation();
      EXPECT_EQ(r.world_camera.translation(), *held);
      const Eigen::Matrix3d estimated =
          keyframe->world_camera.linear().transpose() * r.world_camera.linear();
      const Eigen::Matrix3d truth =
          clip.frames[keyframe->frame_index].T_world_camera.linear().transpose() *
          clip.frames[i].T_world_camera.linear();
      errors_deg.push_back(Eigen::AngleAxisd(estimated.transpose() * truth).angle() * 180.0 /
                           M_PI);
    }
    if (r.new_keyframe) {
      keyframe = &r;
      held.reset();
    }
  }
  ASSERT_FALSE(errors_deg.empty());
  std::sort(errors_deg.begin(), errors_deg.end());
  const double median_deg = errors_deg[errors_deg.size() / 2], worst_deg = errors_deg.back();
  MonoEvaluation e_with, e_without;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), with.estimate, 0.01, &e_with).ok());
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), without.estimate, 0.01, &e_without).ok());
  std::printf(
      "rotation only: %zu frames, rotation against the truth's since the keyframe median %.3f "
      "deg, worst %.3f deg; keyframes %zu (without %zu); Sim(3) ATE %.4f m (without %.4f m), "
      "%zu resets\n",
      turned, median_deg, worst_deg, keyframes_with, keyframes_without, e_with.evaluation.ate.rmse,
      e_without.evaluation.ate.rmse, with.resets);
  EXPECT_GT(turned, 10u);
  // The reference is the keyframe's pose as reported, before later bundle adjustments moved
  // it; the fitted rotation also takes up the hand's sideways motion since the keyframe (1 cm
  // at 3 m is 0.2 deg). Measured: median 0.37 deg, worst 0.58 deg over 62 frames.
  EXPECT_LT(median_deg, 0.5);
  EXPECT_LT(worst_deg, 1.0);
  EXPECT_LT(keyframes_with, keyframes_without);
  EXPECT_LT(e_with.evaluation.ate.rmse, 0.025);
  // With wheels (metric scale, translation measured) it never acts.
  ExpectSamePoses(RunClip(WheeledClip(), true, 0, 0, on), RunClip(WheeledClip(), true));
}

// A camera carried by a person walking through the crowd (config/sim/handheld_crowd_walk.yaml,
// the first 3 s: about 3 m, with the walkers): unlike a standing hand's millimetres, the walk's
// translation is observed. Over segments of 10-50 % of the path the error stays below what an
// estimate that stands still scores, and the whole run's Sim(3) ATE is a small share of the
// distance.
// The camera carried by a person walking through the crowd (config/sim/handheld_crowd_walk.yaml),
// its first kFrames frames (3 s), with the walkers.
const Clip& WalkClip() {
  static const Clip clip = Render("handheld_crowd_walk.yaml", true);
  return clip;
}

TEST(MonoOdometryTest, WalkingCameraTracksItsTranslationThroughTheCrowd) {
  const Clip& clip = WalkClip();
  const ClipRun run = RunClip(clip, false);
  MonoEvaluation eval;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), run.estimate, 0.01, &eval).ok());
  MonoSegmentErrors segments;
  ASSERT_TRUE(EvaluateMonoSegments(eval.evaluation, DefaultSegmentFractions(), &segments).ok());
  std::printf(
      "walking clip: %zu poses, %zu resets, Sim(3) ATE %.4f m over %.2f m (%.2f%%), segment "
      "error %.2f%% (standing still %.2f%%)\n",
      run.estimate.size(), run.resets, eval.evaluation.ate.rmse, eval.distance_m,
      eval.error_percent, segments.mean_percent, segments.standing_still_percent);
  EXPECT_GT(eval.distance_m, 2.5);
  EXPECT_GT(run.estimate.size(), 0.75 * kFrames);
  // The walk is nearly straight: standing still scores close to 100 %.
  EXPECT_GT(segments.standing_still_percent, 95.0);
  // Measured: 4.91 % of 2.94 m, segment error 81.9 % (the map's scale shrinks as the camera
  // walks towards the far wall; the short segments at the start and the end carry it). Without
  // ICGM on this clip: 15.00 % and 105.6 %, worse than standing still.
  EXPECT_LT(segments.mean_percent, 0.9 * segments.standing_still_percent);
  EXPECT_LT(eval.error_percent, 8.0);
}

// new_point_expected_parallax on the whole 10 m walk (world seed 1, with the walkers): gated on
// the measured angle, the new points whose noise enlarged their parallax come out too close and
// the map shrinks against the metres as the camera walks on (its scale by depth grows); gated on
// the angle at the tracked points' depth, the map keeps its scale. The largest spread of the
// scale by depth within a map, and the error, with ICGM. With wheels the option does not act.
TEST(MonoOdometryTest, ExpectedParallaxKeepsTheWalkingMapScale) {
  static const Clip clip = Render("handheld_crowd_walk.yaml", true, 300, 1);
  const MonoOptions off;
  ASSERT_FALSE(off.vo.new_point_expected_parallax);  // the default
  MonoOptions on;
  on.vo.new_point_expected_parallax = true;
  const ClipRun run_off = RunClip(clip, false, 0, 0, off);
  const ClipRun run_on = RunClip(clip, false, 0, 0, on);
  const auto [spread_off, frames_off] = LargestScaleSpread(clip, run_off);
  const auto [spread_on, frames_on] = LargestScaleSpread(clip, run_on);
  MonoEvaluation eval_off, eval_on;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), run_off.estimate, 0.01, &eval_off).ok());
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(clip), run_on.estimate, 0.01, &eval_on).ok());
  std::printf(
      "walking clip, map scale by depth, largest spread within a map: %.2fx gated on the measured "
      "angle (%zu frames, %zu resets, %.2f%% of distance), %.2fx on the expected one (%zu "
      "frames, %zu resets, %.2f%%)\n",
      spread_off, frames_off, run_off.resets, eval_off.error_percent, spread_on, frames_on,
      run_on.resets, eval_on.error_percent);
  ASSERT_GT(frames_off, 60u);
  ASSERT_GT(frames_on, 60u);
  // Measured: 17.41x, 0 resets, 14.29 % of 10.1 m against 1.18x, 2 resets, 2.31 %.
  EXPECT_GT(spread_off, 8.0) << "the map must shrink with the measured angle";
  EXPECT_LT(spread_on, 2.5);
  EXPECT_LT(eval_on.error_percent, 5.0);
  EXPECT_LT(eval_on.error_percent, 0.5 * eval_off.error_percent);

  // With wheels the scale is metric: the gate does not act.
  ExpectSamePoses(RunClip(WheeledClip(), true, 0, 0, on), RunClip(WheeledClip(), true));
}

}  // namespace
}  // namespace icgm
