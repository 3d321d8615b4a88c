#include "core/place/place_recognizer.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "place_views.h"

namespace icgm {
namespace {

constexpr int kPlaces = 20;

PlaceRecognitionOptions Options() {
  PlaceRecognitionOptions o;
  o.exclude_recent_images = 5;
  return o;
}

// Concatenation of two feature sets (b's keypoints after a's).
FeatureSet Join(const FeatureSet& a, const FeatureSet& b) {
  FeatureSet out = a;
  out.keypoints.insert(out.keypoints.end(), b.keypoints.begin(), b.keypoints.end());
  out.descriptors.push_back(b.descriptors);
  return out;
}

// Lap 1: images 0..19 see places 0..19; returns the decisions of every image.
std::vector<PlaceDecision> FirstLap(PlaceRecognizer* r, test::PlaceViews* places) {
  std::vector<PlaceDecision> out;
  for (int i = 0; i < kPlaces; ++i) {
    PlaceDecision d;
    EXPECT_TRUE(r->Process(i, places->View(i, 0.0, 0.0), {}, &d));
    out.push_back(d);
  }
  return out;
}

TEST(PlaceRecognizerTest, SecondLapRecognizesEveryPlaceAndFirstLapNone) {
  for (const std::string matching : {"words", "descriptors"}) {
    SCOPED_TRACE(matching);
    test::PlaceViews places(kPlaces, 200, 3);
    PlaceRecognitionOptions o = Options();
    o.geometry.matching = *ParseEnum<PlaceMatching>(matching);
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    for (const PlaceDecision& d : FirstLap(&r, &places)) EXPECT_EQ(d.match, -1) << d.query;
    for (int i = 0; i < kPlaces; ++i) {
      PlaceDecision d;
      ASSERT_TRUE(r.Process(kPlaces + i, places.View(i, 0.3, 0.1), {}, &d));
      EXPECT_EQ(d.match, i) << "query " << d.query << ": " << d.rejected;
      EXPECT_GE(d.inliers, 20);
    }
  }
}

TEST(PlaceRecognizerTest, TemporalConsistencyRejectsTheFirstQueryOfARevisitOnly) {
  test::PlaceViews places(kPlaces, 200, 3);
  PlaceRecognitionOptions o = Options();
  o.temporal.consistent_queries = 1;
  PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
  FirstLap(&r, &places);
  // Second lap from place 5 on: 20 -> 5, 21 -> 6, ...
  for (int i = 0; i < 10; ++i) {
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces + i, places.View(5 + i, 0.3, 0.1), {}, &d));
    if (i == 0) {
      EXPECT_EQ(d.match, -1);
      EXPECT_EQ(d.best_candidate, 5);
      EXPECT_EQ(d.rejected, "not temporally consistent");
    } else {
      EXPECT_EQ(d.match, 5 + i) << d.rejected;
    }
  }
  // A single look-alike of place 2 in the middle of the revisit has no support.
  PlaceDecision d;
  ASSERT_TRUE(r.Process(40, places.View(2, 0.0, 0.0), {}, &d));
  EXPECT_EQ(d.best_candidate, 2);
  EXPECT_EQ(d.match, -1);
  EXPECT_EQ(d.rejected, "not temporally consistent");
}

TEST(PlaceRecognizerTest, GeometricVerificationRejectsALookAlike) {
  for (const std::string mode : {"words", "descriptors", "off"}) {
    SCOPED_TRACE(mode);
    const bool geometry = mode != "off";
    test::PlaceViews places(kPlaces, 200, 3);
    PlaceRecognitionOptions o = Options();
    o.geometry.enabled = geometry;
    if (geometry) o.geometry.matching = *ParseEnum<PlaceMatching>(mode);
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    FirstLap(&r, &places);
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces, places.LookAlike(5), {}, &d));
    EXPECT_EQ(d.best_candidate, 5);
    if (geometry) {
      EXPECT_EQ(d.match, -1);
      EXPECT_NE(d.rejected.find("inliers"), std::string::npos) << d.rejected;
    } else {
      EXPECT_EQ(d.match, 5) << "without the check the look-alike is a (false) loop";
    }
  }
}

