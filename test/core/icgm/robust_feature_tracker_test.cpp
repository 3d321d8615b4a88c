// RobustFeatureTracker on sequences with known ground truth: a panning camera over static
// landmarks plus fast movers, each landmark with its own random binary descriptor so that the
// putative matches are exactly the landmark identities.
#include "core/icgm/robust_feature_tracker.h"

#include <gtest/gtest.h>

#include <random>

#include "core/common/option_reader.h"
#include "synthetic_scene.h"

namespace icgm {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

struct Landmark {
  Eigen::Vector2d position;  // world position, in pixels of the first frame
  Eigen::Vector2d velocity;  // pixels per frame (zero for static landmarks)
  cv::Mat descriptor;        // 1 x 32 CV_8U
};

class Sequence {
 public:
  Sequence(int num_static, int num_moving, double pan_px_per_frame, uint64_t seed)
      : pan_(pan_px_per_frame), rng_(seed) {
    std::uniform_real_distribution<double> ux(0.0, kWidth + 20.0 * pan_);
    std::uniform_real_distribution<double> uy(0.0, kHeight);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
    for (int i = 0; i < num_static + num_moving; ++i) {
      Landmark l;
      l.position = Eigen::Vector2d(ux(rng_), uy(rng_));
      if (i >= num_static) {
        const double a = angle(rng_);
        l.velocity = 90.0 * Eigen::Vector2d(std::cos(a), std::sin(a));
        l.position.x() = std::uniform_real_distribution<double>(0.0, kWidth)(rng_);
      } else {
        l.velocity.setZero();
      }
      l.descriptor = cv::Mat(1, 32, CV_8U);
      cv::randu(l.descriptor, 0, 256);
      landmarks_.push_back(l);
    }
  }

  // Features of frame t: every landmark inside the image, with 0.3 px noise. ids[k] is the
  // landmark of keypoint k.
  FeatureSet Frame(int t, std::vector<int>* ids) {
    FeatureSet set;
    set.binary = true;
    std::normal_distribution<double> noise(0.0, 0.3);
    ids->clear();
    std::vector<cv::Mat> rows;
    for (size_t i = 0; i < landmarks_.size(); ++i) {
      const Landmark& l = landmarks_[i];
      Eigen::Vector2d p;
      if (l.velocity.isZero()) {
        p = l.position - Eigen::Vector2d(pan_ * t, 0.0);
      } else {
        p = l.position + l.velocity * t;
        p.x() = Wrap(p.x(), kWidth);
        p.y() = Wrap(p.y(), kHeight);
      }
      if (p.x() < 0 || p.x() >= kWidth || p.y() < 0 || p.y() >= kHeight) continue;
      set.keypoints.emplace_back(static_cast<float>(p.x() + noise(rng_)),
                                 static_cast<float>(p.y() + noise(rng_)), 7.0f);
      rows.push_back(l.descriptor);
      ids->push_back(static_cast<int>(i));
    }
    if (!rows.empty()) cv::vconcat(rows, set.descriptors);
    return set;
  }

  bool IsMoving(int id) const { return !landmarks_[id].velocity.isZero(); }

