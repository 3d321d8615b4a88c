#include "core/map/visual_dictionary.h"

#include <gtest/gtest.h>

#include <random>

#include "synthetic_places.h"

namespace icgm {
namespace {

TEST(VisualDictionaryTest, RevisitScoresTheSamePlaceHighestAndNewPlacesLow) {
  test::SyntheticPlaces places(60, 150, 7);
  VisualDictionary dict(DictionaryOptions{});
  // First traversal: 50 places.
  for (int p = 0; p < 50; ++p) ASSERT_TRUE(dict.Add(p, places.View(p, 0.9, 4)));
  const int words_after_first = dict.num_words();
  EXPECT_GE(words_after_first, 50 * 120);
  // Revisit with noisy descriptors: the same place ranks first with a high score.
  for (int p = 0; p < 50; p += 7) {
    std::vector<DictionaryMatch> matches;
    ASSERT_TRUE(dict.Query(places.View(p, 0.8, 8), &matches));
    ASSERT_FALSE(matches.empty());
    EXPECT_EQ(matches.front().keyframe_id, p);
    EXPECT_GT(matches.front().score, 0.5);
    if (matches.size() > 1) {
      EXPECT_LT(matches[1].score, 0.1);
    }
  }
  // Places never seen score low everywhere.
  for (int p = 50; p < 60; ++p) {
    std::vector<DictionaryMatch> matches;
    ASSERT_TRUE(dict.Query(places.View(p, 0.9, 4), &matches));
    for (const auto& m : matches) EXPECT_LT(m.score, 0.1);
  }
  // Adding a revisit reuses words instead of growing the vocabulary much.
  ASSERT_TRUE(dict.Add(100, places.View(3, 0.9, 6)));
  EXPECT_LT(dict.num_words() - words_after_first, 20);
  EXPECT_GT(dict.MemoryBytes(), 0u);
}

TEST(VisualDictionaryTest, NearDuplicatesInOneKeyframeShareAWord) {
  VisualDictionary dict(DictionaryOptions{});
  cv::Mat d(2, 32, CV_8U, cv::Scalar(0x55));
  d.at<uint8_t>(1, 0) = 0x54;  // one bit apart
  WordAssignment words;
  ASSERT_TRUE(dict.Add(0, d, &words));
  ASSERT_EQ(words.size(), 2u);
  EXPECT_EQ(words[0], words[1]);
  EXPECT_EQ(dict.num_words(), 1);
}

TEST(VisualDictionaryTest, FloatDescriptorsUseL2) {
  DictionaryOptions options;
  options.descriptor_type = DescriptorType::kFloat;
  options.new_word_distance_l2 = 0.2;
  options.coarse_cells = 16;
  options.probe_cells = 4;
  VisualDictionary dict(options);
  std::mt19937 rng(1);
  std::normal_distribution<float> n(0.f, 1.f);
  std::vector<cv::Mat> places;
  for (int p = 0; p < 20; ++p) {
    cv::Mat m(80, 64, CV_32F);
    for (int i = 0; i < m.rows * m.cols; ++i) m.at<float>(i / 64, i % 64) = n(rng);
    places.push_back(m);
    ASSERT_TRUE(dict.Add(p, m));
  }
  cv::Mat noisy = places[12].clone();
  for (int i = 0; i < noisy.rows * noisy.cols; ++i)
    noisy.at<float>(i / 64, i % 64) += 0.005f * n(rng);
  std::vector<DictionaryMatch> matches;
  ASSERT_TRUE(dict.Query(noisy, &matches));
  ASSERT_FALSE(matches.empty());
  EXPECT_EQ(matches.front().keyframe_id, 12);
  EXPECT_GT(matches.front().score, 0.9);
}

TEST(VisualDictionaryTest, ReplayingRecordedWordsRebuildsTheSameDictionary) {
  test::SyntheticPlaces places(30, 100, 9);
  VisualDictionary original(DictionaryOptions{});
  VisualDictionary replayed(DictionaryOptions{});
  for (int k = 0; k < 40; ++k) {
    const cv::Mat d = places.View(k % 30, 0.9, 5);
    WordAssignment words;
    ASSERT_TRUE(original.Add(k, d, &words));
    ASSERT_TRUE(replayed.AddAssigned(k, d, words));
  }
  EXPECT_EQ(replayed.num_words(), original.num_words());
  for (int p = 0; p < 30; p += 4) {
    const cv::Mat q = places.View(p, 0.8, 6);
    std::vector<DictionaryMatch> a;
    std::vector<DictionaryMatch> b;
    ASSERT_TRUE(original.Query(q, &a));
    ASSERT_TRUE(replayed.Query(q, &b));
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].keyframe_id, b[i].keyframe_id);
      EXPECT_EQ(a[i].score, b[i].score);
    }
  }
  // An assignment that skips a word id, or has the wrong length, is refused without change.
  const cv::Mat d = places.View(0, 1.0, 0);
  WordAssignment bad(static_cast<size_t>(d.rows), replayed.num_words() + 1);
  EXPECT_FALSE(replayed.AddAssigned(100, d, bad).ok());
  EXPECT_FALSE(replayed.AddAssigned(100, d, WordAssignment(2, 0)).ok());
  EXPECT_EQ(replayed.num_words(), original.num_words());
  EXPECT_EQ(replayed.num_keyframes(), 40);
}