// A replica of place 5 at twice its size, seen from twice as far, gives the same pixels as a
// revisit: the epipolar check accepts it, the RGB-D check (3-D distances doubled) does not.
// A true revisit with depth passes both.
TEST(PlaceRecognizerTest, RgbdVerificationRejectsAReplicaTheEpipolarCheckAccepts) {
  for (const bool rgbd : {false, true}) {
    SCOPED_TRACE(rgbd ? "rgbd" : "epipolar");
    test::PlaceViews places(kPlaces, 200, 3);
    PlaceRecognitionOptions o = Options();
    o.geometry.rgbd = rgbd;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < kPlaces; ++i) {
      PlaceDecision d;
      const FeatureSet f = places.View(i, 0.0, 0.0, 0.85, 4, &points);
      ASSERT_TRUE(r.Process(i, f, {}, &d, &points));
      EXPECT_EQ(d.match, -1);
    }
    PlaceDecision d;
    const FeatureSet replica = places.Replica(5, 2.0, 0.3, 0.1, &points);
    ASSERT_TRUE(r.Process(kPlaces, replica, {}, &d, &points));
    EXPECT_EQ(d.best_candidate, 5);
    if (rgbd) {
      EXPECT_EQ(d.match, -1);
      EXPECT_NE(d.rejected.find("rgbd verification: "), std::string::npos) << d.rejected;
    } else {
      EXPECT_EQ(d.match, 5) << "the replica fits the epipolar geometry of a revisit";
    }
    const FeatureSet revisit = places.View(6, 0.3, 0.1, 0.85, 4, &points);
    ASSERT_TRUE(r.Process(kPlaces + 1, revisit, {}, &d, &points));
    EXPECT_EQ(d.match, 6) << d.rejected;
    EXPECT_GE(d.inliers, 80);  // of ~100 word correspondences
    // Without depth for the query, the RGB-D recognizer falls back to the epipolar check.
    ASSERT_TRUE(r.Process(kPlaces + 2, places.View(7, 0.3, 0.1), {}, &d));
    EXPECT_EQ(d.match, 7) << d.rejected;
  }
}

// Every hypothesis a query tried is listed, best-scored first, with its verification counts and
// verdict; with keep_scores the decision carries every earlier image's score, best first.
TEST(PlaceRecognizerTest, DecisionListsEveryHypothesisWithItsVerdict) {
  test::PlaceViews places(kPlaces, 200, 3);
  PlaceRecognitionOptions o = Options();
  o.candidates = 3;
  PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
  r.set_keep_scores(true);
  FirstLap(&r, &places);
  // A look-alike of place 5 (its descriptors at random pixels): every hypothesis fails.
  PlaceDecision d;
  ASSERT_TRUE(r.Process(kPlaces, places.LookAlike(5), {}, &d));
  ASSERT_FALSE(d.checked.empty());
  EXPECT_EQ(d.checked.front().candidate, 5);
  EXPECT_EQ(d.checked.front().score, d.best_score);
  EXPECT_GE(d.checked.front().correspondences, 100);  // ~170 shared words
  EXPECT_LT(d.checked.front().inliers, o.geometry.min_inliers);
  EXPECT_NE(d.checked.front().verdict.find("inliers <"), std::string::npos)
      << d.checked.front().verdict;
  for (size_t i = 1; i < d.checked.size(); ++i) {
    EXPECT_LE(d.checked[i].score, d.checked[i - 1].score);
    EXPECT_FALSE(d.checked[i].verdict.empty());
  }
  ASSERT_FALSE(d.scores.empty());  // only images sharing a word with the query are scored
  EXPECT_EQ(d.scores.front().keyframe_id, 5);
  EXPECT_EQ(d.scores.front().score, d.best_score);
  // A revisit of place 6: accepted at the first hypothesis, whose verdict is empty.
  ASSERT_TRUE(r.Process(kPlaces + 1, places.View(6, 0.3, 0.1), {}, &d));
  EXPECT_EQ(d.match, 6);
  ASSERT_FALSE(d.checked.empty());
  EXPECT_EQ(d.checked.front().candidate, 6);
  EXPECT_TRUE(d.checked.front().verdict.empty());
  EXPECT_EQ(d.checked.front().inliers, d.inliers);
  // The scores include the recent images, which are no hypotheses.
  ASSERT_TRUE(r.Process(kPlaces + 2, places.View(kPlaces - 1, 0.3, 0.1), {}, &d));
  EXPECT_EQ(d.match, -1);
  EXPECT_TRUE(d.checked.empty());
  ASSERT_FALSE(d.scores.empty());
  EXPECT_EQ(d.scores.front().keyframe_id, kPlaces - 1);
  // Without keep_scores no scores are kept.
  r.set_keep_scores(false);
  ASSERT_TRUE(r.Process(kPlaces + 3, places.View(7, 0.3, 0.1), {}, &d));
  EXPECT_EQ(d.match, 7);
  EXPECT_TRUE(d.scores.empty());
}

