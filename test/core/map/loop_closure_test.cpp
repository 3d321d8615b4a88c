// Loop closure and the full map-building step on a synthetic route driven twice: the first
// traversal is exact, the second drifts; a synthetic registration returns the true relative
// pose between views of the same place (built from the ground truth kept by the test).
#include "core/map/loop_closure.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <set>
#include <vector>

#include "core/map/map_builder.h"
#include "core/map/se3_geodesic.h"
#include "synthetic_places.h"
#include "test_poses.h"

namespace icgm {
namespace {

using test::PoseDistance;

constexpr int kPlaces = 40;

// True pose of place k on a 10 m x 10 m square.
Pose3 PlacePose(int k) {
  const int side = (k / 10) % 4;
  const double s = (k % 10) * 1.0;
  const Vec3 corners[4] = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  const Vec3 dirs[4] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  return MakePose(corners[side] + s * dirs[side],
                  Quat(Eigen::AngleAxisd(side * M_PI / 2, Vec3::UnitZ())));
}

class RouteFixture : public ::testing::Test {
 protected:
  RouteFixture() : places_(kPlaces, 120, 21) {}

  // Keyframe viewing `place`, with relative pose `relative`; the stamp keys the ground truth.
  Keyframe View(int place, const Pose3& relative, const Pose3& truth) {
    Keyframe kf;
    kf.stamp = Time::FromNanoseconds(next_stamp_++);
    truth_[kf.stamp.nanoseconds()] = truth;
    kf.descriptors = places_.View(place, 0.85, 6);
    for (int i = 0; i < kf.descriptors.rows; ++i) {
      kf.keypoints.emplace_back(static_cast<float>(i), 0.f, 5.f);
      kf.points_m.emplace_back(0.0, 0.0, 1.0);
    }
    kf.relative_pose = relative;
    return kf;
  }

  // Registration: the true pose of the query in the candidate when both view the same place.
  RegisterFn TrueRegistration(int inliers = 60) {
    return [this, inliers](const Keyframe& query, const Keyframe& candidate) {
      RegistrationOutcome out;
      const Pose3& tq = truth_.at(query.stamp.nanoseconds());
      const Pose3& tc = truth_.at(candidate.stamp.nanoseconds());
      if (TranslationNorm(Between(tc, tq)) > 0.5) {
        out.status = Status::Error("registration rejected: 4 inliers < 20");
        return out;
      }
      out.status = Status::Ok();
      out.relative_pose = Between(tc, tq);
      out.inliers = inliers;
      out.information = 100.0 * Mat6::Identity();
      return out;
    };
  }

  // Drives the route: loop 0 exact, then loop 1 with a drifting odometry. Returns the mean
  // translation error of loop 1 and the error the drift alone would give.
  // `wheel_drift` (optional): each keyframe also gets the wheels' motion, the true step times
  // this drift.
  void DriveTwice(MapBuilder* builder, const RegisterFn& reg, double* error_after,
                  double* error_odometry_only, int* closures, const Vec6* wheel_drift = nullptr) {
    Vec6 drift;
    drift << 0.03, 0.02, 0.0, 0.0, 0.0, 0.01;
    KeyframeUpdate update;
    Pose3 previous_truth = Pose3::Identity();
    for (int k = 0; k < kPlaces; ++k) {
      const Pose3 t = PlacePose(k);
      const Pose3 wheel = Between(previous_truth, t) * (wheel_drift ? GeodesicExp(*wheel_drift)
                                                                     : Pose3::Identity());
      ASSERT_TRUE(builder->AddKeyframe(View(k, Between(previous_truth, t), t), reg, &update,
                                       nullptr, wheel_drift ? &wheel : nullptr));
      EXPECT_FALSE(update.loop_closed) << "false loop at first visit of place " << k;
      previous_truth = t;
    }
    builder->StartLoop();
    Pose3 odometry_only = builder->map().keyframe(kPlaces - 1).global_pose;
    *error_after = *error_odometry_only = 0.0;
    *closures = 0;
    for (int k = 0; k < kPlaces; ++k) {
      const Pose3 t = PlacePose(k);
      const Pose3 measured = Between(previous_truth, t) * GeodesicExp(drift);
      odometry_only = odometry_only * measured;
      const Pose3 wheel = Between(previous_truth, t) * (wheel_drift ? GeodesicExp(*wheel_drift)
                                                                     : Pose3::Identity());
      ASSERT_TRUE(builder->AddKeyframe(View(k, measured, t), reg, &update, nullptr,
                                       wheel_drift ? &wheel : nullptr));
      *closures += update.loop_closed ? 1 : 0;
      *error_after += (update.pose.translation() - t.translation()).norm() / kPlaces;
      *error_odometry_only += (odometry_only.translation() - t.translation()).norm() / kPlaces;
      previous_truth = t;
    }
  }

