#include "core/nav/obstacle_tracker.h"

#include <gtest/gtest.h>

#include <cmath>

namespace icgm {
namespace {

Time At(double s) { return Time::FromSeconds(20.0 + s); }

// The 5 cm cells of a body's half facing `viewer` (what a depth camera sees of it).
std::vector<Eigen::Vector2d> FrontArc(const Eigen::Vector2d& centre, double radius,
                                      const Eigen::Vector2d& viewer) {
  std::vector<Eigen::Vector2d> cells;
  const Eigen::Vector2d towards = (viewer - centre).normalized();
  for (double a = -M_PI / 2; a <= M_PI / 2; a += 0.1) {
    const double c = std::cos(a), s = std::sin(a);
    const Eigen::Vector2d dir(c * towards.x() - s * towards.y(), s * towards.x() + c * towards.y());
    const Eigen::Vector2d p = centre + radius * dir;
    cells.emplace_back((std::floor(p.x() / 0.05) + 0.5) * 0.05, (std::floor(p.y() / 0.05) + 0.5) * 0.05);
  }
  return cells;
}

TEST(ObstacleTrackerTest, WalkerGetsItsVelocityScenerySeemsStill) {
  ObstacleTracker tracker;
  const Eigen::Vector2d viewer(0, 0), velocity(-0.4, 1.0);
  for (int k = 0; k <= 10; ++k) {
    const double t = 0.1 * k;
    std::vector<Eigen::Vector2d> cells = FrontArc(Eigen::Vector2d(3.0, -1.5) + velocity * t, 0.25, viewer);
    const auto pillar = FrontArc(Eigen::Vector2d(2.0, 1.5), 0.2, viewer);
    cells.insert(cells.end(), pillar.begin(), pillar.end());
    for (double y = -2.0; y <= 2.0; y += 0.05) cells.emplace_back(5.025, y);  // a wall
    tracker.Update(At(t), cells);
  }
  const auto moving = tracker.MovingTracks();
  ASSERT_EQ(moving.size(), 1u);
  EXPECT_NEAR(moving[0].velocity_mps.x(), velocity.x(), 0.1);
  EXPECT_NEAR(moving[0].velocity_mps.y(), velocity.y(), 0.1);
  EXPECT_EQ(tracker.tracks().size(), 2u);  // walker and pillar; the wall is scenery
  // Now the body's centre is at (2.6, -0.5), 1 s later at (2.2, 0.5) (the arc's centroid lies
  // a little towards the viewer).
  EXPECT_LT((tracker.Predict(moving[0], 0.0) - Eigen::Vector2d(2.6, -0.5)).norm(), 0.25);
  EXPECT_LT((tracker.Predict(moving[0], 1.0) - Eigen::Vector2d(2.2, 0.5)).norm(), 0.25);
  EXPECT_LT(tracker.PredictedClearance(Eigen::Vector2d(2.2, 0.5), 1.0), 0.0);
  EXPECT_GT(tracker.PredictedClearance(Eigen::Vector2d(2.2, 0.5), 0.0), 0.5);
  // The pillar does not count as a walker.
  EXPECT_GT(tracker.PredictedClearance(Eigen::Vector2d(2.0, 1.5), 0.0), 1.0);
}

TEST(ObstacleTrackerTest, RobustVelocityKeepsAStandingWalkerStillDespiteAStrayClusterWhenAsked) {
  // A person stands 2 m ahead; for two frames of the last eight the seen cluster is another
  // body 0.4 m beside it (within the association gate), then the person again.
  const auto run = [](bool robust) {
    ObstacleTrackerOptions options;
    options.robust_velocity = robust;
    ObstacleTracker tracker(options);
    const Eigen::Vector2d viewer(0, 0), person(2.0, 0.0), stray(2.0, 0.4);
    for (int k = 0; k <= 12; ++k) {
      tracker.Update(At(0.1 * k), FrontArc(k == 9 || k == 10 ? stray : person, 0.25, viewer));
    }
    EXPECT_EQ(tracker.tracks().size(), 1u);
    return tracker.tracks().empty() ? 1e9 : tracker.tracks()[0].velocity_mps.norm();
  };
  const double least_squares = run(false), robust = run(true);
  EXPECT_GT(least_squares, 0.15) << "the stray frames set the least-squares slope moving";
  EXPECT_LT(robust, 0.05);
  // A walker walking steadily gets the same velocity either way (within 5 cm/s).
  for (const bool robust_on : {false, true}) {
    ObstacleTrackerOptions options;
    options.robust_velocity = robust_on;
    ObstacleTracker tracker(options);
    const Eigen::Vector2d velocity(-0.4, 1.0);
    for (int k = 0; k <= 10; ++k) {
      tracker.Update(At(0.1 * k), FrontArc(Eigen::Vector2d(3.0, -1.5) + velocity * 0.1 * k, 0.25,
                                           Eigen::Vector2d(0, 0)));
    }
    ASSERT_EQ(tracker.tracks().size(), 1u);
    EXPECT_LT((tracker.tracks()[0].velocity_mps - velocity).norm(), 0.1) << robust_on;
  }
}

TEST(ObstacleTrackerTest, AWalkerThatStopsIsAStandingWalkerAPillarIsNot) {
  ObstacleTracker tracker;
  const Eigen::Vector2d viewer(0, 0), velocity(0.0, 1.0);
  Eigen::Vector2d walker(2.0, -1.0);
  const Eigen::Vector2d pillar(2.0, 1.5);
  for (int k = 0; k <= 30; ++k) {
    if (k <= 10) walker = Eigen::Vector2d(2.0, -1.0) + velocity * 0.1 * k;
    std::vector<Eigen::Vector2d> cells = FrontArc(walker, 0.25, viewer);
    const auto still = FrontArc(pillar, 0.2, viewer);
    cells.insert(cells.end(), still.begin(), still.end());
    tracker.Update(At(0.1 * k), cells);
    if (k == 10) {
      ASSERT_EQ(tracker.MovingTracks().size(), 1u);
      EXPECT_TRUE(std::isinf(tracker.StandingWalkerClearance(walker, 0.0)));
    }
  }
  // Stood for 2 s: no longer moving, a standing walker where it stopped.
  EXPECT_TRUE(tracker.MovingTracks().empty());
  EXPECT_LT(tracker.StandingWalkerClearance(walker, 0.0), 0.0);
  // 1 m towards the camera from the body's centre the body's edge is 0.75 m away; the disc
  // (centred on the cells seen, which lie towards the camera) reaches at least as far.
  const double in_front = tracker.StandingWalkerClearance(walker + Eigen::Vector2d(-1.0, 0.0), 0.0);
  EXPECT_LE(in_front, 0.75);
  EXPECT_GT(in_front, 0.4);
  // The pillar never moved: at its centre the nearest standing walker is the one 1.5 m away.
  EXPECT_GT(tracker.StandingWalkerClearance(pillar, 0.0), 1.0);
}

TEST(ObstacleTrackerTest, UnseenTrackMovesOnThenIsDropped) {
  ObstacleTrackerOptions options;
  ObstacleTracker tracker(options);
  const Eigen::Vector2d velocity(1.0, 0.0);
  for (int k = 0; k <= 8; ++k) {
    tracker.Update(At(0.1 * k), FrontArc(Eigen::Vector2d(1.0, 2.0) + velocity * 0.1 * k, 0.25, {0, 0}));
  }
  ASSERT_EQ(tracker.MovingTracks().size(), 1u);
  tracker.Update(At(1.3), {});  // out of view for 0.5 s
  ASSERT_EQ(tracker.MovingTracks().size(), 1u);
  EXPECT_NEAR(tracker.Predict(tracker.MovingTracks()[0], 0.0).x(), 1.0 + 1.3, 0.15);
  tracker.Update(At(0.8 + options.track_timeout_s + 0.1), {});
  EXPECT_TRUE(tracker.tracks().empty());
}

// The camera at the origin looking along `yaw_rad` (+-31 deg, 5 m).
CameraView ViewAlong(double yaw_rad) {
  CameraView view;
  view.yaw_rad = yaw_rad;
  view.half_fov_rad = 31.0 * M_PI / 180.0;
  view.range_m = 5.0;
  return view;
}

TEST(ObstacleTrackerTest, CameraViewHoldsOnlyDiscsWhollyInside) {
  const CameraView view = ViewAlong(0.0);
  EXPECT_TRUE(view.Contains({2.0, 0.0}, 0.25));
  EXPECT_TRUE(view.Contains({2.0, 0.8}, 0.25));    // 22 deg off the axis, its edge at 29 deg
  EXPECT_FALSE(view.Contains({2.0, 1.0}, 0.25));   // centre at 27 deg, edge beyond 31
  EXPECT_FALSE(view.Contains({0.6, 0.9}, 0.25));   // beside the robot
  EXPECT_FALSE(view.Contains({-2.0, 0.0}, 0.25));  // behind
  EXPECT_FALSE(view.Contains({4.9, 0.0}, 0.25));   // partly beyond the range
  EXPECT_FALSE(view.Contains({0.1, 0.0}, 0.25));   // around the camera
}

TEST(ObstacleTrackerTest, WalkerThatLeftTheViewToTheSideIsRememberedWhenAsked) {
  // A walker crosses ahead of the camera from right to left at 0.8 m/s and leaves its view
  // (half field of view 31 deg) after 1 s; from then on nothing is seen (at 1.2 s with the
  // camera still ahead, then after `unseen_s` along `yaw_rad`).
  const auto run = [](double memory_s, double unseen_s, double yaw_rad = 0.0,
                      bool keeps_moving = false) {
    ObstacleTrackerOptions options;
    options.side_memory_s = memory_s;
    options.side_memory_keeps_moving = keeps_moving;
    ObstacleTracker tracker(options);
    for (int k = 0; k <= 10; ++k) {
      tracker.Update(At(0.1 * k), FrontArc(Eigen::Vector2d(1.2, -0.2 + 0.08 * k), 0.25, {0, 0}),
                     Eigen::Vector2d(0, 0), ViewAlong(0.0));
    }
    EXPECT_EQ(tracker.MovingTracks().size(), 1u);
    tracker.Update(At(1.2), {}, Eigen::Vector2d(0, 0), ViewAlong(0.0));
    tracker.Update(At(1.0 + unseen_s), {}, Eigen::Vector2d(0, 0), ViewAlong(yaw_rad));
    return tracker;
  };
  // Off: it moves on at its velocity (0.8 m/s, estimated a little slower from the seen arc:
  // more than 1.2 m in 2 s) and is dropped after 3 s.
  const ObstacleTracker off = run(0.0, 2.0);
  ASSERT_EQ(off.tracks().size(), 1u);
  EXPECT_FALSE(off.tracks()[0].remembered);
  EXPECT_GT(off.Predict(off.tracks()[0], 0.0).y() - off.tracks()[0].position_m.y(), 1.2);
  EXPECT_TRUE(run(0.0, 3.2).tracks().empty());
  // On (4 s, damped over 0.5 s, growing 0.1 m/s): it stays near where it left the view (at most
  // 0.8 * 0.5 m on), no longer a moving track, its disc 0.2 m wider after 2 s; kept past 3 s.
  const ObstacleTracker on = run(4.0, 2.0);
  ASSERT_EQ(on.tracks().size(), 1u);
  const TrackedObstacle& walker = on.tracks()[0];
  EXPECT_TRUE(walker.remembered);
  EXPECT_TRUE(on.MovingTracks().empty());
  EXPECT_TRUE(std::isinf(on.PredictedClearance(Eigen::Vector2d(1.2, 1.0), 0.0)));
  const Disc disc = on.RememberedDisc(walker, 0.0);
  EXPECT_NEAR(disc.centre_m.y(),
              walker.position_m.y() + walker.velocity_mps.y() * 0.5 * (1.0 - std::exp(-4.0)), 1e-9);
  EXPECT_LT(disc.centre_m.y() - walker.position_m.y(), 0.8 * 0.5);
  EXPECT_NEAR(disc.radius_m, walker.radius_m + 0.2, 1e-9);
  EXPECT_EQ(run(4.0, 3.5).tracks().size(), 1u);
  EXPECT_TRUE(run(4.0, 4.2).tracks().empty());
  // Keeping it moving: the other rules predict it at its full velocity, the damped disc
  // stays the remembered one's.
  ObstacleTracker moving = run(4.0, 2.0, 0.0, true);
  ASSERT_EQ(moving.MovingTracks().size(), 1u);
  EXPECT_TRUE(moving.tracks()[0].remembered);
  EXPECT_GT(moving.Predict(moving.tracks()[0], 0.0).y() - moving.tracks()[0].position_m.y(), 1.2);
  EXPECT_NEAR(moving.RememberedDisc(moving.tracks()[0], 0.0).centre_m.y(), disc.centre_m.y(), 1e-9);
  // The camera turned towards its place (45 deg) and sees nothing there: dropped.
  EXPECT_TRUE(run(4.0, 2.0, M_PI / 4).tracks().empty());
  // Without the view nothing is remembered.
  ObstacleTrackerOptions options;
  options.side_memory_s = 4.0;
  ObstacleTracker blind(options);
  blind.Update(At(0.0), FrontArc(Eigen::Vector2d(0.6, 0.9), 0.25, {0, 0}));
  blind.Update(At(0.1), {});
  ASSERT_EQ(blind.tracks().size(), 1u);
  EXPECT_FALSE(blind.tracks()[0].remembered);
}

TEST(ObstacleTrackerTest, UnseenStandingWalkerIsHeldInPlaceWhenAsked) {
  // A walker walks 1 s at 1 m/s, then creeps on at 0.1 m/s (standing, for the tracker) for
  // 1.5 s in view; then it is out of view. A second walker walks on at 1 m/s and leaves the
  // view at the same time.
  const auto run = [](double hold_s, double unseen_s, TrackedObstacle* creeper,
                      TrackedObstacle* walker, int* tracks) {
    ObstacleTrackerOptions options;
    options.standing_hold_s = hold_s;
    ObstacleTracker tracker(options);
    Eigen::Vector2d a(2.0, -1.0), b(1.0, 2.0);
    for (int k = 0; k <= 25; ++k) {
      a += Eigen::Vector2d(0.0, k <= 10 ? 1.0 : 0.1) * 0.1;
      b += Eigen::Vector2d(1.0, 0.0) * 0.1;
      std::vector<Eigen::Vector2d> cells = FrontArc(a, 0.25, {0, 0});
      const auto other = FrontArc(b, 0.25, {0, 0});
      cells.insert(cells.end(), other.begin(), other.end());
      tracker.Update(At(0.1 * k), cells);
    }
    EXPECT_EQ(tracker.MovingTracks().size(), 1u);
    tracker.Update(At(2.5 + unseen_s), {});
    *tracks = static_cast<int>(tracker.tracks().size());
    *creeper = TrackedObstacle();
    *walker = TrackedObstacle();
    for (const TrackedObstacle& t : tracker.tracks()) {
      const Eigen::Vector2d at = tracker.Predict(t, 0.0);
      if (t.moving) {
        *walker = t;
        walker->position_m = at;
      } else {
        *creeper = t;
        creeper->position_m = at;
        EXPECT_TRUE(tracker.Unseen(t));
        // Out of view, it counts among the unseen standing walkers.
        EXPECT_LT(tracker.StandingWalkerClearance(at, 0.0, true), 0.0);
      }
    }
    return tracker;
  };
  TrackedObstacle creeper, walker;
  int tracks = 0;
  // Off: 2 s out of view, the creeping walker has been moved on 0.2 m with its slow velocity;
  // after 3 s (track_timeout_s) both are gone.
  run(0.0, 2.0, &creeper, &walker, &tracks);
  ASSERT_EQ(tracks, 2);
  const double last_seen_y = creeper.position_m.y() - 2.0 * creeper.velocity_mps.y();
  EXPECT_GT(creeper.position_m.y() - last_seen_y, 0.15);
  EXPECT_FALSE(creeper.held);
  run(0.0, 3.2, &creeper, &walker, &tracks);
  EXPECT_EQ(tracks, 0);
  // Held for 6 s: after 5 s out of view it is still there, where it was last seen (no
  // extrapolation); the walker that moved still moved on and was dropped after 3 s.
  run(6.0, 2.0, &creeper, &walker, &tracks);
  ASSERT_EQ(tracks, 2);
  EXPECT_TRUE(creeper.held);
  EXPECT_EQ(creeper.velocity_mps.norm(), 0.0);
  const double held_y = creeper.position_m.y();
  EXPECT_GT(walker.position_m.x(), 1.0 + 2.6 + 1.5);
  run(6.0, 5.0, &creeper, &walker, &tracks);
  ASSERT_EQ(tracks, 1);
  EXPECT_TRUE(creeper.held);
  EXPECT_EQ(creeper.position_m.y(), held_y);
  run(6.0, 6.2, &creeper, &walker, &tracks);
  EXPECT_EQ(tracks, 0);
}

TEST(ObstacleTrackerTest, OnlyATrackSeenOftenEnoughIsHeld) {
  // A body creeps at 0.1 m/s in view for `frames` frames (0.1 s apart), then is out of view.
  // Returns the tracks left `unseen_s` after the last frame it was seen in.
  const auto run = [](int min_frames, int frames, double unseen_s) {
    ObstacleTrackerOptions options;
    options.standing_hold_s = 6.0;
    options.standing_hold_min_frames = min_frames;
    ObstacleTracker tracker(options);
    for (int k = 0; k < frames; ++k) {
      tracker.Update(At(0.1 * k),
                     FrontArc(Eigen::Vector2d(2.0, 0.5 + 0.01 * k), 0.25, Eigen::Vector2d(0, 0)));
    }
    EXPECT_EQ(tracker.tracks().size(), 1u);
    tracker.Update(At(0.1 * (frames - 1) + unseen_s), {});
    return tracker.tracks();
  };
  for (const int n : {3, 5}) {
    // Seen once, or one frame short: not held; gone once track_timeout_s (3 s) is over.
    for (const int frames : {1, n - 1}) {
      const auto soon = run(n, frames, 1.0);
      ASSERT_EQ(soon.size(), 1u) << n << " " << frames;
      EXPECT_FALSE(soon[0].held) << n << " " << frames;
      EXPECT_TRUE(run(n, frames, 3.2).empty()) << n << " " << frames;
    }
    // Seen n times: held where it was last seen, kept for standing_hold_s (6 s).
    const auto held = run(n, n, 5.0);
    ASSERT_EQ(held.size(), 1u) << n;
    EXPECT_TRUE(held[0].held) << n;
    EXPECT_EQ(held[0].velocity_mps.norm(), 0.0) << n;
    EXPECT_TRUE(run(n, n, 6.2).empty()) << n;
  }
  // 1 (the default): even a track seen in a single frame is held.
  const auto single = run(1, 1, 5.0);
  ASSERT_EQ(single.size(), 1u);
  EXPECT_TRUE(single[0].held);
}

TEST(ObstacleTrackerTest, SweptDiscsFollowTheMovingTracksOnly) {
  ObstacleTracker tracker;
  const Eigen::Vector2d velocity(0.0, 1.0);
  for (int k = 0; k <= 8; ++k) {
    std::vector<Eigen::Vector2d> cells =
        FrontArc(Eigen::Vector2d(2.0, -1.0) + velocity * 0.1 * k, 0.25, {0, 0});
    const auto pillar = FrontArc(Eigen::Vector2d(3.0, 1.5), 0.2, {0, 0});
    cells.insert(cells.end(), pillar.begin(), pillar.end());
    tracker.Update(At(0.1 * k), cells);
  }
  ASSERT_EQ(tracker.MovingTracks().size(), 1u);
  const TrackedObstacle walker = tracker.MovingTracks()[0];
  // 1.2 s every 0.5 s: t = 0, 0.5, 1.0 and the horizon's end 1.2.
  const std::vector<Disc> discs = tracker.SweptDiscs(1.2, 0.5);
  ASSERT_EQ(discs.size(), 4u);
  const double times[] = {0.0, 0.5, 1.0, 1.2};
  for (size_t i = 0; i < discs.size(); ++i) {
    EXPECT_LT((discs[i].centre_m - tracker.Predict(walker, times[i])).norm(), 1e-9);
    EXPECT_DOUBLE_EQ(discs[i].radius_m, walker.radius_m);
    EXPECT_GT((discs[i].centre_m - Eigen::Vector2d(3.0, 1.5)).norm(), 0.5);  // not the pillar
  }
  // The walker (now near (2, -0.2)) is predicted 1.2 m further along +y at the end.
  EXPECT_NEAR(discs.back().centre_m.y() - discs.front().centre_m.y(), 1.2, 0.15);
  EXPECT_TRUE(tracker.SweptDiscs(0.0, 0.5).size() == 1u);  // now only
}

TEST(ObstacleTrackerTest, BodyDiscLiesBehindTheSeenCellsWhenAsked) {
  // A torso of 0.19 m radius (the simulator's people: a 0.35 m body disc with the arms) seen
  // from the side while it stands 2 m away, after it walked: the seen half's centroid lies
  // about 0.12 m in front of the centre.
  const Eigen::Vector2d centre(1.0, 2.0), viewer(1.0, 0.0);
  ObstacleTrackerOptions options;
  options.body_offset_m = 0.1;
  ObstacleTracker with_bodies(options), without;
  for (int k = 0; k <= 20; ++k) {
    const Eigen::Vector2d walker = centre + Eigen::Vector2d(std::max(0.0, 1.0 - 0.1 * k), 0.0);
    const auto cells = FrontArc(walker, 0.19, viewer);
    with_bodies.Update(At(0.1 * k), cells, viewer);
    without.Update(At(0.1 * k), cells);
  }
  ASSERT_EQ(with_bodies.tracks().size(), 1u);
  const TrackedObstacle& track = with_bodies.tracks()[0];
  ASSERT_TRUE(ObstacleTracker::IsWalker(track));
  const Disc body = with_bodies.BodyDisc(track, 0.0);
  // Pushed away from the camera along its ray, to within 3 cm of the body's centre.
  EXPECT_NEAR((body.centre_m - track.position_m).norm(), 0.1, 1e-9);
  EXPECT_GT(body.centre_m.y(), track.position_m.y() + 0.099);
  EXPECT_LT((body.centre_m - centre).norm(), 0.03);
  EXPECT_GE(body.radius_m, 0.35);
  // Beside the body (its flank, 0.35 m from the centre) the body disc reaches it; the seen
  // cells' disc does not.
  const Eigen::Vector2d flank = centre + Eigen::Vector2d(0.35, 0.0);
  EXPECT_LT((flank - body.centre_m).norm() - body.radius_m, 0.03);
  const TrackedObstacle& seen = without.tracks()[0];
  EXPECT_GT((flank - seen.position_m).norm() - seen.radius_m, 0.08);
  // Without a viewpoint (or off) the body disc is centred on the seen cells.
  EXPECT_LT((without.BodyDisc(seen, 0.0).centre_m - seen.position_m).norm(), 1e-12);
}

TEST(ObstacleTrackerTest, LostWalkerFoundAgainKeepsItsIdentityWhenAsked) {
  // A walker crosses the view at 1 m/s for 1 s, is out of view for `unseen_s` (it walks on
  // 0.3 s and stops), then is seen again standing where it stopped. A pillar appears at the
  // same time 1.5 m beside the walker's way. Returns the tracks after `standing_frames` frames
  // of the walker standing in view.
  const auto run = [](double reidentify_s, double unseen_s, int* first_id, int* reidentified) {
    ObstacleTrackerOptions options;
    options.reidentify_s = reidentify_s;
    ObstacleTracker tracker(options);
    const Eigen::Vector2d start(2.0, -1.0), velocity(0.0, 1.0);
    for (int k = 0; k <= 10; ++k) {
      tracker.Update(At(0.1 * k), FrontArc(start + velocity * 0.1 * k, 0.25, {0, 0}));
    }
    EXPECT_EQ(tracker.MovingTracks().size(), 1u);
    *first_id = tracker.MovingTracks()[0].id;
    // Out of view: frames without the walker's cells.
    for (double t = 1.1; t < 1.0 + unseen_s - 1e-9; t += 0.1) tracker.Update(At(t), {});
    const Eigen::Vector2d stopped = start + velocity * 1.3;
    const Eigen::Vector2d pillar = stopped + Eigen::Vector2d(-1.5, 0.0);
    for (int k = 0; k < 10; ++k) {
      std::vector<Eigen::Vector2d> cells = FrontArc(stopped, 0.25, {0, 0});
      const auto still = FrontArc(pillar, 0.2, {0, 0});
      cells.insert(cells.end(), still.begin(), still.end());
      tracker.Update(At(1.0 + unseen_s + 0.1 * k), cells);
    }
    *reidentified = tracker.reidentified();
    return tracker.tracks();
  };
  const auto find_near = [](const std::vector<TrackedObstacle>& tracks, const Eigen::Vector2d& p) {
    for (const TrackedObstacle& t : tracks) {
      if ((t.position_m - p).norm() < 0.3) return t;
    }
    ADD_FAILURE() << "no track near " << p.transpose();
    return TrackedObstacle();
  };
  const Eigen::Vector2d stopped(2.0, 0.3), pillar(0.5, 0.3);
  int first_id = 0, reidentified = 0;
  for (const double unseen_s : {1.5, 4.0}) {
    // Off: 1.5 s out of view its prediction (1.5 m on) misses the standing walker, and after
    // 4 s the track is gone: a new track that never moved, not a walker.
    const auto off = run(0.0, unseen_s, &first_id, &reidentified);
    const TrackedObstacle fresh = find_near(off, stopped);
    EXPECT_NE(fresh.id, first_id) << unseen_s;
    EXPECT_FALSE(ObstacleTracker::IsWalker(fresh)) << unseen_s;
    EXPECT_EQ(reidentified, 0);
    // On (6 s): the standing body continues the walker's track, a walker still; the pillar,
    // 1.5 m off the walker's way, is a new track that is no walker.
    const auto on = run(6.0, unseen_s, &first_id, &reidentified);
    const TrackedObstacle found = find_near(on, stopped);
    EXPECT_EQ(found.id, first_id) << unseen_s;
    EXPECT_TRUE(ObstacleTracker::IsWalker(found)) << unseen_s;
    EXPECT_FALSE(found.moving) << unseen_s;
    EXPECT_LT(found.velocity_mps.norm(), 0.1) << unseen_s;
    EXPECT_EQ(reidentified, 1);
    const TrackedObstacle other = find_near(on, pillar);
    EXPECT_NE(other.id, first_id);
    EXPECT_FALSE(ObstacleTracker::IsWalker(other));
    // The coasting copy is gone: one track near the walker's way, none moving on beyond it.
    EXPECT_EQ(on.size(), 2u) << unseen_s;
  }
  // Remembered for less time than it was out of view: a new track again.
  const auto short_memory = run(3.5, 4.0, &first_id, &reidentified);
  EXPECT_FALSE(ObstacleTracker::IsWalker(find_near(short_memory, stopped)));
}

}  // namespace
}  // namespace icgm