// A revisit in which few features fall into the words of the earlier view (here most of its
// descriptors are 60 bits off, beyond the dictionary's 40-bit word radius, as blur or another
// viewpoint does): too few word correspondences for the epipolar check, while ratio-test
// descriptor matching still pairs them. The fallback recognizes it; a look-alike (the same
// descriptors at random pixels) still fails the check with the fallback.
TEST(PlaceRecognizerTest, DescriptorFallbackRecognizesARevisitWithFewWordCorrespondences) {
  for (const bool fallback : {false, true}) {
    SCOPED_TRACE(fallback ? "fallback" : "words only");
    test::PlaceViews places(kPlaces, 200, 3);
    PlaceRecognitionOptions o = Options();
    o.min_score = 0.01;
    o.geometry.descriptor_fallback = fallback;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    FirstLap(&r, &places);
    const FeatureSet query =
        Join(places.View(5, 0.3, 0.1, 0.06), places.View(5, 0.3, 0.1, 0.8, 60));
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces, query, {}, &d));
    ASSERT_EQ(d.best_candidate, 5);
    ASSERT_FALSE(d.checked.empty());
    if (fallback) {
      EXPECT_EQ(d.match, 5) << d.rejected;
      EXPECT_GE(d.inliers, 60);
    } else {
      EXPECT_EQ(d.match, -1);
      EXPECT_NE(d.rejected.find("matches < 20"), std::string::npos) << d.rejected;
    }
    ASSERT_TRUE(r.Process(kPlaces + 1, places.LookAlike(8), {}, &d));
    EXPECT_EQ(d.best_candidate, 8);
    EXPECT_EQ(d.match, -1);
  }
}

// A revisit (second lap from place 5 on) whose second image shares few words with the first
// lap (a quarter of place 6's points, among 200 features of walkers seen nowhere before) scores
// under min_score; continuation makes place 6, next to the previous loop (5), a hypothesis, and
// its geometry fits. A weak view of a place far from the previous loop is not recovered.
TEST(PlaceRecognizerTest, ContinuationRecoversAWeakImageOfARevisit) {
  for (const bool continuation : {false, true}) {
    SCOPED_TRACE(continuation ? "continuation" : "off");
    test::PlaceViews places(kPlaces, 200, 3);
    test::PlaceViews walkers(3, 200, 17);
    PlaceRecognitionOptions o = Options();
    o.min_score = 0.3;  // scaled up with the synthetic scores (a full revisit scores ~0.8)
    o.temporal.continuation = continuation;
    o.temporal.continuation_min_score = 0.05;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    r.set_keep_scores(true);
    FirstLap(&r, &places);
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces, places.View(5, 0.3, 0.1), {}, &d));
    ASSERT_EQ(d.match, 5) << d.rejected;
    ASSERT_TRUE(r.Process(kPlaces + 1,
                          Join(places.View(6, 0.3, 0.1, 0.25), walkers.View(0, 0.0, 0.0)), {}, &d));
    ASSERT_FALSE(d.scores.empty());
    ASSERT_EQ(d.scores.front().keyframe_id, 6);
    ASSERT_LT(d.scores.front().score, o.min_score);
    ASSERT_GE(d.scores.front().score, o.temporal.continuation_min_score);
    if (continuation) {
      EXPECT_EQ(d.match, 6) << d.rejected;
      EXPECT_GE(d.inliers, 20);
    } else {
      EXPECT_EQ(d.match, -1);
      EXPECT_EQ(d.best_candidate, -1);
    }
    // Place 15 is far from the last loop (6): weak, it is no hypothesis either way.
    ASSERT_TRUE(r.Process(
        kPlaces + 2, Join(places.View(15, 0.3, 0.1, 0.25), walkers.View(1, 0.0, 0.0)), {}, &d));
    ASSERT_EQ(d.scores.front().keyframe_id, 15);
    ASSERT_LT(d.scores.front().score, o.min_score);
    EXPECT_EQ(d.match, -1);
    EXPECT_TRUE(d.checked.empty());
  }
}