 private:
  // Wraps around so that movers stay in view and always move fast.
  static double Wrap(double v, double size) {
    const double m = std::fmod(v, size);
    return m < 0 ? m + size : m;
  }
  double pan_;
  std::mt19937_64 rng_;
  std::vector<Landmark> landmarks_;
};

struct RunStats {
  size_t robust_static = 0;
  size_t robust_moving = 0;
  size_t frames = 0;
};

RunStats RunSequence(TrackerMode mode, int window, double pan, int frames = 12) {
  Sequence sequence(300, 40, pan, 5);
  TrackerOptions options;
  options.mode = mode;
  options.window_size = window;
  RobustFeatureTracker tracker(options);
  std::vector<std::vector<int>> ids(frames);
  RunStats stats;
  auto consume = [&](const std::optional<TrackedFrame>& out) {
    if (!out) return;
    const int t = static_cast<int>(out->stamp.nanoseconds());
    ASSERT_EQ(out->robust.size(), ids[t].size());
    ASSERT_EQ(out->match_kept.size(), out->matches_to_previous.size());
    ++stats.frames;
    if (t == 0) return;  // nothing to be robust against yet
    for (size_t k = 0; k < out->robust.size(); ++k) {
      if (!out->robust[k]) continue;
      if (sequence.IsMoving(ids[t][k])) {
        ++stats.robust_moving;
      } else {
        ++stats.robust_static;
      }
    }
  };
  for (int t = 0; t < frames; ++t) {
    consume(tracker.AddFeatures(Time::FromNanoseconds(t), sequence.Frame(t, &ids[t])));
  }
  consume(tracker.Flush());
  EXPECT_EQ(stats.frames, static_cast<size_t>(frames));
  return stats;
}

TEST(RobustFeatureTrackerTest, SingleDirectionalRejectsMovers) {
  const RunStats s = RunSequence(TrackerMode::kSingle, 2, 15.0);
  EXPECT_GT(s.robust_static, 1000u);
  EXPECT_LE(s.robust_moving, (s.robust_static + s.robust_moving) / 50);
}

TEST(RobustFeatureTrackerTest, PirfBaselineKeepsMovers) {
  // Thr -> infinity: every putative match is kept, moving landmarks included.
  const RunStats s = RunSequence(TrackerMode::kPirf, 2, 15.0);
  EXPECT_GT(s.robust_moving, 100u);
}

TEST(RobustFeatureTrackerTest, DoubleDirectionalKeepsAtLeastAsManyStaticFeatures) {
  // A panning camera loses the features entering the view in single-directional mode
  // (thesis eq. 4.21); double-directional recovers them from the next frame (eq. 4.22).
  const RunStats single = RunSequence(TrackerMode::kSingle, 2, 25.0);
  const RunStats twin = RunSequence(TrackerMode::kDouble, 3, 25.0);
  EXPECT_GT(twin.robust_static, single.robust_static);
  EXPECT_LE(twin.robust_moving, (twin.robust_static + twin.robust_moving) / 50);
}

// Thesis Fig. 4.3 keypoint by keypoint: with S = 3, the double-directional robust set C of I_t
// is A u B, A = the keypoints of I_t kept by ICGM against I_t-1 (single-directional, S = 2),
// B = those kept by ICGM between I_t and I_t+1.
TEST(RobustFeatureTrackerTest, DoubleDirectionalIsTheUnionOfBothSingleDirectionalSets) {
  Sequence sequence(300, 40, 25.0, 9);
  const int frames = 6;
  std::vector<std::vector<int>> ids(frames);
  std::vector<FeatureSet> sets;
  for (int t = 0; t < frames; ++t) sets.push_back(sequence.Frame(t, &ids[t]));
  TrackerOptions options;
  options.mode = TrackerMode::kSingle;
  options.window_size = 2;
  RobustFeatureTracker single(options);
  options.mode = TrackerMode::kDouble;
  options.window_size = 3;
  RobustFeatureTracker twin(options);
  std::vector<TrackedFrame> a_sets, c_sets;
  for (int t = 0; t < frames; ++t) {
    a_sets.push_back(*single.AddFeatures(Time::FromNanoseconds(t), sets[t]));
    if (auto c = twin.AddFeatures(Time::FromNanoseconds(t), sets[t])) c_sets.push_back(*c);
  }
  c_sets.push_back(*twin.Flush());
  ASSERT_EQ(c_sets.size(), a_sets.size());
  size_t only_forward = 0, checked = 0;
  for (int t = 1; t + 1 < frames; ++t) {
    // B: keypoints of I_t with a kept match from I_t+1 (the next frame's backward ICGM).
    std::vector<uint8_t> b(a_sets[t].features.size(), 0);
    const TrackedFrame& next = a_sets[t + 1];
    for (size_t m = 0; m < next.matches_to_previous.size(); ++m) {
      if (next.match_kept[m]) b[next.matches_to_previous[m].trainIdx] = 1;
    }
    ASSERT_EQ(c_sets[t].robust.size(), b.size());
    for (size_t k = 0; k < b.size(); ++k) {
      const bool in_a = a_sets[t].robust[k] != 0;
      EXPECT_EQ(c_sets[t].robust[k] != 0, in_a || b[k]) << "frame " << t << " keypoint " << k;
      only_forward += !in_a && b[k];
      ++checked;
    }
  }
  EXPECT_GT(checked, 500u);
  EXPECT_GT(only_forward, 10u);  // the panning camera: B adds keypoints that A lost
}

TEST(RobustFeatureTrackerTest, LargerWindowKeepsFewerFeatures) {
  for (const TrackerMode mode : {TrackerMode::kSingle, TrackerMode::kDouble, TrackerMode::kPirf}) {
    const RunStats s2 = RunSequence(mode, MinWindowSize(mode), 25.0);
    const RunStats s4 = RunSequence(mode, MinWindowSize(mode) + 2, 25.0);
    EXPECT_LT(s4.robust_static, s2.robust_static) << NameOf(mode);
    EXPECT_LE(s4.robust_moving, s2.robust_moving) << NameOf(mode);
  }
}

TEST(RobustFeatureTrackerTest, DoubleDirectionalOutputsWithOneFrameDelay) {
  Sequence sequence(100, 0, 10.0, 3);
  TrackerOptions options;
  options.mode = TrackerMode::kDouble;
  RobustFeatureTracker tracker(options);
  std::vector<int> ids;
  EXPECT_FALSE(tracker.AddFeatures(Time::FromNanoseconds(0), sequence.Frame(0, &ids)));
  auto out = tracker.AddFeatures(Time::FromNanoseconds(1), sequence.Frame(1, &ids));
  ASSERT_TRUE(out);
  EXPECT_EQ(out->stamp, Time::FromNanoseconds(0));
  // Frame 0 has no previous frame, but its forward link to frame 1 makes it robust (S = 3).
  EXPECT_GT(out->NumRobust(), 50u);
  out = tracker.Flush();
  ASSERT_TRUE(out);
  EXPECT_EQ(out->stamp, Time::FromNanoseconds(1));
  EXPECT_FALSE(tracker.Flush());

  options.mode = TrackerMode::kSingle;
  RobustFeatureTracker single(options);
  out = single.AddFeatures(Time::FromNanoseconds(0), sequence.Frame(0, &ids));
  ASSERT_TRUE(out);
  EXPECT_EQ(out->NumRobust(), 0u);
  EXPECT_FALSE(single.Flush());
}

TEST(RobustFeatureTrackerTest, EmptyFramesAndImagesDoNotBreakTheSequence) {
  TrackerOptions options;
  options.mode = TrackerMode::kDouble;
  RobustFeatureTracker tracker(options);
  tracker.AddImage(Time::FromNanoseconds(0), cv::Mat());
  auto out = tracker.AddFeatures(Time::FromNanoseconds(1), FeatureSet());
  ASSERT_TRUE(out);
  EXPECT_TRUE(out->robust.empty());
  test::SceneOptions scene_options;
  const test::ScenePair scene = test::RenderScenePair(scene_options);
  tracker.AddImage(Time::FromNanoseconds(2), scene.image_a);
  const auto frame_a = tracker.AddImage(Time::FromNanoseconds(3), scene.image_b);
  ASSERT_TRUE(frame_a);
  EXPECT_EQ(frame_a->stamp, Time::FromNanoseconds(2));
  const auto frame_b = tracker.Flush();
  ASSERT_TRUE(frame_b);
  EXPECT_TRUE(frame_b->icgm_status.ok()) << frame_b->icgm_status.reason();
  EXPECT_DOUBLE_EQ(frame_b->icgm_threshold_used, options.icgm.threshold);
  EXPECT_GT(frame_b->NumRobust(), 100u);
  // Kept matches (query = image b, train = image a) are on the static plane.
  int kept = 0;
  int kept_static = 0;
  for (size_t m = 0; m < frame_b->matches_to_previous.size(); ++m) {
    if (!frame_b->match_kept[m]) continue;
    const cv::DMatch& match = frame_b->matches_to_previous[m];
    const cv::Point2f pa = frame_a->features.keypoints[match.trainIdx].pt;
    const cv::Point2f pb = frame_b->features.keypoints[match.queryIdx].pt;
    ++kept;
    kept_static += test::ClassifyMatch(scene, Eigen::Vector2d(pa.x, pa.y),
                                       Eigen::Vector2d(pb.x, pb.y)) == test::MatchTruth::kStatic;
    EXPECT_TRUE(frame_b->robust[match.queryIdx]);
  }
  EXPECT_GT(kept, 100);
  EXPECT_GE(kept_static, kept * 95 / 100);
}

TEST(TrackerOptionsTest, ReadsShippedConfig) {
  const OptionReader root =
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/icgm.yaml");
  TrackerOptions options;
  ReadOptions(root, &options);
  EXPECT_EQ(options.mode, TrackerMode::kDouble);
  EXPECT_EQ(options.window_size, 3);  // thesis 6.1.3.1: double-directional ICGM, S = 3
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{tracker: {mode: triple}}"), &options),
               LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{tracker: {window_size: 1}}"), &options),
               LoadError);
  // S = 2 cannot hold I_t-1, I_t and I_t+1: an error for double-directional ICGM only.
  TrackerOptions single;
  EXPECT_NO_THROW(ReadOptions(
      OptionReader::FromString("{tracker: {mode: single, window_size: 2}}"), &single));
  EXPECT_EQ(single.window_size, 2);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{tracker: {mode: double, window_size: 2}}"),
                           &options),
               LoadError);
}

}  // namespace
}  // namespace icgm
