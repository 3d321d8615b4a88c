#include "core/nav/crowd_guard.h"

#include <gtest/gtest.h>

#include "unicycle.h"

namespace icgm {
namespace {

constexpr double kDt = 0.1;
constexpr double kRobotRadius = 0.3;
constexpr double kWalkerRadius = 0.25;
Time At(double s) { return Time::FromSeconds(10.0 + s); }

std::vector<Eigen::Vector2d> Disc(const Eigen::Vector2d& centre) {
  std::vector<Eigen::Vector2d> cells;
  for (double x = -kWalkerRadius; x <= kWalkerRadius; x += 0.05) {
    for (double y = -kWalkerRadius; y <= kWalkerRadius; y += 0.05) {
      if (std::hypot(x, y) <= kWalkerRadius) cells.push_back(centre + Eigen::Vector2d(x, y));
    }
  }
  return cells;
}

double Ramp(double from, double to, double step) { return from + std::clamp(to - from, -step, step); }

struct Outcome {
  double min_gap_m = 1e9;  // footprint to the walker's body
  bool intervened = false;
  bool filtered = false;  // the gap filter (options.gap_filter_m) changed a command
  bool evaded = false;    // the evasive rule (options.evasive_gap_m) changed a command
  bool braked = false;    // the stopping-distance rule (options.stopping_gap_m) changed one
  bool approached = false;  // the approach speed (options.approach_gap_m) slowed one
  // The walker's gap when a command was first slowed below the wanted speed (by any rule).
  double slowed_at_gap_m = -1.0;
  double largest_drop_mps = 0.0;  // the command's forward speed, frame to frame
  std::string actions;
  Pose2D pose;
};

// A robot that wants `wanted` meets a walker walking straight on (it does not yield); the guard
// sees the walker through the tracker (exact cells every frame). guard = false: no guard. The
// walker stands still from walker_stops_s on. With options.gap_filter_m the command (guarded or
// not) goes through the gap filter, the evasive rule and the stopping-distance rule last (each
// unchanged when off). personal_space_m >= 0: the walker does not step closer than this to the
// footprint (the simulator's non-yielding walkers).
Outcome Meet(const VelocityCommand& wanted, Eigen::Vector2d walker, const Eigen::Vector2d& v,
             bool guarded, double seconds, CrowdGuardOptions options = CrowdGuardOptions(),
             double walker_stops_s = 1e9, double personal_space_m = -1.0) {
  ObstacleGrid grid;  // scenery: none
  ObstacleTracker tracker;
  CrowdGuard guard(options);
  Pose2D pose{0, 0, 0};
  VelocityCommand base;  // what the base does (acceleration-limited)
  VelocityCommand sent;
  Outcome out;
  for (double t = 0.0; t < seconds; t += kDt) {
    grid.AddPoints(At(t), pose.position(), {});
    tracker.Update(At(t), Disc(walker));
    VelocityCommand cmd = wanted;
    if (guarded) {
      const GuardResult g = guard.Check(pose, sent, wanted, kRobotRadius, grid, tracker);
      cmd = g.command;
      if (g.intervened && out.actions.find(g.action) == std::string::npos) out.actions += g.action + ";";
      out.intervened |= g.intervened;
    }
    const VelocityCommand kept = guard.FilterGap(pose, cmd, kRobotRadius, tracker);
    out.filtered |= kept.linear_mps != cmd.linear_mps || kept.angular_radps != cmd.angular_radps;
    cmd = kept;
    const VelocityCommand slowed = guard.ApproachSpeed(pose, cmd, kRobotRadius, tracker);
    out.approached |= slowed.linear_mps != cmd.linear_mps;
    cmd = slowed;
    const VelocityCommand evaded = guard.Evade(pose, sent, cmd, kRobotRadius, grid, tracker);
    out.evaded |= evaded.linear_mps != cmd.linear_mps || evaded.angular_radps != cmd.angular_radps;
    cmd = evaded;
    const VelocityCommand braked = guard.BrakeToStopShort(pose, sent, cmd, kRobotRadius, tracker);
    out.braked |= braked.linear_mps != cmd.linear_mps;
    cmd = braked;
    const double gap = (walker - pose.position()).norm() - kWalkerRadius - kRobotRadius;
    if (out.slowed_at_gap_m < 0.0 && cmd.linear_mps < wanted.linear_mps - 1e-9) {
      out.slowed_at_gap_m = gap;
    }
    out.largest_drop_mps = std::max(out.largest_drop_mps, sent.linear_mps - cmd.linear_mps);
    sent = cmd;
    base.linear_mps = Ramp(base.linear_mps, cmd.linear_mps, 1.0 * kDt);
    base.angular_radps = Ramp(base.angular_radps, cmd.angular_radps, 3.0 * kDt);
    pose = test::Drive(pose, base, kDt);
    const Eigen::Vector2d step = walker + v * kDt;
    const bool keeps_space =
        personal_space_m < 0.0 ||
        (step - pose.position()).norm() - kWalkerRadius - kRobotRadius >= personal_space_m;
    if (t < walker_stops_s && keeps_space) walker = step;
    out.min_gap_m = std::min(out.min_gap_m, (walker - pose.position()).norm() - kWalkerRadius - kRobotRadius);
  }
  out.pose = pose;
  return out;
}

TEST(CrowdGuardTest, YieldsToAWalkerCrossingAhead) {
  const VelocityCommand ahead{0.5, 0.0};
  const Eigen::Vector2d start(1.2, -2.0), velocity(0.0, 1.1);
  const Outcome blind = Meet(ahead, start, velocity, false, 5.0);
  ASSERT_LT(blind.min_gap_m, 0.0) << "the scenario must be a collision without the guard";
  const Outcome guarded = Meet(ahead, start, velocity, true, 5.0);
  EXPECT_TRUE(guarded.intervened);
  EXPECT_GT(guarded.min_gap_m, 0.1) << guarded.actions;
  // It went on afterwards (yielded, did not give up).
  EXPECT_GT(guarded.pose.x_m, 1.0) << guarded.actions;
}

TEST(CrowdGuardTest, OwnMotionOnlyLetsAWalkerOvertakeButStillYieldsAhead) {
  // A walker overtakes the robot from behind, passing 0.25 m beside its footprint: the guard
  // (which sees it all round, as with a scanner) slows or swerves for it; with own_motion_only
  // it does not, since standing the robot would be passed as closely.
  const VelocityCommand ahead{0.4, 0.0};
  const Eigen::Vector2d behind(-2.5, 0.8), fast(1.3, 0.0);
  CrowdGuardOptions own;
  own.own_motion_only = true;
  const Outcome guarded = Meet(ahead, behind, fast, true, 5.0);
  EXPECT_TRUE(guarded.intervened);
  const Outcome overtaken = Meet(ahead, behind, fast, true, 5.0, own);
  EXPECT_FALSE(overtaken.intervened) << overtaken.actions;
  EXPECT_GT(overtaken.min_gap_m, 0.2);
  // A walker crossing ahead, into which the robot would drive: still yielded to.
  const Outcome crossing = Meet({0.5, 0.0}, {1.2, -2.0}, {0.0, 1.1}, true, 5.0, own);
  EXPECT_TRUE(crossing.intervened);
  EXPECT_GT(crossing.min_gap_m, 0.1) << crossing.actions;
  EXPECT_GT(crossing.pose.x_m, 1.0) << crossing.actions;
}

TEST(CrowdGuardTest, StandingRobotGetsOutOfAWalkersWay) {
  const VelocityCommand stand{0.0, 0.0};
  // The walker comes from the left, its path through the robot.
  const Eigen::Vector2d start(0.0, 3.0), velocity(0.0, -1.1);
  const Outcome blind = Meet(stand, start, velocity, false, 5.0);
  ASSERT_LT(blind.min_gap_m, -0.4);
  const Outcome guarded = Meet(stand, start, velocity, true, 5.0);
  EXPECT_TRUE(guarded.intervened);
  EXPECT_GT(guarded.min_gap_m, 0.0) << guarded.actions;
}

TEST(CrowdGuardTest, SlowsEarlyForAWalkerThatWillCrossCloseAhead) {
  // Without a guard the walker crosses 0.35 m ahead of the footprint: more than min_gap_m, less
  // than the caution gap.
  const VelocityCommand ahead{0.5, 0.0};
  const Eigen::Vector2d start(1.8, -2.0), velocity(0.0, 1.1);
  const Outcome blind = Meet(ahead, start, velocity, false, 5.0);
  ASSERT_GT(blind.min_gap_m, 0.32);
  ASSERT_LT(blind.min_gap_m, 0.40);
  CrowdGuardOptions cautious;
  cautious.min_gap_m = 0.3;
  cautious.caution_gap_m = 0.45;
  const Outcome guarded = Meet(ahead, start, velocity, true, 5.0, cautious);
  EXPECT_TRUE(guarded.intervened);
  EXPECT_GT(guarded.min_gap_m, blind.min_gap_m + 0.05) << guarded.actions;
  EXPECT_GT(guarded.pose.x_m, 1.0) << guarded.actions;  // and went on
  // Caution off: the guard lets the same command pass (it keeps min_gap_m).
  CrowdGuardOptions plain = cautious;
  plain.caution_gap_m = plain.min_gap_m;
  const Outcome passed = Meet(ahead, start, velocity, true, 5.0, plain);
  EXPECT_LT(passed.min_gap_m, guarded.min_gap_m - 0.05) << passed.actions;
}

TEST(CrowdGuardTest, KeepsTheGapFromAWalkerThatStoppedWhenAsked) {
  // The walker crosses ahead and stops in the robot's way, 1.6 m ahead of its centre.
  const VelocityCommand ahead{0.4, 0.0};
  const Eigen::Vector2d start(1.6, -1.5), velocity(0.0, 1.0);
  const Outcome blind = Meet(ahead, start, velocity, false, 6.0, CrowdGuardOptions(), 1.5);
  ASSERT_LT(blind.min_gap_m, 0.0) << "the scenario must be a collision without the guard";
  // Moving walkers only: once the walker stands the guard lets the robot drive into it (the
  // grid's safety stop is not part of this test).
  const Outcome moving_only = Meet(ahead, start, velocity, true, 6.0, CrowdGuardOptions(), 1.5);
  EXPECT_LT(moving_only.min_gap_m, 0.0) << moving_only.actions;
  CrowdGuardOptions standing;
  standing.standing_walkers = true;
  const Outcome guarded = Meet(ahead, start, velocity, true, 6.0, standing, 1.5);
  EXPECT_TRUE(guarded.intervened);
  EXPECT_GT(guarded.min_gap_m, 0.25) << guarded.actions;
  // A pillar (never moving) is the grid's business: the same robot passes beside one.
  const Outcome pillar =
      Meet(VelocityCommand{0.4, 0.0}, {1.6, 0.95}, {0.0, 0.0}, true, 3.0, standing);
  EXPECT_FALSE(pillar.intervened) << pillar.actions;
}

TEST(CrowdGuardTest, PassesWalkersThatDoNotCome) {
  // Walking away, and crossing well behind: the wanted command goes through unchanged.
  for (const auto& [start, velocity] : std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{
           {{2.0, 0.5}, {1.0, 0.0}}, {{-1.5, -2.0}, {0.0, 1.0}}}) {
    const Outcome o = Meet(VelocityCommand{0.5, 0.0}, start, velocity, true, 3.0);
    EXPECT_FALSE(o.intervened) << o.actions;
  }
}

// The rule scenarios below: the robot wants 0.4 m/s straight ahead and the guard's own tracking
// is off, so only the rule under test can slow it.
// The walker crosses and stops in the robot's way, 1.6 m ahead.
Outcome StoppedAhead(const CrowdGuardOptions& options) {
  return Meet(VelocityCommand{0.4, 0.0}, {1.6, -1.5}, {0.0, 1.0}, false, 8.0, options, 1.5);
}

// A walker walking on ahead of the robot at its speed.
Outcome WalkingOnAhead(const CrowdGuardOptions& options) {
  return Meet(VelocityCommand{0.4, 0.0}, {1.4, 0.0}, {0.4, 0.0}, false, 4.0, options);
}

// The walker comes from the side and stops beside the robot's line, 1.6 m ahead, with its
// centre `side_m` off the line.
Outcome StoppedBeside(double side_m, double seconds, const CrowdGuardOptions& options) {
  return Meet(VelocityCommand{0.4, 0.0}, {1.6, side_m}, {0.0, -1.0}, false, seconds, options,
              0.75);
}

CrowdGuardOptions GapFilter(double gap_m) {
  CrowdGuardOptions o;
  o.gap_filter_m = gap_m;
  return o;
}

TEST(CrowdGuardGapFilterTest, StopsShortOfAWalkerThatStoppedAhead) {
  const Outcome blind = StoppedAhead(CrowdGuardOptions());
  ASSERT_LT(blind.min_gap_m, 0.0) << "the scenario must be a collision without the filter";
  const Outcome kept = StoppedAhead(GapFilter(0.32));
  EXPECT_TRUE(kept.filtered);
  // The base lags the command (1 m/s^2): a few centimetres of the margin go.
  EXPECT_GT(kept.min_gap_m, 0.27);
  EXPECT_LT(kept.min_gap_m, 0.45) << "it comes close, then stops (does not stop far away)";
  // A walker walking on ahead of the robot at its speed is followed without a stop.
  const Outcome follow = WalkingOnAhead(GapFilter(0.32));
  EXPECT_FALSE(follow.filtered);
  EXPECT_GT(follow.pose.x_m, 1.2);
}

TEST(CrowdGuardGapFilterTest, PassesAWalkerStandingBesideUnlessThePassIsTooClose) {
  // Passing 0.40 m from its body: the command is never touched.
  const Outcome wide = StoppedBeside(1.75, 8.0, GapFilter(0.32));
  const Outcome wide_blind = StoppedBeside(1.75, 8.0, CrowdGuardOptions());
  EXPECT_FALSE(wide.filtered);
  EXPECT_NEAR(wide.pose.x_m, wide_blind.pose.x_m, 1e-9);
  // Passing 0.20 m from it: held at the margin rather than driven past.
  const Outcome near = StoppedBeside(1.55, 8.0, GapFilter(0.32));
  const Outcome near_blind = StoppedBeside(1.55, 8.0, CrowdGuardOptions());
  ASSERT_LT(near_blind.min_gap_m, 0.25);
  EXPECT_TRUE(near.filtered);
  EXPECT_GT(near.min_gap_m, 0.27);
}

CrowdGuardOptions Approach(double gap_m) {
  CrowdGuardOptions o;
  o.approach_gap_m = gap_m;
  return o;
}

TEST(CrowdGuardApproachTest, SlowsToAStopShortOfAWalkerThatStoppedAhead) {
  const Outcome blind = StoppedAhead(CrowdGuardOptions());
  ASSERT_LT(blind.min_gap_m, 0.0) << "the scenario must be a collision without the rule";
  const Outcome kept = StoppedAhead(Approach(0.32));
  EXPECT_TRUE(kept.approached);
  EXPECT_GT(kept.min_gap_m, 0.28);
  EXPECT_LT(kept.min_gap_m, 0.40) << "it comes close, then stops (does not stop far away)";
  // It slows within approach_near_m (0.6 m) only, and by at most the 1 m/s^2 the base brakes.
  EXPECT_LT(kept.slowed_at_gap_m, 0.6 + 1e-9);
  EXPECT_LT(kept.largest_drop_mps, 0.4 + 1e-9);
  // Off: unchanged.
  const Outcome off = StoppedAhead(CrowdGuardOptions());
  EXPECT_FALSE(off.approached);
  // A walker walking on ahead of the robot at its speed (0.85 m from the footprint) is followed
  // untouched.
  const Outcome follow = WalkingOnAhead(Approach(0.32));
  EXPECT_FALSE(follow.approached);
}

TEST(CrowdGuardApproachTest, PassesAWalkerStandingBesideUntouchedAndHoldsATooNarrowPass) {
  // Passing 0.40 m from its body: untouched (the gap falls under approach_near_m only where
  // the robot's motion hardly closes it).
  const Outcome wide = StoppedBeside(1.75, 10.0, Approach(0.32));
  const Outcome wide_blind = StoppedBeside(1.75, 10.0, CrowdGuardOptions());
  EXPECT_FALSE(wide.approached);
  EXPECT_NEAR(wide.pose.x_m, wide_blind.pose.x_m, 1e-9);
  EXPECT_GT(wide.pose.x_m, 2.6) << "past the walker";
  // Passing 0.20 m from it: held short of the gap.
  const Outcome near = StoppedBeside(1.55, 10.0, Approach(0.32));
  const Outcome near_blind = StoppedBeside(1.55, 10.0, CrowdGuardOptions());
  ASSERT_LT(near_blind.min_gap_m, 0.25);
  EXPECT_GT(near.min_gap_m, 0.28);
  EXPECT_LT(near.pose.x_m, 1.6) << "it stops before coming abreast";
}

CrowdGuardOptions Evasive(double gap_m, double reverse_mps) {
  CrowdGuardOptions o;
  o.evasive_gap_m = gap_m;
  o.evasive_reverse_mps = reverse_mps;
  return o;
}

TEST(CrowdGuardEvasiveTest, StopsShortOfAWalkerThatStoppedAhead) {
  const Outcome blind = StoppedAhead(CrowdGuardOptions());
  ASSERT_LT(blind.min_gap_m, 0.0) << "the scenario must be a collision without the rule";
  const Outcome kept = StoppedAhead(Evasive(0.3, 0.0));
  EXPECT_TRUE(kept.evaded);
  EXPECT_GT(kept.min_gap_m, 0.29);
  EXPECT_LT(kept.min_gap_m, 0.45) << "it comes close, then stops (does not stop far away)";
  // A walker walking on ahead of the robot at its speed is followed untouched.
  const Outcome follow = WalkingOnAhead(Evasive(0.3, 0.0));
  EXPECT_FALSE(follow.evaded);
  EXPECT_GT(follow.pose.x_m, 1.2);
}

TEST(CrowdGuardEvasiveTest, BacksOffFromAWalkerComingStraightOnWhenAllowed) {
  // The robot stands (it wants to); a walker walks straight at it and stops 0.1 m from the
  // footprint. The rule is told to expect no personal space (constant velocity).
  const VelocityCommand stand{0.0, 0.0};
  const Eigen::Vector2d start(2.5, 0.0), velocity(-1.0, 0.0);
  const double stops_s = (2.5 - kRobotRadius - kWalkerRadius - 0.1) / 1.0;
  CrowdGuardOptions forward = Evasive(0.3, 0.0), reverse = Evasive(0.3, 0.3);
  forward.walker_personal_space_m = reverse.walker_personal_space_m = 0.0;
  const Outcome standing = Meet(stand, start, velocity, false, 4.0, forward, stops_s);
  const Outcome backing = Meet(stand, start, velocity, false, 4.0, reverse, stops_s);
  // Forward-only, standing (or a sidestep) is the best the rule has: the walker comes to 0.1 m.
  EXPECT_LT(standing.min_gap_m, 0.15);
  // Backing off is allowed: it keeps more of the gap.
  EXPECT_TRUE(backing.evaded);
  EXPECT_GT(backing.min_gap_m, standing.min_gap_m + 0.05);
  EXPECT_LT(backing.pose.x_m, -0.05) << "it backed off";
}

TEST(CrowdGuardGapFilterTest, LetsCommandsThatWidenTheGapThrough) {
  // A walker that walked up and stands 0.2 m from the footprint on the robot's left.
  ObstacleTracker tracker;
  Eigen::Vector2d walker(0.0, 2.75);
  for (double t = 0.0; t < 3.0; t += kDt) {
    tracker.Update(At(t), Disc(walker));
    if (t < 2.0) walker += Eigen::Vector2d(0.0, -1.0) * kDt;
  }
  const CrowdGuard guard(GapFilter(0.32));
  const Pose2D away{0, 0, -0.3};  // heading 17 deg to the right, away from it
  const Pose2D pose{0, 0, 0.5};   // heading 29 deg to the left, towards it
  const auto same = [](const VelocityCommand& a, const VelocityCommand& b) {
    return a.linear_mps == b.linear_mps && a.angular_radps == b.angular_radps;
  };
  // Turning in place, and driving off to the right (or straight on, away): unchanged.
  EXPECT_TRUE(same(guard.FilterGap(pose, {0.0, 1.0}, kRobotRadius, tracker), {0.0, 1.0}));
  for (const VelocityCommand c :
       {VelocityCommand{0.3, 0.0}, VelocityCommand{0.3, -1.0}, VelocityCommand{0.3, 0.5}}) {
    EXPECT_TRUE(same(guard.FilterGap(away, c, kRobotRadius, tracker), c)) << c.angular_radps;
  }
  // Driving on towards it: the forward speed goes, the turn stays.
  const VelocityCommand towards{0.3, 0.5};
  const VelocityCommand filtered = guard.FilterGap(pose, towards, kRobotRadius, tracker);
  EXPECT_LT(filtered.linear_mps, 0.5 * towards.linear_mps);
  // Off (gap_filter_m = 0): nothing changes.
  EXPECT_TRUE(same(CrowdGuard().FilterGap(pose, towards, kRobotRadius, tracker), towards));
}

// A walker walks past the standing robot on its left, along its heading, and stops with its
// body 0.35 m from the footprint, 0.6 m ahead of the robot's centre (at 2.2 s); from
// `out_of_view_s` on the camera no longer sees it. From 3.2 s on the robot wants to drive on,
// turning left towards it.
Outcome BesideAndOutOfView(const CrowdGuardOptions& options, const ObstacleTrackerOptions& tracking,
                           double out_of_view_s) {
  ObstacleGrid grid;  // scenery: none (the grid's memory is not part of this test)
  ObstacleTracker tracker(tracking);
  const CrowdGuard guard(options);
  const double side_y = 0.35 + kWalkerRadius + kRobotRadius;
  Eigen::Vector2d walker(-1.6, side_y);
  Pose2D pose{0, 0, 0};
  VelocityCommand base, sent;
  Outcome out;
  const VelocityCommand wanted{0.3, 0.6};
  for (double t = 0.0; t < 8.0; t += kDt) {
    grid.AddPoints(At(t), pose.position(), {});
    tracker.Update(At(t), t < out_of_view_s ? Disc(walker) : std::vector<Eigen::Vector2d>());
    // Standing until the walker has stopped; then the robot drives.
    const VelocityCommand want = t < 3.2 ? VelocityCommand{0.0, 0.0} : wanted;
    const GuardResult g = guard.Check(pose, sent, want, kRobotRadius, grid, tracker);
    if (g.intervened && out.actions.find(g.action) == std::string::npos)
      out.actions += g.action + ";";
    out.intervened |= g.intervened;
    sent = g.command;
    base.linear_mps = Ramp(base.linear_mps, sent.linear_mps, 1.0 * kDt);
    base.angular_radps = Ramp(base.angular_radps, sent.angular_radps, 3.0 * kDt);
    pose = test::Drive(pose, base, kDt);
    walker.x() = std::min(0.6, walker.x() + 1.0 * kDt);
    out.min_gap_m =
        std::min(out.min_gap_m, (walker - pose.position()).norm() - kWalkerRadius - kRobotRadius);
  }
  out.pose = pose;
  return out;
}

TEST(CrowdGuardTest, KeepsTheGapFromAWalkerOutOfViewWhenAsked) {
  ObstacleTrackerOptions held;
  held.standing_hold_s = 6.0;
  // Off: the guard counts only moving walkers; the robot turns into the standing one.
  const Outcome off = BesideAndOutOfView(CrowdGuardOptions(), held, 3.2);
  ASSERT_LT(off.min_gap_m, 0.1) << "the scenario must be a close pass without the option";
  EXPECT_FALSE(off.intervened);
  CrowdGuardOptions unseen;
  unseen.unseen_walkers = true;
  // On: the walker out of view (held where it was last seen) keeps min_gap_m (or the gap the
  // robot already has: 0.35 m).
  const Outcome on = BesideAndOutOfView(unseen, held, 3.2);
  EXPECT_TRUE(on.intervened);
  EXPECT_GT(on.min_gap_m, 0.28) << on.actions;
  // A walker in view is left to the grid, as without the option.
  const Outcome seen = BesideAndOutOfView(unseen, held, 1e9);
  EXPECT_FALSE(seen.intervened) << seen.actions;
  EXPECT_NEAR(seen.min_gap_m, off.min_gap_m, 1e-9);
}

// A person stands beside a robot at the origin facing +x, on its left; the camera saw it for
// 0.5 s while looking at it, then the robot faced ahead (+-31 deg): from the frames `ahead` on
// (each a stamp and the cells seen) it is out of view, remembered.
ObstacleTracker RememberPerson(const ObstacleTrackerOptions& options, const Eigen::Vector2d& person,
                               const std::vector<std::pair<double, std::vector<Eigen::Vector2d>>>& ahead) {
  ObstacleTracker tracker(options);
  CameraView view;
  view.half_fov_rad = 31.0 * M_PI / 180.0;
  view.range_m = 5.0;
  view.yaw_rad = std::atan2(person.y(), person.x());
  for (int k = 0; k < 5; ++k) tracker.Update(At(0.1 * k), Disc(person), Eigen::Vector2d(0, 0), view);
  view.yaw_rad = 0.0;
  for (const auto& [t, cells] : ahead) tracker.Update(At(t), cells, Eigen::Vector2d(0, 0), view);
  return tracker;
}

// The smallest gap to the person over `seconds` of a command from standing at the origin.
double ClosestToPerson(const Eigen::Vector2d& person, const VelocityCommand& c, double seconds) {
  double gap = 1e9;
  VelocityCommand base;
  Pose2D p{0, 0, 0};
  for (int k = 0; k < std::lround(seconds / kDt); ++k) {
    base.linear_mps = Ramp(base.linear_mps, c.linear_mps, 1.0 * kDt);
    base.angular_radps = Ramp(base.angular_radps, c.angular_radps, 3.0 * kDt);
    p = test::Drive(p, base, kDt);
    gap = std::min(gap, (person - p.position()).norm() - kWalkerRadius - kRobotRadius);
  }
  return gap;
}

TEST(CrowdGuardTest, KeepsTheRobotsOwnMotionOffARememberedWalkerWhenAsked) {
  // The person 0.61 m from the footprint, 59 deg to the left.
  ObstacleTrackerOptions memory;
  memory.side_memory_s = 4.0;
  const Eigen::Vector2d person(0.6, 1.0);
  const ObstacleTracker tracker = RememberPerson(memory, person, {{0.5, {}}});
  ASSERT_EQ(tracker.tracks().size(), 1u);
  ASSERT_TRUE(tracker.tracks()[0].remembered);
  ObstacleGrid grid;  // scenery: none
  grid.AddPoints(At(0.5), Eigen::Vector2d(0, 0), {});
  const Pose2D pose{0, 0, 0};
  const VelocityCommand still{0.0, 0.0};
  const VelocityCommand left{0.5, 1.0}, ahead{0.4, 0.0}, right{0.4, -1.0};
  ASSERT_LT(ClosestToPerson(person, left, 1.5), 0.2) << "turning left must run the footprint at the person";
  // Off: nothing counts the person (it does not move); the turn goes through.
  const GuardResult off = CrowdGuard().Check(pose, still, left, kRobotRadius, grid, tracker);
  EXPECT_FALSE(off.intervened);
  // On: the turn towards the person is replaced by one that keeps 0.3 m over the rule's
  // horizon (1 s); straight on and turning away pass unchanged.
  CrowdGuardOptions options;
  options.remembered_gap_m = 0.3;
  const CrowdGuard guard(options);
  const GuardResult on = guard.Check(pose, still, left, kRobotRadius, grid, tracker);
  EXPECT_TRUE(on.intervened);
  EXPECT_GT(ClosestToPerson(person, on.command, 1.0), 0.29) << on.action;
  for (const VelocityCommand& c : {ahead, right}) {
    EXPECT_FALSE(guard.Check(pose, still, c, kRobotRadius, grid, tracker).intervened)
        << c.angular_radps;
  }
  // On the guard's alternatives only: the wanted turn goes through.
  options.remembered_alternatives_only = true;
  EXPECT_FALSE(CrowdGuard(options).Check(pose, still, left, kRobotRadius, grid, tracker).intervened);
  // Farther than remembered_near_m from the footprint: left alone.
  options.remembered_alternatives_only = false;
  options.remembered_near_m = 0.4;
  EXPECT_FALSE(CrowdGuard(options).Check(pose, still, left, kRobotRadius, grid, tracker).intervened);
}

TEST(CrowdGuardTest, DoesNotSwerveIntoARememberedWalkerWhenAsked) {
  // A person 0.53 m from the footprint, 56 deg to the left, is remembered while a walker comes
  // head on, 0.4 m right of the robot's line, at 1 m/s (seen for 0.5 s, moving); the robot
  // wants to drive on.
  ObstacleTrackerOptions memory;
  memory.side_memory_s = 4.0;
  std::vector<std::pair<double, std::vector<Eigen::Vector2d>>> ahead;
  for (int k = 5; k < 10; ++k) ahead.push_back({0.1 * k, Disc({1.9 - 0.1 * (k - 5), -0.4})});
  const Eigen::Vector2d person(0.6, 0.9);
  const ObstacleTracker tracker = RememberPerson(memory, person, ahead);
  ASSERT_EQ(tracker.MovingTracks().size(), 1u);
  ObstacleGrid grid;  // scenery: none
  grid.AddPoints(At(0.9), Eigen::Vector2d(0, 0), {});
  const Pose2D pose{0, 0, 0};
  const VelocityCommand still{0.0, 0.0}, wanted{0.5, 0.0};
  // Off: the guard swerves left, out of the walker's way and into the person.
  const GuardResult off = CrowdGuard().Check(pose, still, wanted, kRobotRadius, grid, tracker);
  ASSERT_TRUE(off.intervened);
  EXPECT_EQ(off.action, "swerve");
  EXPECT_GT(off.command.angular_radps, 0.0);
  EXPECT_LT(ClosestToPerson(person, off.command, 1.0), 0.3);
  // On the alternatives only: another way out, and the person keeps 0.3 m.
  CrowdGuardOptions options;
  options.remembered_gap_m = 0.3;
  options.remembered_alternatives_only = true;
  const GuardResult on = CrowdGuard(options).Check(pose, still, wanted, kRobotRadius, grid, tracker);
  EXPECT_TRUE(on.intervened);
  EXPECT_GT(ClosestToPerson(person, on.command, 1.0), 0.29) << on.action;
}

TEST(CrowdGuardTest, BlindSideSpeedNearAWalkerOutOfView) {
  // A walker walked up and stands 0.3 m from the footprint on the robot's left; then it is out
  // of view.
  ObstacleTracker tracker;
  Eigen::Vector2d walker(0.3, 2.85);
  for (double t = 0.0; t < 3.0; t += kDt) {
    tracker.Update(At(t), Disc(walker));
    if (walker.y() > 0.3 + kWalkerRadius + kRobotRadius) walker += Eigen::Vector2d(0.0, -1.0) * kDt;
  }
  CrowdGuardOptions options;
  options.blind_side_speed_mps = 0.2;
  options.blind_side_gap_m = 0.5;
  const CrowdGuard guard(options);
  const Pose2D pose{0, 0, 0};
  const VelocityCommand wanted{0.6, 0.3};
  // In view: unchanged.
  VelocityCommand c = guard.BlindSideSpeed(pose, wanted, kRobotRadius, tracker);
  EXPECT_EQ(c.linear_mps, wanted.linear_mps);
  tracker.Update(At(3.0), {});
  // Out of view and within 0.5 m: the same arc at 0.2 m/s; slower commands pass.
  c = guard.BlindSideSpeed(pose, wanted, kRobotRadius, tracker);
  EXPECT_DOUBLE_EQ(c.linear_mps, 0.2);
  EXPECT_DOUBLE_EQ(c.angular_radps / c.linear_mps, wanted.angular_radps / wanted.linear_mps);
  c = guard.BlindSideSpeed(pose, {0.1, 0.3}, kRobotRadius, tracker);
  EXPECT_EQ(c.linear_mps, 0.1);
  // 1 m farther on, the walker is more than 0.5 m from the footprint: unchanged.
  c = guard.BlindSideSpeed(Pose2D{1.2, 0, 0}, wanted, kRobotRadius, tracker);
  EXPECT_EQ(c.linear_mps, wanted.linear_mps);
  // Off: unchanged.
  c = CrowdGuard().BlindSideSpeed(pose, wanted, kRobotRadius, tracker);
  EXPECT_EQ(c.linear_mps, wanted.linear_mps);
}

CrowdGuardOptions Stopping(double gap_m) {
  CrowdGuardOptions o;
  o.stopping_gap_m = gap_m;
  return o;
}

TEST(CrowdGuardStoppingTest, BrakesInTimeForAWalkerComingHeadOn) {
  // A walker walks straight at the robot at 1 m/s and stops 0.3 m from its footprint (its
  // personal space, as the simulator's walkers that do not yield); the robot wants 0.5 m/s.
  const VelocityCommand ahead{0.5, 0.0};
  const Eigen::Vector2d start(5.0, 0.0), velocity(-1.0, 0.0);
  constexpr double kSpace = 0.3;
  const Outcome blind = Meet(ahead, start, velocity, false, 6.0, CrowdGuardOptions(), 1e9, kSpace);
  ASSERT_LT(blind.min_gap_m, 0.0);
  // The guard alone slows and swerves first (2.45 m off: its 1.5 s horizon), but once the
  // walker stands it no longer counts it and the robot drives on into its space: 0.21 m.
  const Outcome guarded = Meet(ahead, start, velocity, true, 6.0, CrowdGuardOptions(), 1e9, kSpace);
  ASSERT_LT(guarded.min_gap_m, 0.25) << "the scenario must be a close pass with the guard alone";
  // With the rule on top of the guard the robot stops short of it: 0.35 m.
  const Outcome braked = Meet(ahead, start, velocity, true, 6.0, Stopping(0.35), 1e9, kSpace);
  EXPECT_TRUE(braked.braked);
  EXPECT_GT(braked.min_gap_m, 0.33) << braked.actions;
  // The rule alone brakes proportionally (1.40 m off, at most 0.08 m/s less from one frame to
  // the next; the guard's alternatives 0.165 m/s) and keeps 0.32 m.
  const Outcome alone = Meet(ahead, start, velocity, false, 6.0, Stopping(0.35), 1e9, kSpace);
  EXPECT_TRUE(alone.braked);
  EXPECT_GT(alone.min_gap_m, 0.3);
  EXPECT_LT(alone.largest_drop_mps, 0.1);
  EXPECT_GT(alone.slowed_at_gap_m, 1.0) << "braking starts well before the walker's space";
}

TEST(CrowdGuardStoppingTest, StopsShortOfAWalkerThatStoppedAheadAndFollowsOneWalkingOn) {
  const Outcome blind = StoppedAhead(CrowdGuardOptions());
  ASSERT_LT(blind.min_gap_m, 0.0) << "the scenario must be a collision without the rule";
  const Outcome kept = StoppedAhead(Stopping(0.35));
  EXPECT_TRUE(kept.braked);
  EXPECT_GT(kept.min_gap_m, 0.3);  // 0.33 m
  EXPECT_LT(kept.min_gap_m, 0.45) << "it comes close, then stops (does not stop far away)";
  // A walker walking on ahead of the robot at its speed is followed untouched.
  const Outcome follow = WalkingOnAhead(Stopping(0.35));
  EXPECT_FALSE(follow.braked);
  EXPECT_GT(follow.pose.x_m, 1.2);
}

// Walker bodies. A person is drawn as the simulator's: a torso of kTorsoRadius of which the
// camera sees the front half, inside a body disc of kBodyRadius (the arms); the gap is measured
// from the footprint to that body disc. The person walks in from the left across the robot's
// way at 1 m/s and stops `lateral_m` beside the robot's straight line, 2 m ahead of its start
// (it moved, so the tracker knows it for a walker); the robot wants `wanted` straight on.
constexpr double kTorsoRadius = 0.19;
constexpr double kBodyRadius = 0.35;

std::vector<Eigen::Vector2d> SeenTorso(const Eigen::Vector2d& centre, const Eigen::Vector2d& eye) {
  std::vector<Eigen::Vector2d> cells;
  const Eigen::Vector2d towards = (eye - centre).normalized();
  for (double a = -M_PI; a < M_PI; a += 0.05 / kTorsoRadius) {
    const Eigen::Vector2d n(std::cos(a), std::sin(a));
    if (n.dot(towards) > 0.05) cells.push_back(centre + kTorsoRadius * n);
  }
  return cells;
}

struct BodyPass {
  double min_gap_m = 1e9;  // footprint to the body disc
  double end_x_m = 0.0;
  bool intervened = false;
};

BodyPass PassAPerson(const VelocityCommand& wanted, double lateral_m, double seconds,
                     const CrowdGuardOptions& options, const ObstacleTrackerOptions& bodies,
                     bool walks_in = true) {
  ObstacleGrid grid;  // scenery: none (the guard alone)
  ObstacleTracker tracker(bodies);
  CrowdGuard guard(options);
  const Eigen::Vector2d stop_at(2.0, lateral_m), velocity(0.0, -1.0);
  Eigen::Vector2d person = stop_at + Eigen::Vector2d(0.0, walks_in ? 1.5 : 0.0);
  Pose2D pose{0, 0, 0};
  VelocityCommand base, sent;
  BodyPass out;
  for (double t = 0.0; t < seconds; t += kDt) {
    grid.AddPoints(At(t), pose.position(), {});
    const Eigen::Vector2d eye = pose.position() + 0.1 * Eigen::Vector2d(std::cos(pose.yaw_rad),
                                                                        std::sin(pose.yaw_rad));
    tracker.Update(At(t), SeenTorso(person, eye), eye);
    const GuardResult g = guard.Check(pose, sent, wanted, kRobotRadius, grid, tracker);
    out.intervened |= g.intervened;
    sent = g.command;
    base.linear_mps = Ramp(base.linear_mps, sent.linear_mps, 1.0 * kDt);
    base.angular_radps = Ramp(base.angular_radps, sent.angular_radps, 3.0 * kDt);
    pose = test::Drive(pose, base, kDt);
    if (person.y() > stop_at.y()) person = (person + velocity * kDt).cwiseMax(stop_at);
    out.min_gap_m = std::min(out.min_gap_m,
                             (person - pose.position()).norm() - kBodyRadius - kRobotRadius);
  }
  out.end_x_m = pose.x_m;
  return out;
}

CrowdGuardOptions Bodies(double gap_m) {
  CrowdGuardOptions o;
  o.body_gap_m = gap_m;
  return o;
}

ObstacleTrackerOptions BodyBehind(double offset_m) {
  ObstacleTrackerOptions o;
  o.body_offset_m = offset_m;
  return o;
}

TEST(CrowdGuardBodyTest, PassesAPersonStandingBesideAtTheGapOrStops) {
  const VelocityCommand ahead{0.4, 0.0};
  // 0.85 m beside the line: passing straight leaves 0.20 m to the body. The guard counts only
  // moving walkers: once the person stands the robot drives past that close.
  const BodyPass plain = PassAPerson(ahead, 0.85, 12.0, CrowdGuardOptions(), BodyBehind(0.0));
  ASSERT_LT(plain.min_gap_m, 0.22) << "the scenario must be a close pass with the guard alone";
  // With the bodies (0.1 m behind the seen torso, 0.35 m wide) the robot keeps 0.3 m from the
  // body or stands.
  const BodyPass kept = PassAPerson(ahead, 0.85, 12.0, Bodies(0.3), BodyBehind(0.1));
  EXPECT_TRUE(kept.intervened);
  EXPECT_GT(kept.min_gap_m, 0.28);
  // 1.3 m beside the line (0.65 m to the body) the rule changes nothing once the person stands:
  // the robot drives on as far as without it.
  const BodyPass wide_plain = PassAPerson(ahead, 1.3, 10.0, CrowdGuardOptions(), BodyBehind(0.0));
  const BodyPass wide = PassAPerson(ahead, 1.3, 10.0, Bodies(0.3), BodyBehind(0.1));
  EXPECT_GT(wide.min_gap_m, 0.55);
  EXPECT_NEAR(wide.end_x_m, wide_plain.end_x_m, 0.15);
}

TEST(CrowdGuardBodyTest, CreepingRobotStopsShortOfAPersonInItsWay) {
  // A stand-off: the person stops on the robot's line, the controller creeps on at 0.1 m/s.
  const VelocityCommand creep{0.1, 0.0};
  const BodyPass plain = PassAPerson(creep, 0.0, 25.0, CrowdGuardOptions(), BodyBehind(0.0));
  ASSERT_LT(plain.min_gap_m, 0.0) << "the scenario must be a collision with the guard alone";
  const BodyPass kept = PassAPerson(creep, 0.0, 25.0, Bodies(0.3), BodyBehind(0.1));
  EXPECT_GT(kept.min_gap_m, 0.28);
  EXPECT_LT(kept.min_gap_m, 0.45) << "it comes close, then stops (does not stop far away)";
  // Creeping keeps the wider creep gap.
  CrowdGuardOptions creeping = Bodies(0.3);
  creeping.body_creep_speed_mps = 0.2;
  creeping.body_creep_gap_m = 0.45;
  const BodyPass wide = PassAPerson(creep, 0.0, 25.0, creeping, BodyBehind(0.1));
  EXPECT_GT(wide.min_gap_m, 0.42);
  // The creeping rule alone (body_gap_m 0): the same stop at 0.3 m, while a robot that drives
  // at 0.4 m/s past a person standing 1.3 m beside its line is not slowed by it.
  CrowdGuardOptions creep_only;
  creep_only.body_creep_speed_mps = 0.2;
  creep_only.body_creep_gap_m = 0.3;
  const BodyPass alone = PassAPerson(creep, 0.0, 25.0, creep_only, BodyBehind(0.1));
  EXPECT_GT(alone.min_gap_m, 0.28);
  EXPECT_LT(alone.min_gap_m, 0.45);
  const VelocityCommand ahead{0.4, 0.0};
  const BodyPass passing = PassAPerson(ahead, 1.3, 10.0, creep_only, BodyBehind(0.1));
  const BodyPass passing_plain = PassAPerson(ahead, 1.3, 10.0, CrowdGuardOptions(), BodyBehind(0.0));
  EXPECT_NEAR(passing.end_x_m, passing_plain.end_x_m, 0.15);
}

TEST(CrowdGuardBodyTest, APersonNeverSeenMovingCountsWithAllTracks) {
  // The person stands on the robot's line from the first frame on: to the tracker a still
  // object, not a walker, so the walkers' bodies leave the creeping robot to run into it; with
  // body_all_tracks every track is a body and the robot stops short.
  const VelocityCommand creep{0.1, 0.0};
  const BodyPass walkers = PassAPerson(creep, 0.0, 25.0, Bodies(0.3), BodyBehind(0.1), false);
  EXPECT_LT(walkers.min_gap_m, 0.0);
  CrowdGuardOptions all = Bodies(0.3);
  all.body_all_tracks = true;
  const BodyPass tracks = PassAPerson(creep, 0.0, 25.0, all, BodyBehind(0.1), false);
  EXPECT_GT(tracks.min_gap_m, 0.28);
  EXPECT_LT(tracks.min_gap_m, 0.45);
}

}  // namespace
}  // namespace icgm