// A continuation hypothesis with fewer epipolar inliers than min_inliers: after a loop to place
// 5, a view of place 6 keeping 15% of its points among 200 walker features (under 20 of them,
// all fitting one geometry) is rejected at min_inliers 20 and accepted with
// continuation_min_inliers 10 (the previous loop is next to it: temporal agreement). The same
// weak view of place 15, far from the last loop, is no hypothesis, and a weak look-alike of
// place 7 (its descriptors at random pixels) next to the loop stays rejected.
TEST(PlaceRecognizerTest, ContinuationMinInliersAcceptsAWeakViewNextToThePreviousLoop) {
  for (const int min_inliers : {0, 10}) {
    SCOPED_TRACE("continuation_min_inliers " + std::to_string(min_inliers));
    test::PlaceViews places(kPlaces, 200, 3);
    test::PlaceViews walkers(4, 200, 17);
    PlaceRecognitionOptions o = Options();
    o.min_score = 0.3;  // scaled up with the synthetic scores (a full revisit scores ~0.8)
    o.temporal.continuation_min_score = 0.005;
    o.temporal.continuation_min_inliers = min_inliers;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    r.set_keep_scores(true);
    FirstLap(&r, &places);
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces, places.View(5, 0.3, 0.1), {}, &d));
    ASSERT_EQ(d.match, 5) << d.rejected;
    ASSERT_TRUE(r.Process(kPlaces + 1,
                          Join(places.View(6, 0.3, 0.1, 0.15), walkers.View(0, 0.0, 0.0)), {}, &d));
    ASSERT_FALSE(d.checked.empty());
    ASSERT_EQ(d.checked.front().candidate, 6);
    ASSERT_LT(d.checked.front().score, o.min_score);
    if (min_inliers > 0) {
      EXPECT_EQ(d.match, 6) << d.checked.front().verdict;
      EXPECT_GE(d.inliers, 10);
      EXPECT_LT(d.inliers, 20);
    } else {
      EXPECT_EQ(d.match, -1);
      EXPECT_NE(d.checked.front().verdict.find(" < 20"), std::string::npos)
          << d.checked.front().verdict;
    }
    // Far from the last loop: no hypothesis.
    ASSERT_TRUE(r.Process(
        kPlaces + 2, Join(places.View(15, 0.3, 0.1, 0.15), walkers.View(1, 0.0, 0.0)), {}, &d));
    EXPECT_EQ(d.match, -1);
    EXPECT_TRUE(d.checked.empty());
    // A revisit of place 6 again, then a weak look-alike of place 7 next to it.
    ASSERT_TRUE(r.Process(kPlaces + 3, places.View(6, 0.3, 0.1), {}, &d));
    ASSERT_EQ(d.match, 6) << d.rejected;
    ASSERT_TRUE(
        r.Process(kPlaces + 4, Join(places.LookAlike(7, 0.15), walkers.View(2, 0.0, 0.0)), {}, &d));
    ASSERT_FALSE(d.checked.empty());
    EXPECT_EQ(d.checked.front().candidate, 7);
    EXPECT_EQ(d.match, -1);
  }
}

// Lap 1 with depth: images 0..19 see places 0..19 and carry each keypoint's 3-D point.
void FirstLapWithDepth(PlaceRecognizer* r, test::PlaceViews* places) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < kPlaces; ++i) {
    PlaceDecision d;
    const FeatureSet f = places->View(i, 0.0, 0.0, 0.85, 4, &points);
    ASSERT_TRUE(r->Process(i, f, {}, &d, &points));
    ASSERT_EQ(d.match, -1);
  }
}