  // `passes` passes over places 0..9 added to `map` (ids 0-9, 10-19, ...), the true poses as
  // global poses.
  void MapPlacesInOrder(HybridMap* map, int passes = 1) {
    int id = -1;
    Pose3 previous = Pose3::Identity();
    for (int pass = 0; pass < passes; ++pass) {
      for (int k = 0; k < 10; ++k) {
        ASSERT_TRUE(map->AddKeyframe(View(k, Between(previous, PlacePose(k)), PlacePose(k)),
                                     Mat6::Identity(), &id));
        previous = PlacePose(k);
      }
    }
  }

  test::SyntheticPlaces places_;
  std::map<int64_t, Pose3> truth_;
  int64_t next_stamp_ = 1;
};

TEST_F(RouteFixture, MappingClosesLoopsAndReducesDrift) {
  MapBuilder builder(MapBuilderOptions{});
  double after = 0.0;
  double odometry = 0.0;
  int closures = 0;
  DriveTwice(&builder, TrueRegistration(), &after, &odometry, &closures);
  EXPECT_GT(closures, kPlaces * 3 / 4);
  EXPECT_GT(odometry, 0.5);
  EXPECT_LT(after, odometry / 3.0);
  // Loop links point from the first traversal to the second.
  int loop_links = 0;
  for (const auto& l : builder.map().links()) {
    if (l.type != LinkType::kLoopClosure) continue;
    ++loop_links;
    EXPECT_LT(l.from_id, kPlaces);
    EXPECT_GE(l.to_id, kPlaces);
    EXPECT_EQ(l.from_id + kPlaces, l.to_id);
  }
  EXPECT_EQ(loop_links, closures);
}

TEST_F(RouteFixture, WheelLinksBesideVisualStepsSteadyThePoseGraph) {
  MapBuilderOptions options;
  options.loop_closure.correction = LoopCorrection::kPoseGraph;
  // The wheels: 1% short and 0.5 mrad of heading bias per 1 m step (vision: 10 mrad).
  Vec6 wheel_drift;
  wheel_drift << -0.01, 0.0, 0.0, 0.0, 0.0, 0.0005;
  double with_wheels = 0.0, without_wheels = 0.0, odometry = 0.0;
  int closures_with = 0, closures_without = 0;
  MapBuilder builder(options);
  DriveTwice(&builder, TrueRegistration(), &with_wheels, &odometry, &closures_with, &wheel_drift);
  options.map.wheel_links = false;
  MapBuilder plain(options);
  DriveTwice(&plain, TrueRegistration(), &without_wheels, &odometry, &closures_without,
             &wheel_drift);
  ASSERT_GT(closures_with, kPlaces / 2);
  ASSERT_GT(closures_without, kPlaces / 2);
  std::printf("mean error of the second traversal: %.3f m with wheel links, %.3f m without "
              "(odometry alone %.3f m)\n", with_wheels, without_wheels, odometry);
  // Measured: 0.096 m with, 0.136 m without.
  EXPECT_LT(with_wheels, 0.85 * without_wheels);

  // One wheel link beside every odometry link (every step here is visual), from the previous
  // keyframe, with the given motion and an information that weakens with the step length.
  int wheel_links = 0;
  for (const Link& l : builder.map().links()) {
    if (l.type != LinkType::kWheelOdometry) continue;
    ++wheel_links;
    EXPECT_EQ(builder.map().keyframe(l.to_id).previous_id, l.from_id);
    EXPECT_EQ(l.information, builder.WheelLinkInformation(l.relative_pose));
  }
  EXPECT_EQ(wheel_links, 2 * kPlaces - 1);
  for (const Link& l : plain.map().links()) EXPECT_NE(l.type, LinkType::kWheelOdometry);
  const Pose3 short_step = MakePose(Vec3(0.1, 0, 0), Quat::Identity());
  const Pose3 long_step = MakePose(Vec3(1.0, 0, 0), Quat::Identity());
  EXPECT_GT(builder.WheelLinkInformation(short_step)(0, 0),
            2.0 * builder.WheelLinkInformation(long_step)(0, 0));
  EXPECT_GT(builder.WheelLinkInformation(short_step)(5, 5),
            2.0 * builder.WheelLinkInformation(long_step)(5, 5));
}

TEST_F(RouteFixture, NoWheelLinkBesideAStepTheWheelsPlaced) {
  MapBuilder builder(MapBuilderOptions{});
  KeyframeUpdate update;
  const Pose3 step = MakePose(Vec3(1.0, 0, 0), Quat::Identity());
  ASSERT_TRUE(builder.AddKeyframe(View(0, Pose3::Identity(), Pose3::Identity()), RegisterFn(),
                                  &update, nullptr, &step));
  Keyframe by_wheels = View(1, step, step);
  by_wheels.relative_source = RelativePoseSource::kWheelOdometry;
  ASSERT_TRUE(builder.AddKeyframe(by_wheels, RegisterFn(), &update, nullptr, &step));
  ASSERT_TRUE(builder.AddKeyframe(View(2, step, step * step), RegisterFn(), &update, nullptr,
                                  &step));
  std::vector<LinkType> types;
  for (const Link& l : builder.map().links()) types.push_back(l.type);
  // The session's first keyframe has no previous one; the wheel step is its own odometry link.
  EXPECT_EQ(types, (std::vector<LinkType>{LinkType::kOdometry, LinkType::kOdometry,
                                          LinkType::kWheelOdometry}));
}

TEST_F(RouteFixture, LocalizationReachesFullConsensus) {
  MapBuilder builder(MapBuilderOptions{});
  builder.SetMode(MapMode::kLocalization);
  double after = 0.0;
  double odometry = 0.0;
  int closures = 0;
  DriveTwice(&builder, TrueRegistration(), &after, &odometry, &closures);
  ASSERT_GT(closures, 0);
  // alpha = 1 and exact betas from an exact first loop: corrected poses are the truth.
  for (int id = kPlaces; id < builder.map().size(); ++id) {
    const Keyframe& kf = builder.map().keyframe(id);
    if (builder.map().sessions()[0].last_corrected_id == id) {
      EXPECT_LT(PoseDistance(kf.global_pose, PlacePose(id - kPlaces)), 1e-6);
    }
  }
  EXPECT_LT(after, odometry / 5.0);
}

TEST_F(RouteFixture, PoseGraphCorrectionClosesLoopsAndReducesDrift) {
  MapBuilderOptions options;
  options.loop_closure.correction = LoopCorrection::kPoseGraph;
  MapBuilder builder(options);
  double after = 0.0;
  double odometry = 0.0;
  int closures = 0;
  DriveTwice(&builder, TrueRegistration(), &after, &odometry, &closures);
  EXPECT_GT(closures, kPlaces * 3 / 4);
  EXPECT_LT(after, odometry / 3.0);
}

TEST_F(RouteFixture, PoseGraphWhileLocalizingKeepsEarlierLoopsFixed) {
  MapBuilderOptions options;
  options.loop_closure.correction = LoopCorrection::kPoseGraph;
  MapBuilder builder(options);
  builder.SetMode(MapMode::kLocalization);
  double after = 0.0;
  double odometry = 0.0;
  int closures = 0;
  DriveTwice(&builder, TrueRegistration(), &after, &odometry, &closures);
  ASSERT_GT(closures, 0);
  for (int id = 0; id < kPlaces; ++id) {
    EXPECT_LT(PoseDistance(builder.map().keyframe(id).global_pose, PlacePose(id)), 1e-9);
  }
  EXPECT_LT(after, odometry / 3.0);
}

TEST_F(RouteFixture, ReloadedMapRebuildsTheSameDictionary) {
  MapBuilder builder(MapBuilderOptions{});
  double after = 0.0;
  double odometry = 0.0;
  int closures = 0;
  DriveTwice(&builder, TrueRegistration(), &after, &odometry, &closures);
  for (const auto& kf : builder.map().keyframes()) {
    ASSERT_EQ(kf.word_ids.size(), kf.keypoints.size());
  }
  // Reset from a copy with recorded words (replay) and from one without (search): both give
  // the original dictionary, and the searched one records the words again.
  HybridMap without_words = builder.map();
  for (int id = 0; id < without_words.size(); ++id) without_words.SetWordIds(id, {});
  MapBuilder replayed(MapBuilderOptions{});
  MapBuilder searched(MapBuilderOptions{});
  ASSERT_TRUE(replayed.Reset(builder.map()));
  ASSERT_TRUE(searched.Reset(without_words));
  EXPECT_EQ(replayed.dictionary().num_words(), builder.dictionary().num_words());
  EXPECT_EQ(searched.dictionary().num_words(), builder.dictionary().num_words());
  EXPECT_EQ(searched.map().keyframe(7).word_ids, builder.map().keyframe(7).word_ids);
  const cv::Mat query = places_.View(5, 0.8, 6);
  std::vector<DictionaryMatch> a;
  std::vector<DictionaryMatch> b;
  ASSERT_TRUE(builder.dictionary().Query(query, &a));
  ASSERT_TRUE(replayed.dictionary().Query(query, &b));
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.front().keyframe_id, b.front().keyframe_id);
  EXPECT_EQ(a.front().score, b.front().score);
}

TEST_F(RouteFixture, TooFewInliersMeansNoLoopClosure) {
  MapBuilder builder(MapBuilderOptions{});
  double after = 0.0;
  double odometry = 0.0;
  int closures = 0;
  DriveTwice(&builder, TrueRegistration(/*inliers=*/5), &after, &odometry, &closures);
  EXPECT_EQ(closures, 0);
  EXPECT_NEAR(after, odometry, 1e-6);
}

TEST_F(RouteFixture, FalseLoopFarFromTheOwnPoseIsRejected) {
  LoopClosureOptions options;
  options.exclude_recent_keyframes = 0;
  // The own-loop uncertainty gate alone: the bound on a loop link's motion (which would also
  // refuse this 30 m link) is lifted.
  options.max_link_translation_m = 1e9;
  options.max_link_rad = 4.0;
  HybridMap map;
  int id = -1;
  for (int k = 0; k < 3; ++k) {
    Keyframe kf =
        View(k, k == 0 ? PlacePose(0) : Between(PlacePose(k - 1), PlacePose(k)), PlacePose(k));
    ASSERT_TRUE(map.AddKeyframe(kf, Mat6::Identity(), &id));
  }
  Keyframe query = View(1, Pose3::Identity(), PlacePose(1));
  query.global_pose = PlacePose(2);  // own-loop estimate: near place 2
  const RegisterFn wrong = [](const Keyframe&, const Keyframe&) {
    RegistrationOutcome out;
    out.status = Status::Ok();
    out.relative_pose = MakePose(Vec3(30.0, 0, 0), Quat::Identity());  // 30 m away
    out.inliers = 80;
    return out;
  };
  const LoopClosureDetector detector(options);
  const LoopClosureResult r = detector.Detect(query, {{1, 0.9}}, map, wrong, 1.0);
  EXPECT_FALSE(r.status.ok());
  EXPECT_NE(r.status.reason().find("uncertainty"), std::string::npos) << r.status.reason();
  ASSERT_EQ(r.evidence.size(), 1u);
  EXPECT_NE(r.evidence[0].rejected.find("jump"), std::string::npos);
  // The same registration is accepted when it is consistent with the own-loop pose.
  const RegisterFn right = [](const Keyframe&, const Keyframe&) {
    RegistrationOutcome out;
    out.status = Status::Ok();
    out.relative_pose = Pose3::Identity();
    out.inliers = 80;
    return out;
  };
  const LoopClosureResult ok = detector.Detect(query, {{1, 0.9}}, map, right, 1.0);
  ASSERT_TRUE(ok.status.ok()) << ok.status.reason();
  EXPECT_LT(PoseDistance(ok.loop_closure_pose, PlacePose(1)), 1e-9);
  EXPECT_LT(PoseDistance(ok.delta_pose_diff, Between(PlacePose(2), PlacePose(1))), 1e-9);
}

TEST_F(RouteFixture, ProximityCandidatesLinkEachEarlierPassTheDictionaryMissed) {
  // Two passes over places 0..9 (ids 0-9 and 10-19), the true poses as global poses.
  HybridMap map;
  ASSERT_NO_FATAL_FAILURE(MapPlacesInOrder(&map, 2));
  ASSERT_LT(PoseDistance(map.keyframe(14).global_pose, PlacePose(4)), 1e-9);
  // The query sees place 4 from 0.1 m further on; its estimate is 0.05 m off.
  const Pose3 truth = Compose(PlacePose(4), MakePose(Vec3(0.1, 0, 0), Quat::Identity()));
  Keyframe query = View(4, Pose3::Identity(), truth);
  query.global_pose = Compose(truth, MakePose(Vec3(0, 0.05, 0), Quat::Identity()));

  LoopClosureOptions options;
  options.exclude_recent_keyframes = 0;
  options.proximity_candidates = 3;
  options.proximity_separation = 5;
  // Off (the thesis): no dictionary candidate, no loop closure.
  options.proximity_candidates = 0;
  const LoopClosureResult off = LoopClosureDetector(options).Detect(
      query, {}, map, TrueRegistration(), 0.0);
  EXPECT_FALSE(off.status.ok());
  EXPECT_EQ(off.registrations, 0);

  options.proximity_candidates = 3;
  const LoopClosureResult r =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(), 0.0);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  // Places 3 and 5 are 0.9 m and 1.1 m away: only the two views of place 4 are tried.
  EXPECT_EQ(r.registrations, 2);
  ASSERT_EQ(r.evidence.size(), 2u);
  std::set<int> linked;
  for (const LoopEvidence& e : r.evidence) {
    EXPECT_TRUE(e.proximity);
    EXPECT_TRUE(e.rejected.empty()) << e.rejected;
    EXPECT_LT(PoseDistance(e.global_pose, truth), 1e-9);
    linked.insert(e.candidate_id);
  }
  EXPECT_EQ(linked, (std::set<int>{4, 14}));
  EXPECT_LT(PoseDistance(r.loop_closure_pose, truth), 1e-9);

