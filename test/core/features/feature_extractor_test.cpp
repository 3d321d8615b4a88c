// Every detector finds features on a corner-rich texture, honours the budget and the descriptor
// policy, and returns an empty set for empty or unsupported images.
#include "core/features/feature_extractor.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "../icgm/synthetic_scene.h"
#include "core/common/option_reader.h"

namespace icgm {
namespace {

class FeatureExtractorTest : public ::testing::TestWithParam<std::string> {};

TEST_P(FeatureExtractorTest, FindsFeaturesWithinBudget) {
  FeatureOptions options;
  options.detector = *ParseEnum<Detector>(GetParam());
  options.max_features = 500;
  auto extractor = FeatureExtractor::Create(options);
  ASSERT_NE(extractor, nullptr);
  EXPECT_EQ(extractor->name(), GetParam());
  const cv::Mat image = test::MakeTexture(cv::Size(640, 480), 3);
  const FeatureSet set = extractor->Extract(image);
  EXPECT_GT(set.size(), 200u);
  EXPECT_LE(set.size(), 500u);
  EXPECT_EQ(set.descriptors.rows, static_cast<int>(set.size()));
  EXPECT_EQ(set.binary, extractor->binary());
  EXPECT_EQ(set.descriptors.depth(), set.binary ? CV_8U : CV_32F);
  for (const cv::KeyPoint& kp : set.keypoints) {
    ASSERT_GE(kp.pt.x, 0.0f);
    ASSERT_LT(kp.pt.x, 640.0f);
    ASSERT_GE(kp.pt.y, 0.0f);
    ASSERT_LT(kp.pt.y, 480.0f);
  }
  // Gray input gives the same kind of output.
  cv::Mat gray;
  cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  EXPECT_GT(extractor->Extract(gray).size(), 200u);
}

TEST_P(FeatureExtractorTest, EmptyAndUnsupportedImagesGiveEmptySets) {
  FeatureOptions options;
  options.detector = *ParseEnum<Detector>(GetParam());
  auto extractor = FeatureExtractor::Create(options);
  ASSERT_NE(extractor, nullptr);
  EXPECT_TRUE(extractor->Extract(cv::Mat()).empty());
  EXPECT_TRUE(extractor->Extract(cv::Mat(480, 640, CV_32FC1, cv::Scalar(0.5))).empty());
  EXPECT_TRUE(extractor->Extract(cv::Mat(480, 640, CV_8UC2, cv::Scalar(7, 9))).empty());
  // A flat image has no corners.
  EXPECT_TRUE(extractor->Extract(cv::Mat(480, 640, CV_8UC3, cv::Scalar(90, 90, 90))).empty());
  // Tiny images must not crash.
  const FeatureSet tiny = extractor->Extract(test::MakeTexture(cv::Size(8, 8), 5));
  EXPECT_EQ(tiny.descriptors.rows, static_cast<int>(tiny.size()));
}

INSTANTIATE_TEST_SUITE_P(AllDetectors, FeatureExtractorTest,
                         ::testing::Values("orb", "sift", "akaze", "gftt_orb", "surf"));

TEST(FeatureExtractorCreateTest, EveryDetectorChoiceHasAnExtractorOfThatName) {
  for (const std::string& name : EnumChoices<Detector>()) {
    FeatureOptions options;
    options.detector = *ParseEnum<Detector>(name);
    const auto extractor = FeatureExtractor::Create(options);
    ASSERT_NE(extractor, nullptr) << name;
    EXPECT_EQ(extractor->name(), name);
  }
}

TEST(FeatureOptionsTest, ReadsAndRangeChecks) {
  FeatureOptions options;
  ReadOptions(OptionReader::FromString("{detector: sift, max_features: 300}"), &options);
  EXPECT_EQ(options.detector, Detector::kSift);
  EXPECT_EQ(options.max_features, 300);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{detector: brief}"), &options), LoadError);
  ReadOptions(OptionReader::FromString("{detector: surf, surf_hessian_threshold: 250, "
                                       "surf_octaves: 3, surf_intervals: 5, surf_upright: true}"),
              &options);
  EXPECT_EQ(options.detector, Detector::kSurf);
  EXPECT_DOUBLE_EQ(options.surf_hessian_threshold, 250.0);
  EXPECT_EQ(options.surf_octaves, 3);
  EXPECT_EQ(options.surf_intervals, 5);
  EXPECT_TRUE(options.surf_upright);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{surf_intervals: 2}"), &options), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{surf_octaves: 0}"), &options), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{max_features: 0}"), &options), LoadError);
}

}  // namespace
}  // namespace icgm

namespace icgm {
namespace {

TEST(PyramidPixelSigmaTest, GrowsWithTheOctave) {
  cv::KeyPoint k(10.f, 10.f, 31.f);
  k.octave = 0;
  EXPECT_DOUBLE_EQ(PyramidPixelSigma(k, 1.2), 1.0);
  k.octave = 3;
  EXPECT_NEAR(PyramidPixelSigma(k, 1.2), 1.728, 1e-12);
  EXPECT_DOUBLE_EQ(PyramidPixelSigma(k, 1.0), 1.0);  // a scale factor of 1 weighs all alike
  k.octave = -1;                                     // not a pyramid level
  EXPECT_DOUBLE_EQ(PyramidPixelSigma(k, 1.2), 1.0);
}

}  // namespace
}  // namespace icgm