// A weak view of `place` (a quarter of its points among 200 features of walkers seen nowhere
// before) from `sideways_m`, with its 3-D points.
FeatureSet WeakView(test::PlaceViews* places, test::PlaceViews* walkers, int place,
                    double sideways_m, int walker, std::vector<Eigen::Vector3d>* points) {
  std::vector<Eigen::Vector3d> a, b;
  const FeatureSet f = Join(places->View(place, sideways_m, 0.05, 0.25, 4, &a),
                            walkers->View(walker, 0.0, 0.0, 0.85, 4, &b));
  *points = a;
  points->insert(points->end(), b.begin(), b.end());
  return f;
}

// The first image of a revisit scores under min_score and follows no loop (continuation cannot
// help): as a depth candidate, its rigid fit within the motion bound makes it the loop. The
// same weak view from 1.2 m away fits one rigid motion too but lies beyond the bound, and
// without depth the query has no depth candidates.
TEST(PlaceRecognizerTest, DepthCandidatesRecoverAWeakFirstImageOfARevisit) {
  for (const int depth_candidates : {0, 3}) {
    SCOPED_TRACE("depth_candidates " + std::to_string(depth_candidates));
    test::PlaceViews places(kPlaces, 200, 3);
    test::PlaceViews walkers(3, 200, 17);
    PlaceRecognitionOptions o = Options();
    o.min_score = 0.3;  // scaled up with the synthetic scores (a full revisit scores ~0.8)
    o.depth_candidates = depth_candidates;
    o.depth_min_score = 0.05;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    r.set_keep_scores(true);
    FirstLapWithDepth(&r, &places);
    std::vector<Eigen::Vector3d> points;
    PlaceDecision d;
    FeatureSet f = WeakView(&places, &walkers, 6, 0.2, 0, &points);
    ASSERT_TRUE(r.Process(kPlaces, f, {}, &d, &points));
    ASSERT_EQ(d.scores.front().keyframe_id, 6);
    ASSERT_LT(d.scores.front().score, o.min_score);
    ASSERT_GE(d.scores.front().score, o.depth_min_score);
    if (depth_candidates > 0) {
      EXPECT_EQ(d.match, 6) << d.rejected;
      EXPECT_GE(d.inliers, 20);
    } else {
      EXPECT_EQ(d.match, -1);
      EXPECT_TRUE(d.checked.empty());
    }
    f = WeakView(&places, &walkers, 12, 1.2, 1, &points);
    ASSERT_TRUE(r.Process(kPlaces + 1, f, {}, &d, &points));
    ASSERT_EQ(d.scores.front().keyframe_id, 12);
    ASSERT_LT(d.scores.front().score, o.min_score);
    EXPECT_EQ(d.match, -1);
    if (depth_candidates > 0) {
      ASSERT_FALSE(d.checked.empty());
      EXPECT_EQ(d.checked.front().candidate, 12);
      EXPECT_NE(d.checked.front().verdict.find("m > 0.45 m"), std::string::npos)
          << d.checked.front().verdict;
    }
    f = WeakView(&places, &walkers, 9, 0.2, 2, &points);
    ASSERT_TRUE(r.Process(kPlaces + 2, f, {}, &d));  // no depth
    ASSERT_EQ(d.scores.front().keyframe_id, 9);
    EXPECT_EQ(d.match, -1);
    EXPECT_TRUE(d.checked.empty());
  }
}