  // Ids 4 and 14 closer than proximity_separation count as one pass: one link.
  options.proximity_separation = 20;
  const LoopClosureResult one =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(), 0.0);
  ASSERT_TRUE(one.status.ok()) << one.status.reason();
  EXPECT_EQ(one.evidence.size(), 1u);
  EXPECT_EQ(one.registrations, 1);

  // A dictionary candidate of place 4 that registers covers its pass: only the other is tried.
  options.proximity_separation = 5;
  const LoopClosureResult both =
      LoopClosureDetector(options).Detect(query, {{14, 0.9}}, map, TrueRegistration(), 0.0);
  ASSERT_TRUE(both.status.ok()) << both.status.reason();
  ASSERT_EQ(both.evidence.size(), 2u);
  EXPECT_FALSE(both.evidence[0].proximity);
  EXPECT_EQ(both.evidence[0].candidate_id, 14);
  EXPECT_TRUE(both.evidence[1].proximity);
  EXPECT_EQ(both.evidence[1].candidate_id, 4);
  EXPECT_EQ(both.registrations, 2);
}

TEST_F(RouteFixture, StartCandidatesLinkTheSessionsFirstModelsTheDictionaryMissed) {
  // One pass over places 0..9 (ids 0-9), then the query comes back to place 1 with its
  // estimate 0.3 m off (the drift since the start): too far for a 0.2 m proximity search.
  HybridMap map;
  map.StartSession("session");
  ASSERT_NO_FATAL_FAILURE(MapPlacesInOrder(&map));
  const Pose3 truth = Compose(PlacePose(1), MakePose(Vec3(0.1, 0, 0), Quat::Identity()));
  Keyframe query = View(1, Pose3::Identity(), truth);
  query.global_pose = Compose(truth, MakePose(Vec3(0, 0.3, 0), Quat::Identity()));
  query.session_id = map.current_session();

  LoopClosureOptions options;
  options.exclude_recent_keyframes = 5;
  options.proximity_candidates = 3;
  options.proximity_radius_m = 0.2;
  // Off: no dictionary candidate, none near the estimate, no loop closure.
  const LoopClosureResult off =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(), 0.0);
  EXPECT_FALSE(off.status.ok());
  EXPECT_EQ(off.registrations, 0);

  // The first three models are tried; only place 1 is within the registration's reach.
  options.start_candidates = 3;
  const LoopClosureResult r =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(), 0.0);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  EXPECT_EQ(r.registrations, 3);
  ASSERT_EQ(r.evidence.size(), 1u);
  EXPECT_TRUE(r.evidence[0].start);
  EXPECT_EQ(r.evidence[0].candidate_id, 1);
  EXPECT_LT(PoseDistance(r.loop_closure_pose, truth), 1e-9);

  // A dictionary candidate among them is not registered twice.
  const LoopClosureResult proposed =
      LoopClosureDetector(options).Detect(query, {{1, 0.9}}, map, TrueRegistration(), 0.0);
  ASSERT_TRUE(proposed.status.ok()) << proposed.status.reason();
  EXPECT_EQ(proposed.registrations, 3);
  ASSERT_EQ(proposed.evidence.size(), 1u);
  EXPECT_FALSE(proposed.evidence[0].start);
}

