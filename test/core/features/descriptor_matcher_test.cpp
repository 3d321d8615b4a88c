// Matches between an image and a copy under a known homography land on the mapped points; the
// ratio test and mutual check only remove matches; bad inputs give no matches.
#include "core/features/descriptor_matcher.h"

#include <gtest/gtest.h>

#include <set>

#include <opencv2/imgproc.hpp>

#include "../icgm/synthetic_scene.h"
#include "core/common/option_reader.h"

namespace icgm {
namespace {

struct Pair {
  FeatureSet a;
  FeatureSet b;
  cv::Matx33d h;
};

Pair MakePair(const std::string& detector) {
  test::SceneOptions scene_options;
  scene_options.num_pedestrians = 0;
  const test::ScenePair scene = test::RenderScenePair(scene_options);
  FeatureOptions options;
  options.detector = *ParseEnum<Detector>(detector);
  auto extractor = FeatureExtractor::Create(options);
  return {extractor->Extract(scene.image_a), extractor->Extract(scene.image_b), scene.homography};
}

double CorrectFraction(const Pair& pair, const std::vector<cv::DMatch>& matches) {
  if (matches.empty()) return 0.0;
  int correct = 0;
  for (const cv::DMatch& m : matches) {
    const cv::Point2f pa = pair.a.keypoints[m.queryIdx].pt;
    const cv::Point2f pb = pair.b.keypoints[m.trainIdx].pt;
    const cv::Vec3d q = pair.h * cv::Vec3d(pa.x, pa.y, 1.0);
    if (std::hypot(q[0] / q[2] - pb.x, q[1] / q[2] - pb.y) < 3.0) ++correct;
  }
  return static_cast<double>(correct) / matches.size();
}

class DescriptorMatcherTest : public ::testing::TestWithParam<std::string> {};

TEST_P(DescriptorMatcherTest, RatioMatchesFollowTheHomography) {
  const Pair pair = MakePair(GetParam());
  ASSERT_GT(pair.a.size(), 200u);
  MatcherOptions options;
  const auto matches = DescriptorMatcher(options).Match(pair.a, pair.b);
  EXPECT_GT(matches.size(), pair.a.size() / 4);
  EXPECT_GT(CorrectFraction(pair, matches), 0.9);
  std::set<int> queries;
  for (const cv::DMatch& m : matches) {
    ASSERT_GE(m.queryIdx, 0);
    ASSERT_LT(m.queryIdx, static_cast<int>(pair.a.size()));
    ASSERT_GE(m.trainIdx, 0);
    ASSERT_LT(m.trainIdx, static_cast<int>(pair.b.size()));
    EXPECT_TRUE(queries.insert(m.queryIdx).second) << "query matched twice";
  }
}

TEST_P(DescriptorMatcherTest, RatioAndMutualCheckOnlyRemoveWrongMatches) {
  const Pair pair = MakePair(GetParam());
  MatcherOptions plain;
  plain.ratio = 1.0;
  MatcherOptions mutual = plain;
  mutual.mutual_check = true;
  MatcherOptions ratio;
  ratio.ratio = 0.7;
  const auto plain_matches = DescriptorMatcher(plain).Match(pair.a, pair.b);
  const auto mutual_matches = DescriptorMatcher(mutual).Match(pair.a, pair.b);
  const auto ratio_matches = DescriptorMatcher(ratio).Match(pair.a, pair.b);
  EXPECT_EQ(plain_matches.size(), pair.a.size());
  EXPECT_LT(mutual_matches.size(), plain_matches.size());
  EXPECT_LT(ratio_matches.size(), plain_matches.size());
  EXPECT_GT(CorrectFraction(pair, mutual_matches), CorrectFraction(pair, plain_matches));
  EXPECT_GT(CorrectFraction(pair, ratio_matches), CorrectFraction(pair, plain_matches));
  std::set<int> trains;
  for (const cv::DMatch& m : mutual_matches) {
    EXPECT_TRUE(trains.insert(m.trainIdx).second) << "mutual matches must be one-to-one";
  }
}

INSTANTIATE_TEST_SUITE_P(AllDetectors, DescriptorMatcherTest,
                         ::testing::Values("orb", "sift", "akaze", "gftt_orb", "surf"));

TEST(DescriptorMatcherLshTest, LshFindsTheSameKindOfMatches) {
  const Pair pair = MakePair("orb");
  MatcherOptions options;
  options.binary_index = BinaryIndex::kLsh;
  const auto matches = DescriptorMatcher(options).Match(pair.a, pair.b);
  EXPECT_GT(matches.size(), pair.a.size() / 5);
  EXPECT_GT(CorrectFraction(pair, matches), 0.9);
}

// FLANN's kd-trees draw from the calling thread's OpenCV generator: whatever that thread ran
// before, the same frames give the same matches (a nodelet thread and the offline tool agree).
TEST(DescriptorMatcherFlannTest, SameFramesGiveTheSameMatchesWhateverTheThreadsGenerator) {
  const Pair pair = MakePair("surf");
  MatcherOptions options;
  options.flann_trees = 4;
  options.flann_checks = 8;  // few leaves: the randomized trees' choice shows in the result
  const DescriptorMatcher matcher(options);
  cv::theRNG() = cv::RNG(1);
  const auto first = matcher.Match(pair.a, pair.b);
  const uint64_t after_first = cv::theRNG().state;
  ASSERT_FALSE(first.empty());
  for (const uint64_t seed : {2ULL, 77ULL, 123456789ULL}) {
    cv::theRNG() = cv::RNG(seed);
    const auto again = matcher.Match(pair.a, pair.b);
    EXPECT_EQ(cv::theRNG().state, cv::RNG(seed).state) << "the thread's generator is given back";
    ASSERT_EQ(again.size(), first.size()) << "seed " << seed;
    for (size_t i = 0; i < first.size(); ++i) {
      EXPECT_EQ(again[i].queryIdx, first[i].queryIdx);
      EXPECT_EQ(again[i].trainIdx, first[i].trainIdx);
    }
  }
  EXPECT_EQ(after_first, cv::RNG(1).state);
}

TEST(DescriptorMatcherBadInputTest, EmptyOrIncompatibleSetsGiveNoMatches) {
  const Pair orb = MakePair("orb");
  const Pair sift = MakePair("sift");
  const DescriptorMatcher matcher{MatcherOptions()};
  EXPECT_TRUE(matcher.Match(FeatureSet(), orb.b).empty());
  EXPECT_TRUE(matcher.Match(orb.a, FeatureSet()).empty());
  EXPECT_TRUE(matcher.Match(orb.a, sift.b).empty());
  FeatureSet misaligned = orb.a;
  misaligned.keypoints.pop_back();
  EXPECT_TRUE(matcher.Match(misaligned, orb.b).empty());
  // A single train descriptor: no ratio test possible, nearest neighbour still returned.
  FeatureSet one;
  one.keypoints = {orb.b.keypoints[0]};
  one.descriptors = orb.b.descriptors.row(0).clone();
  EXPECT_EQ(matcher.Match(orb.a, one).size(), orb.a.size());
}

TEST(MatcherOptionsTest, ReadsAndRangeChecks) {
  MatcherOptions options;
  ReadOptions(OptionReader::FromString("{ratio: 0.7, mutual_check: true, binary_index: lsh}"),
              &options);
  EXPECT_DOUBLE_EQ(options.ratio, 0.7);
  EXPECT_TRUE(options.mutual_check);
  EXPECT_EQ(options.binary_index, BinaryIndex::kLsh);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{ratio: 1.5}"), &options), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{binary_index: kd}"), &options), LoadError);
}

}  // namespace
}  // namespace icgm