// A depth candidate whose view has depth for few of its keypoints (a quarter: walkers and
// missing depth): about 15 3-D matches, all fitting one rigid motion, under min_inliers 20,
// while its image geometry fits with 50+ correspondences. Rejected without the agreement,
// accepted with rgbd_agreement_min_inliers 10. A replica (twice the size from twice as far: the
// same pixels, another 3-D layout) with the same depth stays rejected: its epipolar check
// passes, its rigid fit does not.
TEST(PlaceRecognizerTest, RgbdAgreementAcceptsFewer3DInliersWhenTheEpipolarCheckAgrees) {
  for (const int agreement : {0, 10}) {
    SCOPED_TRACE("rgbd_agreement_min_inliers " + std::to_string(agreement));
    test::PlaceViews places(kPlaces, 200, 3);
    test::PlaceViews walkers(3, 200, 17);
    PlaceRecognitionOptions o = Options();
    o.min_score = 0.6;  // scaled up with the synthetic scores (a full revisit scores ~0.8)
    o.depth_candidates = 3;
    o.depth_min_score = 0.05;
    o.temporal.continuation = false;
    o.geometry.rgbd_agreement_min_inliers = agreement;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    FirstLapWithDepth(&r, &places);
    // Depth for every fourth keypoint of the view (none for the walkers).
    auto sparse_depth = [](std::vector<Eigen::Vector3d>* points, size_t place_points) {
      for (size_t k = 0; k < points->size(); ++k) {
        if (k >= place_points || k % 4 != 0) (*points)[k].setConstant(std::nan(""));
      }
    };
    std::vector<Eigen::Vector3d> a, b;
    FeatureSet f =
        Join(places.View(6, 0.2, 0.05, 0.35, 4, &a), walkers.View(0, 0.0, 0.0, 0.85, 4, &b));
    const size_t place_points = a.size();
    a.insert(a.end(), b.begin(), b.end());
    sparse_depth(&a, place_points);
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces, f, {}, &d, &a));
    ASSERT_FALSE(d.checked.empty());
    ASSERT_EQ(d.checked.front().candidate, 6);
    ASSERT_LT(d.checked.front().score, o.min_score);
    if (agreement > 0) {
      EXPECT_EQ(d.match, 6) << d.checked.front().verdict;
      EXPECT_GE(d.inliers, 10);
      EXPECT_LT(d.inliers, 20);
      EXPECT_NEAR(d.checked.front().translation_m, 0.2, 0.05);
    } else {
      EXPECT_EQ(d.match, -1);
      EXPECT_NE(d.checked.front().verdict.find("rgbd verification"), std::string::npos)
          << d.checked.front().verdict;
    }
    const FeatureSet replica =
        Join(places.Replica(9, 2.0, 0.2, 0.05, &a), walkers.View(1, 0.0, 0.0, 0.85, 4, &b));
    const size_t replica_points = a.size();
    a.insert(a.end(), b.begin(), b.end());
    sparse_depth(&a, replica_points);
    ASSERT_TRUE(r.Process(kPlaces + 1, replica, {}, &d, &a));
    ASSERT_FALSE(d.checked.empty());
    EXPECT_EQ(d.checked.front().candidate, 9);
    EXPECT_EQ(d.match, -1);
  }
}

// Place 5 is seen twice before: image 5 from its reference pose with most of its points (the
// higher score) and image 20 from 0.6 m to the right with fewer. A query from 0.55 m to the
// right is verified against both, rigidly (rgbd) or by the epipolar check; the best-scored is
// the loop by default, the nearer view (0.05 m against 0.55 m) with rgbd_nearest, which with
// the epipolar check measures each verified hypothesis's motion by the RGB-D fit.
void NearestVerifiedViewCase(bool rgbd, bool nearest) {
  test::PlaceViews places(kPlaces, 300, 3);
  PlaceRecognitionOptions o = Options();
  o.geometry.rgbd = rgbd;
  o.geometry.rgbd_nearest = nearest;
  o.temporal.continuation = false;
  PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
  FirstLapWithDepth(&r, &places);
  std::vector<Eigen::Vector3d> points;
  PlaceDecision d;
  FeatureSet f = places.View(5, 0.6, 0.0, 0.5, 4, &points);
  ASSERT_TRUE(r.Process(kPlaces, f, {}, &d, &points));
  ASSERT_EQ(d.match, 5) << d.rejected;
  for (int i = 1; i <= 6; ++i) {  // other places, so that image 20 is no recent image
    f = places.View(10 + i, 0.0, 0.0, 0.85, 4, &points);
    ASSERT_TRUE(r.Process(kPlaces + i, f, {}, &d, &points));
  }
  f = places.View(5, 0.55, 0.0, 0.85, 4, &points);
  ASSERT_TRUE(r.Process(kPlaces + 7, f, {}, &d, &points));
  ASSERT_GE(d.checked.size(), 2u);
  ASSERT_EQ(d.checked[0].candidate, 5);
  ASSERT_EQ(d.checked[1].candidate, kPlaces);
  if (nearest) {
    EXPECT_EQ(d.match, kPlaces) << d.rejected;
    EXPECT_NE(d.checked[0].verdict.find("is nearer"), std::string::npos) << d.checked[0].verdict;
    EXPECT_NEAR(d.checked[0].translation_m, 0.55, 0.03);
    EXPECT_NEAR(d.checked[1].translation_m, 0.05, 0.03);
  } else {
    EXPECT_EQ(d.match, 5) << d.rejected;
    EXPECT_EQ(d.checked[1].verdict, "not checked");
    // Only the RGB-D check fits a motion.
    EXPECT_EQ(std::isfinite(d.checked[0].translation_m), rgbd);
  }
}