TEST_F(RouteFixture, StartCandidatesHaveTheirOwnInlierThresholdAndRecency) {
  // Places 0..9 (ids 0-9); the query revisits place 1, proposed by the dictionary as model 1
  // and registered with 15 inliers, below the loop links' 20.
  HybridMap map;
  map.StartSession("session");
  ASSERT_NO_FATAL_FAILURE(MapPlacesInOrder(&map));
  const Pose3 truth = Compose(PlacePose(1), MakePose(Vec3(0.1, 0, 0), Quat::Identity()));
  Keyframe query = View(1, Pose3::Identity(), truth);
  query.global_pose = truth;
  query.session_id = map.current_session();
  LoopClosureOptions options;
  options.exclude_recent_keyframes = 5;
  options.start_candidates = 3;
  // One threshold for all: 15 inliers verify nothing.
  const LoopClosureResult shared =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(15), 0.0);
  EXPECT_FALSE(shared.status.ok());
  EXPECT_EQ(shared.registrations, 3);
  // A start-only threshold of 12 verifies the start model...
  options.start_min_inliers = 12;
  const LoopClosureResult start =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(15), 0.0);
  ASSERT_TRUE(start.status.ok()) << start.status.reason();
  ASSERT_EQ(start.evidence.size(), 1u);
  EXPECT_TRUE(start.evidence[0].start);
  EXPECT_EQ(start.evidence[0].candidate_id, 1);
  // Models within exclude_recent_keyframes of the query are not start candidates, unless the
  // start candidates' own recency allows them.
  options.exclude_recent_keyframes = 20;
  const LoopClosureResult recent =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(15), 0.0);
  EXPECT_FALSE(recent.status.ok());
  EXPECT_EQ(recent.registrations, 0);
  options.start_exclude_recent_keyframes = 5;
  const LoopClosureResult own_recency =
      LoopClosureDetector(options).Detect(query, {}, map, TrueRegistration(15), 0.0);
  ASSERT_TRUE(own_recency.status.ok()) << own_recency.status.reason();
  EXPECT_EQ(own_recency.registrations, 3);
  ASSERT_EQ(own_recency.evidence.size(), 1u);
  EXPECT_EQ(own_recency.evidence[0].candidate_id, 1);
  options.exclude_recent_keyframes = 5;
  // ... but not the same model proposed by the dictionary: loop links keep min_inliers.
  options.start_candidates = 0;
  const LoopClosureResult dictionary =
      LoopClosureDetector(options).Detect(query, {{1, 0.9}}, map, TrueRegistration(15), 0.0);
  EXPECT_FALSE(dictionary.status.ok());
  EXPECT_EQ(dictionary.registrations, 1);
}

