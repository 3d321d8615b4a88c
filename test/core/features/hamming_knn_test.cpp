// The popcount Hamming search agrees with a bit-by-bit reference on random descriptors of
// several widths, including widths that are not a multiple of 8 bytes (AKAZE: 61).
#include "core/features/hamming_knn.h"

#include <gtest/gtest.h>

#include <climits>

namespace icgm {
namespace {

int ReferenceDistance(const cv::Mat& a, int i, const cv::Mat& b, int j) {
  int d = 0;
  for (int c = 0; c < a.cols; ++c) {
    const uint8_t x = a.at<uint8_t>(i, c) ^ b.at<uint8_t>(j, c);
    for (int bit = 0; bit < 8; ++bit) d += (x >> bit) & 1;
  }
  return d;
}

TEST(HammingKnnTest, MatchesBitwiseReference) {
  cv::RNG rng(5);
  for (const int width : {32, 61, 5, 64}) {
    cv::Mat train(150, width, CV_8UC1);
    cv::Mat query(40, width, CV_8UC1);
    rng.fill(train, cv::RNG::UNIFORM, 0, 256);
    rng.fill(query, cv::RNG::UNIFORM, 0, 256);
    // Plant near-copies so that the nearest neighbour is distinct and known.
    for (int q = 0; q < 20; ++q) {
      train.row(q * 7).copyTo(query.row(q));
      query.at<uint8_t>(q, q % width) ^= 0x01;
    }
    std::vector<HammingKnn2> knn;
    ASSERT_TRUE(HammingKnn2Search(query, train, &knn));
    ASSERT_EQ(knn.size(), 40u);
    for (int q = 0; q < query.rows; ++q) {
      int d1 = INT_MAX, d2 = INT_MAX;
      for (int t = 0; t < train.rows; ++t) {
        const int d = ReferenceDistance(query, q, train, t);
        if (d < d1) {
          d2 = d1;
          d1 = d;
        } else if (d < d2) {
          d2 = d;
        }
      }
      EXPECT_EQ(knn[q].best_distance, d1) << "width " << width;
      EXPECT_EQ(knn[q].second_distance, d2) << "width " << width;
      EXPECT_EQ(ReferenceDistance(query, q, train, knn[q].best), d1);
      if (q < 20) {
        EXPECT_EQ(knn[q].best, q * 7);
        EXPECT_EQ(knn[q].best_distance, 1);
      }
    }
  }
}

// Many rows at equal distances (a few distinct rows repeated): the lowest train row wins and
// the second distance equals the best, for train sizes around the eight-row steps.
TEST(HammingKnnTest, TiesKeepTheLowestRow) {
  cv::RNG rng(11);
  for (const int rows : {7, 8, 9, 16, 23, 64, 101}) {
    cv::Mat distinct(3, 32, CV_8UC1);
    rng.fill(distinct, cv::RNG::UNIFORM, 0, 256);
    cv::Mat train(rows, 32, CV_8UC1);
    for (int t = 0; t < rows; ++t) distinct.row((t * 5 + rows) % 3).copyTo(train.row(t));
    cv::Mat query(30, 32, CV_8UC1);
    rng.fill(query, cv::RNG::UNIFORM, 0, 256);
    for (int q = 0; q < 3; ++q) distinct.row(q).copyTo(query.row(q));
    std::vector<HammingKnn2> knn;
    ASSERT_TRUE(HammingKnn2Search(query, train, &knn));
    for (int q = 0; q < query.rows; ++q) {
      int d1 = INT_MAX, d2 = INT_MAX, best = -1;
      for (int t = 0; t < rows; ++t) {
        const int d = ReferenceDistance(query, q, train, t);
        if (d < d1) {
          d2 = d1;
          d1 = d;
          best = t;
        } else if (d < d2) {
          d2 = d;
        }
      }
      EXPECT_EQ(knn[q].best, best) << rows << " rows, query " << q;
      EXPECT_EQ(knn[q].best_distance, d1) << rows << " rows, query " << q;
      EXPECT_EQ(knn[q].second_distance, d2) << rows << " rows, query " << q;
    }
  }
}

TEST(HammingKnnTest, EdgeCases) {
  std::vector<HammingKnn2> knn;
  cv::Mat one(1, 32, CV_8UC1, cv::Scalar(0xAA));
  cv::Mat two(2, 32, CV_8UC1, cv::Scalar(0x55));
  ASSERT_TRUE(HammingKnn2Search(two, one, &knn));
  ASSERT_EQ(knn.size(), 2u);
  EXPECT_EQ(knn[0].best, 0);
  EXPECT_EQ(knn[0].best_distance, 256);
  EXPECT_EQ(knn[0].second_distance, INT_MAX);
  ASSERT_TRUE(HammingKnn2Search(two, cv::Mat(0, 32, CV_8UC1), &knn));
  EXPECT_EQ(knn[0].best, -1);
  EXPECT_FALSE(HammingKnn2Search(two, cv::Mat(2, 16, CV_8UC1), &knn));
  EXPECT_TRUE(knn.empty());
  EXPECT_FALSE(HammingKnn2Search(two, cv::Mat(2, 8, CV_32FC1), &knn));
}

}  // namespace
}  // namespace icgm