TEST(PlaceRecognizerTest, RgbdNearestTakesTheNearestVerifiedView) {
  for (const bool rgbd : {true, false}) {
    for (const bool nearest : {false, true}) {
      SCOPED_TRACE(std::string(rgbd ? "rgbd check, " : "epipolar check, ") +
                   (nearest ? "nearest" : "best-scored"));
      NearestVerifiedViewCase(rgbd, nearest);
    }
  }
}

// A revisit whose features mostly fell into other words (60 bits flipped) has too few word
// correspondences for the RGB-D check; rgbd_descriptor_fallback retries on ratio-test
// descriptor matches with depth and finds the rigid motion. A replica (another 3-D layout)
// stays rejected.
TEST(PlaceRecognizerTest, RgbdDescriptorFallbackRecognizesARevisitWithFewWordCorrespondences) {
  for (const bool fallback : {false, true}) {
    SCOPED_TRACE(fallback ? "fallback" : "words only");
    test::PlaceViews places(kPlaces, 200, 3);
    PlaceRecognitionOptions o = Options();
    o.min_score = 0.01;
    o.geometry.rgbd = true;
    o.geometry.rgbd_descriptor_fallback = fallback;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    FirstLapWithDepth(&r, &places);
    std::vector<Eigen::Vector3d> a, b;
    const FeatureSet query =
        Join(places.View(5, 0.3, 0.1, 0.06, 4, &a), places.View(5, 0.3, 0.1, 0.8, 60, &b));
    a.insert(a.end(), b.begin(), b.end());
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces, query, {}, &d, &a));
    ASSERT_EQ(d.best_candidate, 5);
    if (fallback) {
      EXPECT_EQ(d.match, 5) << d.rejected;
      EXPECT_GE(d.inliers, 60);
    } else {
      EXPECT_EQ(d.match, -1);
      EXPECT_NE(d.rejected.find("3-D matches < 20"), std::string::npos) << d.rejected;
    }
    const FeatureSet replica = places.Replica(8, 2.0, 0.3, 0.1, &a);
    ASSERT_TRUE(r.Process(kPlaces + 1, replica, {}, &d, &a));
    EXPECT_EQ(d.best_candidate, 8);
    EXPECT_EQ(d.match, -1);
  }
}

TEST(PlaceRecognizerTest, MinimumWordsGuardStopsAFrameWithFewWords) {
  for (const int min_words : {50, 0}) {
    test::PlaceViews places(kPlaces, 200, 3);
    PlaceRecognitionOptions o = Options();
    o.min_query_words = min_words;
    o.geometry.enabled = false;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    FirstLap(&r, &places);
    PlaceDecision d;
    ASSERT_TRUE(r.Process(kPlaces, places.View(3, 0.0, 0.0, 0.12), {}, &d));
    ASSERT_LT(d.words, 50);
    EXPECT_EQ(d.best_candidate, 3);
    if (min_words > 0) {
      EXPECT_EQ(d.match, -1);
      EXPECT_NE(d.rejected.find("too few words"), std::string::npos) << d.rejected;
    } else {
      EXPECT_EQ(d.match, 3);
    }
  }
}