TEST_F(RouteFixture, LoopLinkMustJoinModelsAtTheSamePlace) {
  HybridMap map;
  int id = -1;
  ASSERT_TRUE(map.AddKeyframe(View(0, PlacePose(0), PlacePose(0)), Mat6::Identity(), &id));
  // The query is 0.4 m from the model; the registration measures that correctly.
  const Pose3 apart = MakePose(Vec3(0.4, 0, 0), Quat::Identity());
  Keyframe query = View(0, Pose3::Identity(), Compose(PlacePose(0), apart));
  query.global_pose = Compose(PlacePose(0), apart);
  LoopClosureOptions options;
  options.exclude_recent_keyframes = 0;
  options.max_link_translation_m = 0.3;
  const LoopClosureResult far =
      LoopClosureDetector(options).Detect(query, {{0, 0.9}}, map, TrueRegistration(), 0.0);
  EXPECT_FALSE(far.status.ok());
  EXPECT_TRUE(far.evidence.empty());
  options.max_link_translation_m = 0.5;
  const LoopClosureResult near =
      LoopClosureDetector(options).Detect(query, {{0, 0.9}}, map, TrueRegistration(), 0.0);
  ASSERT_TRUE(near.status.ok()) << near.status.reason();
  ASSERT_EQ(near.evidence.size(), 1u);
  EXPECT_LT(PoseDistance(near.evidence[0].registration.relative_pose, apart), 1e-9);
}