// SIFT rows as OpenCV computes them: non-negative, norm 512. Revisits add a little noise.
TEST(VisualDictionaryTest, SiftScaledDescriptorsRecognizePlacesOnlyWhenNormalised) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::normal_distribution<float> noise(0.f, 0.01f);
  auto sift_rows = [&](const cv::Mat& unit, bool noisy) {
    cv::Mat out = unit.clone();
    for (int r = 0; r < out.rows; ++r) {
      for (int c = 0; c < out.cols; ++c) {
        if (noisy) out.at<float>(r, c) = std::max(0.f, out.at<float>(r, c) + noise(rng));
      }
      out.row(r) *= 512.0 / cv::norm(out.row(r));
    }
    return out;
  };
  std::vector<cv::Mat> places;
  for (int p = 0; p < 10; ++p) {
    cv::Mat m(100, 128, CV_32F);
    for (int i = 0; i < m.rows * m.cols; ++i) m.at<float>(i / 128, i % 128) = u(rng);
    places.push_back(m);
  }
  for (const bool normalize : {true, false}) {
    DictionaryOptions options;
    options.descriptor_type = DescriptorType::kFloat;
    options.normalize_float_descriptors = normalize;
    options.coarse_cells = 16;
    VisualDictionary dict(options);
    for (int p = 0; p < 10; ++p) ASSERT_TRUE(dict.Add(p, sift_rows(places[p], false)));
    std::vector<DictionaryMatch> matches;
    ASSERT_TRUE(dict.Query(sift_rows(places[6], true), &matches));
    if (normalize) {
      EXPECT_EQ(dict.num_words(), 1000);
      ASSERT_FALSE(matches.empty());
      EXPECT_EQ(matches.front().keyframe_id, 6);
      EXPECT_GT(matches.front().score, 0.8);
    } else {
      // new_word_distance_l2 = 0.3 on rows of norm 512: no revisit ever finds its word.
      EXPECT_TRUE(matches.empty());
    }
  }
}

