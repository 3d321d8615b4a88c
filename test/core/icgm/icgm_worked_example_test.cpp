// Thesis Algorithm 1 (ICGM) and Fig. 4.3 (double-directional ICGM) on small examples worked out
// by hand in the comments; the tests check the code against those numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/icgm/icgm_matcher.h"
#include "core/icgm/robust_feature_tracker.h"

namespace icgm {
namespace {

using V2 = Eigen::Vector2d;

// Six matches p_k <-> p'_k, Thr = 0.1. Matches 0, 1, 2 move by (10, 0) (the camera), 4 and 5 by
// (14, 0) and (12, 0) (a few pixels of noise), 3 by (30, 0) (a walker).
struct SixMatches {
  std::vector<V2> a{{0, 0}, {100, 0}, {50, 100}, {50, -50}, {0, 100}, {100, 100}};
  std::vector<V2> b{{10, 0}, {110, 0}, {60, 100}, {80, -50}, {14, 100}, {112, 100}};
};

void ExpectNear(const V2& v, double x, double y, const std::string& what) {
  EXPECT_NEAR(v.x(), x, 1e-9) << what;
  EXPECT_NEAR(v.y(), y, 1e-9) << what;
}

// Seed pair (0, 1): p_0 - p_1 = (-100, 0) = p'_0 - p'_1, RoD 0 <= Thr.
//   CG_0 = (50, 0), CG_1 = (60, 0), SCG = 2.
// k = 2: CGV_0 = (50, 0) - (50, 100) = (0, -100), CGV_1 = (60, 0) - (60, 100) = (0, -100);
//   RoD = 0 / 200 = 0 -> kept. CG_0 = 2/3 ((50, 0) + (50, 100) / 2) = (50, 33.333),
//   CG_1 = (60, 33.333), SCG = 3.
// k = 3: CGV_0 = (0, 83.333), CGV_1 = (60 - 80, 83.333) = (-20, 83.333);
//   |CGV_0 - CGV_1| = 20, |CGV_0| + |CGV_1| = 83.333 + 85.700 = 169.033, RoD = 0.11832 > 0.1 ->
//   rejected, centres unchanged.
// k = 4: CGV_0 = (50, -66.667), CGV_1 = (46, -66.667); 4 / (83.333 + 80.996) = 0.024341 -> kept.
//   CG_0 = (150, 200) / 4 = (37.5, 50), CG_1 = (194, 200) / 4 = (48.5, 50), SCG = 4.
// k = 5: CGV_0 = (-62.5, -50), CGV_1 = (-63.5, -50); 1 / (80.039 + 80.822) = 0.0062166 -> kept.
//   CG_0 = (250, 300) / 5 = (50, 60), CG_1 = (306, 300) / 5 = (61.2, 60), SCG = 5.
// Result p_R = {0, 1, 2, 4, 5}.
TEST(IcgmWorkedExampleTest, AlgorithmOneStepByStep) {
  const SixMatches m;
  std::vector<IcgmStep> steps;
  const IcgmResult r = RunIcgmFromSeed(m.a, m.b, 0, 1, 0.1, &steps);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  ASSERT_EQ(steps.size(), 4u);
  const int match[4] = {2, 3, 4, 5};
  const double rod[4] = {0.0, 20.0 / (250.0 / 3.0 + std::hypot(20.0, 250.0 / 3.0)),
                         4.0 / (std::hypot(50.0, 200.0 / 3.0) + std::hypot(46.0, 200.0 / 3.0)),
                         1.0 / (std::hypot(62.5, 50.0) + std::hypot(63.5, 50.0))};
  const bool kept[4] = {true, false, true, true};
  const double cg[4][4] = {{50, 100.0 / 3, 60, 100.0 / 3},
                           {50, 100.0 / 3, 60, 100.0 / 3},
                           {37.5, 50, 48.5, 50},
                           {50, 60, 61.2, 60}};
  for (int s = 0; s < 4; ++s) {
    const std::string what = "step " + std::to_string(s);
    EXPECT_EQ(steps[s].match, match[s]) << what;
    EXPECT_NEAR(steps[s].rod, rod[s], 1e-9) << what;
    EXPECT_EQ(steps[s].kept, kept[s]) << what;
    ExpectNear(steps[s].cg_a, cg[s][0], cg[s][1], what + " CG_0");
    ExpectNear(steps[s].cg_b, cg[s][2], cg[s][3], what + " CG_1");
  }
  // The rounded values written above, as a check of the hand arithmetic itself.
  EXPECT_NEAR(steps[1].rod, 0.11832, 1e-5);
  EXPECT_NEAR(steps[2].rod, 0.024341, 1e-6);
  EXPECT_NEAR(steps[3].rod, 0.0062166, 1e-7);
  EXPECT_EQ(r.kept, (std::vector<uint8_t>{1, 1, 1, 0, 1, 1}));
  EXPECT_EQ(r.num_kept, 5u);
  ExpectNear(r.cg_a, 50, 60, "final CG_0");
  ExpectNear(r.cg_b, 61.2, 60, "final CG_1");
}

// Algorithm 1 tests each match once against the centres of that moment, so the order matters.
// The same six matches with the walker tested last: after 2, 4 and 5 the centres are
// CG_0 = (50, 60), CG_1 = (61.2, 60) (as above), and for k = 3
//   CGV_0 = (0, 110), CGV_1 = (61.2 - 80, 110) = (-18.8, 110),
//   RoD = 18.8 / (110 + 111.595) = 0.084839 <= 0.1 -> kept.
// The centres moved away from the walker, so its 20 px of own motion became a smaller share.
TEST(IcgmWorkedExampleTest, AlgorithmOneDependsOnTheOrderOfTheTests) {
  const SixMatches m;
  const std::vector<int> order{0, 1, 2, 4, 5, 3};
  std::vector<V2> a, b;
  for (int k : order) {
    a.push_back(m.a[k]);
    b.push_back(m.b[k]);
  }
  std::vector<IcgmStep> steps;
  const IcgmResult r = RunIcgmFromSeed(a, b, 0, 1, 0.1, &steps);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  ASSERT_EQ(steps.size(), 4u);
  EXPECT_EQ(order[steps[3].match], 3);
  EXPECT_NEAR(steps[3].rod, 18.8 / (110.0 + std::hypot(18.8, 110.0)), 1e-9);
  EXPECT_NEAR(steps[3].rod, 0.084839, 1e-6);
  EXPECT_TRUE(steps[3].kept);
  EXPECT_EQ(r.num_kept, 6u);
  // CG after the walker: ((250, 300) + (50, -50)) / 6 and ((306, 300) + (80, -50)) / 6.
  ExpectNear(r.cg_a, 50, 250.0 / 6, "CG_0");
  ExpectNear(r.cg_b, 386.0 / 6, 250.0 / 6, "CG_1");
}

// RunIcgm draws the seed pair at random (Algorithm 1's first loop); with one seed and no
// refinement the rest is the deterministic pass above from the pair it drew.
TEST(IcgmWorkedExampleTest, RandomSeedThenTheSamePassAsFromThatSeed) {
  const SixMatches m;
  IcgmOptions options;
  options.threshold = 0.1;
  options.seed_pairs = 1;
  options.refine = false;
  std::map<std::pair<int, int>, int> seeds_seen;
  for (uint64_t rng_seed = 1; rng_seed <= 30; ++rng_seed) {
    options.rng_seed = rng_seed;
    const IcgmResult r = RunIcgm(m.a, m.b, options);
    ASSERT_TRUE(r.status.ok()) << r.status.reason();
    ASSERT_GE(r.seed_i, 0);
    ASSERT_GE(r.seed_j, 0);
    // The drawn pair passed the first loop's test.
    EXPECT_LE(RatioOfDifference(m.a[r.seed_i] - m.a[r.seed_j], m.b[r.seed_i] - m.b[r.seed_j]), 0.1);
    const IcgmResult same = RunIcgmFromSeed(m.a, m.b, r.seed_i, r.seed_j, 0.1);
    EXPECT_EQ(r.kept, same.kept) << "seed pair " << r.seed_i << ", " << r.seed_j;
    EXPECT_LT((r.cg_a - same.cg_a).norm(), 1e-12);
    ++seeds_seen[{std::min(r.seed_i, r.seed_j), std::max(r.seed_i, r.seed_j)}];
  }
  EXPECT_GT(seeds_seen.size(), 3u);  // the seed pair really is drawn
}

TEST(IcgmWorkedExampleTest, UnusableSeedPairIsAnErrorWithReason) {
  const SixMatches m;
  // Pair (0, 3): p_0 - p_3 = (-50, 50), p'_0 - p'_3 = (-70, 50); RoD = 20 / (70.711 + 86.023)
  // = 0.1276 > 0.1.
  const IcgmResult r = RunIcgmFromSeed(m.a, m.b, 0, 3, 0.1);
  EXPECT_FALSE(r.status.ok());
  EXPECT_NE(r.status.reason().find("RoD 0.1276 > Thr 0.1"), std::string::npos) << r.status.reason();
  EXPECT_EQ(r.num_kept, 0u);
  EXPECT_FALSE(RunIcgmFromSeed(m.a, m.b, 2, 2, 0.1).status.ok());
  EXPECT_FALSE(RunIcgmFromSeed(m.a, m.b, 0, 6, 0.1).status.ok());
}

// Thesis Fig. 4.3 by hand: three frames I_t-1, I_t, I_t+1; the camera pans by (10, 0) px per
// frame. Landmarks (position in I_t-1 / I_t / I_t+1):
//   S1..S5 static, in all three frames             -> in A and in B
//   L  static, leaves the view after I_t           -> (610, 240) in I_t: in A, not in B
//   E  static, enters the view in I_t              -> (30, 240) in I_t: in B, not in A
//   M  walks all the time (+110 px, then -90 px)   -> in neither
//   W  still, then walks (+110 px) after I_t       -> in A, not in B
//   V  walks (-90 px) until I_t, then stands still -> in B, not in A
// A = ICGM(I_t-1, I_t), B = ICGM(I_t, I_t+1), C = A u B = everything but M.
// Worked by hand (and checked for every seed pair the first loop can draw): a pair holding a
// walker has RoD >= 0.16 > Thr, any static pair RoD 0, and against the static centres the
// walkers have RoD >= 0.39 (M 0.57 / 0.75, V 0.39, W 0.65), so the kept sets do not depend on
// the random seed.
TEST(IcgmWorkedExampleTest, DoubleDirectionalIsAUnionBKeypointByKeypoint) {
  struct Landmark {
    std::string name;
    std::vector<V2> at;  // per frame; NaN = not in view
    bool in_a, in_b;
  };
  const double nan = std::nan("");
  const V2 none(nan, nan);
  auto pan = [](double x, double y) { return std::vector<V2>{{x, y}, {x + 10, y}, {x + 20, y}}; };
  const std::vector<Landmark> landmarks{
      {"S1", pan(100, 100), true, true},
      {"S2", pan(500, 120), true, true},
      {"S3", pan(300, 400), true, true},
      {"S4", pan(120, 380), true, true},
      {"S5", pan(520, 360), true, true},
      {"L", {{600, 240}, {610, 240}, none}, true, false},
      {"E", {none, {30, 240}, {40, 240}}, false, true},
      {"M", {{280, 200}, {390, 200}, {300, 260}}, false, false},
      {"W", {{250, 300}, {260, 300}, {370, 300}}, true, false},
      {"V", {{350, 160}, {260, 160}, {270, 160}}, false, true},
  };
  // One random 256-bit descriptor per landmark, the same in every frame.
  std::mt19937 rng(5);
  std::vector<cv::Mat> descriptor;
  for (size_t l = 0; l < landmarks.size(); ++l) {
    cv::Mat d(1, 32, CV_8U);
    for (int c = 0; c < 32; ++c) d.at<uint8_t>(0, c) = static_cast<uint8_t>(rng());
    descriptor.push_back(d);
  }
  std::vector<FeatureSet> frames(3);
  std::vector<std::vector<int>> landmark_of(3);  // keypoint -> landmark
  for (int f = 0; f < 3; ++f) {
    for (size_t l = 0; l < landmarks.size(); ++l) {
      const V2& p = landmarks[l].at[f];
      if (!std::isfinite(p.x())) continue;
      frames[f].keypoints.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 7.f);
      frames[f].descriptors.push_back(descriptor[l]);
      landmark_of[f].push_back(static_cast<int>(l));
    }
  }
  TrackerOptions options;
  options.icgm.threshold = 0.08;
  options.matcher.max_distance = 40;  // a landmark not in the other frame finds no match
  options.mode = TrackerMode::kSingle;
  options.window_size = 2;
  RobustFeatureTracker single(options);
  options.mode = TrackerMode::kDouble;
  options.window_size = 3;  // the thesis's S = 3: I_t-1, I_t, I_t+1
  RobustFeatureTracker twin(options);
  std::vector<TrackedFrame> a_frames, c_frames;
  for (int f = 0; f < 3; ++f) {
    a_frames.push_back(*single.AddFeatures(Time::FromNanoseconds(f), frames[f]));
    if (auto c = twin.AddFeatures(Time::FromNanoseconds(f), frames[f])) c_frames.push_back(*c);
  }
  ASSERT_EQ(c_frames.size(), 2u);  // I_t-1 and I_t; I_t+1 waits for its successor
  const TrackedFrame& a = a_frames[1];
  const TrackedFrame& c = c_frames[1];
  const TrackedFrame& next = a_frames[2];
  ASSERT_EQ(a.features.size(), 10u);  // S1..S5, L, E, M, W, V
  ASSERT_EQ(c.robust.size(), a.features.size());
  // B: keypoints of I_t with a kept match from I_t+1.
  std::vector<uint8_t> b(a.features.size(), 0);
  for (size_t m = 0; m < next.matches_to_previous.size(); ++m) {
    if (next.match_kept[m]) b[next.matches_to_previous[m].trainIdx] = 1;
  }
  for (size_t k = 0; k < a.features.size(); ++k) {
    const Landmark& l = landmarks[landmark_of[1][k]];
    EXPECT_EQ(a.robust[k] != 0, l.in_a) << l.name << " in A";
    EXPECT_EQ(b[k] != 0, l.in_b) << l.name << " in B";
    EXPECT_EQ(c.robust[k] != 0, l.in_a || l.in_b) << l.name << " in C";
  }
  EXPECT_EQ(a.NumRobust(), 7u);  // S1..S5, L, W
  EXPECT_EQ(c.NumRobust(), 9u);  // all but M
}

}  // namespace
}  // namespace icgm