TEST_F(RouteFixture, BestThreeCandidatesPerLoopAreTried) {
  LoopClosureOptions options;
  options.exclude_recent_keyframes = 0;
  options.min_score = 0.1;
  HybridMap map;
  int id = -1;
  for (int k = 0; k < 6; ++k) {
    ASSERT_TRUE(
        map.AddKeyframe(View(k, Pose3::Identity(), Pose3::Identity()), Mat6::Identity(), &id));
  }
  std::vector<int> tried;
  const RegisterFn record = [&tried](const Keyframe&, const Keyframe& candidate) {
    tried.push_back(candidate.id);
    RegistrationOutcome out;
    out.status = Status::Error("registration rejected: test");
    return out;
  };
  Keyframe query = View(0, Pose3::Identity(), Pose3::Identity());
  const LoopClosureResult r = LoopClosureDetector(options).Detect(
      query, {{4, 0.9}, {2, 0.8}, {5, 0.5}, {1, 0.4}, {0, 0.05}}, map, record, 0.0);
  EXPECT_FALSE(r.status.ok());
  EXPECT_EQ(tried, (std::vector<int>{4, 2, 5}));
  EXPECT_NE(r.status.reason().find("registration failed"), std::string::npos);
}

// Thesis 6.1.1.2 steps 3-4 and eq. 6.2/6.3 worked by hand. Keyframes 0..5 form loop 0 and
// 6..8 loop 1, the chain steps 0.1 m along x (L_k = (0.1 k, 0, 0) in loop 0). The current model
// is at L_Current = (0.30, 0.05, 0). The registration returns, per candidate, the beta_i that
// puts the current model at the hypothesis H = L_li (+) beta_i written here (no rotation), with
// the inliers written here:
//   loop 0, dictionary order 4, 2, 5:  H_4 = (0.35, 0.02)  30 inliers
//                                      H_2 = (0.32, 0.03)  55 inliers  <- most inliers
//                                      H_5 = (0.25, 0.00)  40 inliers
//   loop 1:                            H_7 = (0.28, 0.05)  45 inliers
// Step 4 keeps H_2 for loop 0 (not the best-scored candidate 4), and loop 1 has H_7. Eq. 6.2
// with equal information and equal rotations is the plain mean of the translations:
//   L_LoopClosure = ((0.32 + 0.28) / 2, (0.03 + 0.05) / 2, 0) = (0.30, 0.04, 0),
// and eq. 6.3 DeltaPose_Diff = L_Current^-1 L_LoopClosure = (0.00, -0.01, 0).
TEST_F(RouteFixture, BestBetaPerLoopHasMostInliersAndEq62AveragesTheLoops) {
  LoopClosureOptions options;
  options.exclude_recent_keyframes = 0;
  HybridMap map;
  int id = -1;
  const Pose3 step = MakePose(Vec3(0.1, 0, 0), Quat::Identity());
  for (int k = 0; k < 9; ++k) {
    if (k == 6) map.StartLoop();
    ASSERT_TRUE(map.AddKeyframe(View(k, k == 0 ? Pose3::Identity() : step, Pose3::Identity()),
                                Mat6::Identity(), &id));
  }
  ASSERT_LT((map.keyframe(4).global_pose.translation() - Vec3(0.4, 0, 0)).norm(), 1e-12);
  ASSERT_EQ(map.keyframe(2).loop_id, map.keyframe(5).loop_id);
  ASSERT_NE(map.keyframe(2).loop_id, map.keyframe(7).loop_id);
  const std::map<int, std::pair<Vec3, int>> hypothesis{{4, {Vec3(0.35, 0.02, 0), 30}},
                                                       {2, {Vec3(0.32, 0.03, 0), 55}},
                                                       {5, {Vec3(0.25, 0.00, 0), 40}},
                                                       {7, {Vec3(0.28, 0.05, 0), 45}}};
  std::vector<int> tried;
  const RegisterFn reg = [&](const Keyframe&, const Keyframe& candidate) {
    tried.push_back(candidate.id);
    RegistrationOutcome out;
    const auto& [h, inliers] = hypothesis.at(candidate.id);
    out.status = Status::Ok();
    out.relative_pose = Between(candidate.global_pose, MakePose(h, Quat::Identity()));
    out.inliers = inliers;
    out.information = 100.0 * Mat6::Identity();
    return out;
  };
  Keyframe query = View(0, Pose3::Identity(), Pose3::Identity());
  query.global_pose = MakePose(Vec3(0.30, 0.05, 0), Quat::Identity());
  const LoopClosureResult r = LoopClosureDetector(options).Detect(
      query, {{4, 0.9}, {2, 0.8}, {7, 0.7}, {5, 0.5}}, map, reg, 0.0);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  EXPECT_EQ(tried, (std::vector<int>{4, 2, 5, 7}));  // loop 0's three, then loop 1's
  ASSERT_EQ(r.evidence.size(), 2u);
  EXPECT_EQ(r.evidence[0].candidate_id, 2);
  EXPECT_EQ(r.evidence[0].registration.inliers, 55);
  EXPECT_LT((r.evidence[0].global_pose.translation() - Vec3(0.32, 0.03, 0)).norm(), 1e-12);
  EXPECT_EQ(r.evidence[1].candidate_id, 7);
  EXPECT_LT((r.loop_closure_pose.translation() - Vec3(0.30, 0.04, 0)).norm(), 1e-9);
  EXPECT_LT(RotationAngleRad(r.loop_closure_pose), 1e-9);
  EXPECT_LT((r.delta_pose_diff.translation() - Vec3(0.0, -0.01, 0)).norm(), 1e-9);
}