// Weights: all 1 gives the unweighted score; a query's low-weight rows count less.
TEST(VisualDictionaryTest, WeightsOfOneGiveTheUnweightedScoreAndLowWeightsCountLess) {
  test::SyntheticPlaces places(12, 100, 5);
  VisualDictionary plain(DictionaryOptions{});
  VisualDictionary weighted(DictionaryOptions{});
  for (int k = 0; k < 12; ++k) {
    const cv::Mat d = places.View(k, 0.9, 3);
    const std::vector<float> ones(static_cast<size_t>(d.rows), 1.f);
    ASSERT_TRUE(plain.Add(k, d));
    ASSERT_TRUE(weighted.Add(k, d, nullptr, nullptr, &ones));
  }
  // Query: half of place 3's view, half of place 9's.
  cv::Mat a = places.View(3, 0.5, 3), b = places.View(9, 0.5, 3);
  cv::Mat q;
  cv::vconcat(a, b, q);
  WordAssignment words;
  ASSERT_TRUE(plain.Quantize(q, &words));
  const auto unweighted = plain.Score(words);
  std::vector<float> w(static_cast<size_t>(q.rows), 1.f);
  const auto ones = weighted.Score(words, 0, &w);
  ASSERT_EQ(unweighted.size(), ones.size());
  for (size_t i = 0; i < ones.size(); ++i) {
    EXPECT_EQ(ones[i].keyframe_id, unweighted[i].keyframe_id);
    EXPECT_NEAR(ones[i].score, unweighted[i].score, 1e-9);
  }
  // Place 9's rows at weight 0.2: place 3 ranks first, whichever ranked first before.
  for (int r = a.rows; r < q.rows; ++r) w[static_cast<size_t>(r)] = 0.2f;
  const auto low9 = weighted.Score(words, 0, &w);
  ASSERT_FALSE(low9.empty());
  EXPECT_EQ(low9.front().keyframe_id, 3);
  for (int r = 0; r < q.rows; ++r) w[static_cast<size_t>(r)] = r < a.rows ? 0.2f : 1.f;
  const auto low3 = weighted.Score(words, 0, &w);
  ASSERT_FALSE(low3.empty());
  EXPECT_EQ(low3.front().keyframe_id, 9);
  for (const auto& m : low3) EXPECT_LE(m.score, 1.0 + 1e-12);
}

// The weighted score is a cosine: scaling every weight of the query, or of a keyframe, alike
// changes no score (an image whose features all weigh 0.9 scores as with weights of 1).
TEST(VisualDictionaryTest, ScoresIgnoreAUniformScaleOfAnImagesWeights) {
  test::SyntheticPlaces places(8, 100, 5);
  VisualDictionary ones(DictionaryOptions{});
  VisualDictionary scaled(DictionaryOptions{});
  for (int k = 0; k < 8; ++k) {
    const cv::Mat d = places.View(k, 0.9, 3);
    const std::vector<float> one(static_cast<size_t>(d.rows), 1.f);
    const std::vector<float> part(static_cast<size_t>(d.rows), k % 2 ? 0.9f : 0.4f);
    ASSERT_TRUE(ones.Add(k, d, nullptr, nullptr, &one));
    ASSERT_TRUE(scaled.Add(k, d, nullptr, nullptr, &part));
  }
  const cv::Mat q = places.View(5, 0.6, 3);
  WordAssignment words;
  ASSERT_TRUE(ones.Quantize(q, &words));
  const std::vector<float> one(static_cast<size_t>(q.rows), 1.f);
  const std::vector<float> part(static_cast<size_t>(q.rows), 0.7f);
  const auto a = ones.Score(words, 0, &one);
  const auto b = scaled.Score(words, 0, &part);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a.front().keyframe_id, 5);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].keyframe_id, b[i].keyframe_id);
    EXPECT_NEAR(a[i].score, b[i].score, 1e-6);
  }
}

TEST(VisualDictionaryTest, BadInputIsAnErrorWithReason) {
  VisualDictionary dict(DictionaryOptions{});
  ASSERT_TRUE(dict.Add(5, cv::Mat(3, 32, CV_8U, cv::Scalar(1))));
  const Status wrong_type = dict.Add(6, cv::Mat(3, 32, CV_32F, cv::Scalar(1)));
  EXPECT_FALSE(wrong_type.ok());
  EXPECT_NE(wrong_type.reason().find("CV_8U"), std::string::npos);
  EXPECT_FALSE(dict.Add(7, cv::Mat(3, 16, CV_8U, cv::Scalar(1))).ok());
  EXPECT_FALSE(dict.Add(5, cv::Mat(3, 32, CV_8U, cv::Scalar(1))).ok());  // id not increasing
  std::vector<DictionaryMatch> matches;
  EXPECT_FALSE(dict.Query(cv::Mat(2, 16, CV_8U, cv::Scalar(0)), &matches).ok());
  EXPECT_TRUE(dict.Query(cv::Mat(), &matches).ok());
  EXPECT_TRUE(matches.empty());
}

}  // namespace
}  // namespace icgm