// A crowd seen at image 7 walks through the revisit of place 2: its features (not verified by
// ICGM) are more than the static ones (verified). Plain features recognize the crowd, weighted
// features the place.
TEST(PlaceRecognizerTest, VerifiedFeaturesOutweighACrowdSeenBefore) {
  auto run = [](double unverified_weight, bool share_weighting) {
    test::PlaceViews places(kPlaces, 200, 3);
    test::PlaceViews crowd(1, 300, 11);
    PlaceRecognitionOptions o = Options();
    o.unverified_weight = unverified_weight;
    o.weight_by_verified_share = share_weighting;
    o.geometry.enabled = false;  // the scores alone
    PlaceRecognizer r(o, DictionaryOptions());
    for (int i = 0; i < kPlaces; ++i) {
      FeatureSet f = places.View(i, 0.0, 0.0);
      std::vector<uint8_t> verified(f.size(), 1);
      if (i == 7) {
        const FeatureSet people = crowd.View(0, 0.0, 0.0, 0.6);
        f = Join(f, people);
        verified.resize(f.size(), 0);
      }
      PlaceDecision d;
      EXPECT_TRUE(r.Process(i, f, verified, &d));
    }
    const FeatureSet stat = places.View(2, 0.3, 0.1, 0.35);
    const FeatureSet people = crowd.View(0, 0.0, 0.0, 0.6);
    std::vector<uint8_t> verified(stat.size(), 1);
    verified.resize(stat.size() + people.size(), 0);
    PlaceDecision d;
    EXPECT_TRUE(r.Process(kPlaces + 10, Join(stat, people), verified, &d));
    return d;
  };
  EXPECT_EQ(run(1.0, false).match, 7) << "plain features: the crowd wins";
  EXPECT_EQ(run(0.3, false).match, 2) << "weighted: the place wins";
  EXPECT_EQ(run(0.3, true).match, 2) << "weighted by the verified share: the place wins";
}

// A sparse revisit: ICGM verified few features (consecutive images a metre apart share few).
// Verified features alone are too few words; unverified ones at a lower weight recognize it.
TEST(PlaceRecognizerTest, UnverifiedFeaturesRecognizeASparseRevisit) {
  auto run = [](double unverified_weight, bool share_weighting = false) {
    test::PlaceViews places(kPlaces, 200, 3);
    PlaceRecognitionOptions o = Options();
    o.unverified_weight = unverified_weight;
    o.weight_by_verified_share = share_weighting;
    PlaceRecognizer r(o, DictionaryOptions(), test::PlaceViews::Camera());
    for (int i = 0; i < kPlaces; ++i) {
      const FeatureSet f = places.View(i, 0.0, 0.0);
      std::vector<uint8_t> verified(f.size(), 0);
      for (size_t k = 0; k < verified.size(); k += 10) verified[k] = 1;
      PlaceDecision d;
      EXPECT_TRUE(r.Process(i, f, verified, &d));
    }
    const FeatureSet f = places.View(4, 0.3, 0.1);
    std::vector<uint8_t> verified(f.size(), 0);
    for (size_t k = 0; k < verified.size(); k += 10) verified[k] = 1;
    PlaceDecision d;
    EXPECT_TRUE(r.Process(kPlaces + 10, f, verified, &d));
    return d;
  };
  const PlaceDecision icgm_only = run(0.0);
  EXPECT_EQ(icgm_only.match, -1);
  EXPECT_LT(icgm_only.words, 50);
  const PlaceDecision weighted = run(0.3);
  EXPECT_EQ(weighted.match, 4) << weighted.rejected;
  // By the verified share (10 %): the unverified features weigh 0.9 even with a floor of 0.
  const PlaceDecision by_share = run(0.0, true);
  EXPECT_EQ(by_share.match, 4) << by_share.rejected;
  EXPECT_GE(by_share.words, 50);
}

TEST(PlaceRecognizerTest, WrongDescriptorsAreAnErrorAndChangeNothing) {
  PlaceRecognizer r(Options(), DictionaryOptions());
  FeatureSet f;
  f.keypoints.resize(3);
  f.descriptors = cv::Mat::zeros(3, 64, CV_32F);
  f.binary = false;
  PlaceDecision d;
  const Status s = r.Process(0, f, {}, &d);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("binary"), std::string::npos) << s.reason();
  EXPECT_EQ(r.dictionary().num_keyframes(), 0);
}

}  // namespace
}  // namespace icgm