TEST(MapBuilderOdometryInformation, RegistrationCovarianceWithFloorOrFixedSigmas) {
  MapBuilderOptions options;
  options.map.visual_information = VisualInformation::kFixed;
  Mat6 covariance = Mat6::Zero();
  covariance.diagonal() << 1e-4, 4e-4, 1e-4, 1e-6, 1e-6, 4e-6;
  covariance(0, 4) = covariance(4, 0) = 2e-6;
  const Mat6 fixed_visual =
      MapBuilder(options).OdometryInformation(RelativePoseSource::kVisual, &covariance);
  EXPECT_NEAR(fixed_visual(0, 0), 1.0 / (0.02 * 0.02), 1e-6);
  EXPECT_NEAR(fixed_visual(3, 3), 1.0 / (0.01 * 0.01), 1e-6);
  options.map.visual_information = VisualInformation::kRegistration;
  const MapBuilder builder(options);
  Mat6 floored = covariance;
  for (int i = 0; i < 6; ++i) floored(i, i) += i < 3 ? 0.005 * 0.005 : 0.002 * 0.002;
  const Mat6 information = builder.OdometryInformation(RelativePoseSource::kVisual, &covariance);
  EXPECT_LT((information * floored - Mat6::Identity()).norm(), 1e-9);
  // Wheel steps or no covariance: the fixed sigmas.
  EXPECT_NEAR(builder.OdometryInformation(RelativePoseSource::kVisual)(0, 0), 1.0 / (0.02 * 0.02),
              1e-6);
  EXPECT_NEAR(builder.OdometryInformation(RelativePoseSource::kWheelOdometry, &covariance)(0, 0),
              1.0 / (0.05 * 0.05), 1e-6);
  // A step the wheels placed, with the wheels' motion known: the wheel-link model; a visual
  // step keeps its registration covariance.
  const Pose3 step = MakePose(Vec3(0.3, 0.0, 0.0), Quat::Identity());
  EXPECT_EQ(builder.OdometryInformation(RelativePoseSource::kWheelOdometry, nullptr, &step),
            builder.WheelLinkInformation(step));
  EXPECT_EQ(builder.OdometryInformation(RelativePoseSource::kVisual, &covariance, &step),
            information);
}

}  // namespace
}  // namespace icgm
