// Precision and recall on hand-built score lists with answers worked out by hand, and the plot.
#include "core/eval/precision_recall.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "core/eval/precision_recall_plot.h"

namespace icgm {
namespace {

// Frames 0..6; 3, 4, 5 and 6 are revisits.
PlaceTruth HandTruth() {
  PlaceTruth t;
  t.same_place = {{}, {}, {}, {0}, {1}, {2}, {0, 1}};
  return t;
}

std::vector<PlaceQuery> HandQueries() {
  return {
      {0, -1, 0.0},  // first frame: no candidate
      {1, 0, 0.1},   // not a revisit: false positive whenever accepted
      {2, -1, 0.0},  // no candidate
      {3, 0, 0.9},   // true
      {4, 2, 0.8},   // wrong place: false
      {5, 2, 0.7},   // true
      {6, 1, 0.95},  // true (either 0 or 1)
  };
}

TEST(PrecisionRecallTest, SweepMatchesHandComputedCurve) {
  const PrecisionRecallCurve c = SweepPrecisionRecall(HandQueries(), HandTruth());
  EXPECT_EQ(c.revisits, 4);
  EXPECT_EQ(c.queries, 7);
  ASSERT_EQ(c.points.size(), 5u);
  const double thresholds[] = {0.95, 0.9, 0.8, 0.7, 0.1};
  const int tp[] = {1, 2, 2, 3, 3};
  const int fp[] = {0, 0, 1, 1, 2};
  const double precision[] = {1.0, 1.0, 2.0 / 3.0, 0.75, 0.6};
  const double recall[] = {0.25, 0.5, 0.5, 0.75, 0.75};
  for (size_t k = 0; k < 5; ++k) {
    EXPECT_DOUBLE_EQ(c.points[k].threshold, thresholds[k]) << k;
    EXPECT_EQ(c.points[k].true_positives, tp[k]) << k;
    EXPECT_EQ(c.points[k].false_positives, fp[k]) << k;
    EXPECT_NEAR(c.points[k].precision, precision[k], 1e-12) << k;
    EXPECT_NEAR(c.points[k].recall, recall[k], 1e-12) << k;
  }
  EXPECT_DOUBLE_EQ(c.recall_at_full_precision, 0.5);
  EXPECT_DOUBLE_EQ(c.threshold_at_full_precision, 0.9);
}

// A frame without ground truth (a gap in the motion capture) makes its loops unknown: neither
// true nor false, at one threshold and along the curve. Frame 2 unknown: query 4's loop to it
// (wrong place in HandTruth) and query 5's (right place) no longer count; queries 3 and 6 stay.
// Query 4 is a revisit (of frame 1) whose loop goes to the unknown frame: whether it found its
// place cannot be judged, so it is neither found nor missed (it leaves recall's revisits
// wherever its loop is accepted); where its loop is not accepted it is a miss.
TEST(PrecisionRecallTest, LoopsOfFramesWithoutGroundTruthCountNeitherWay) {
  PlaceTruth truth = HandTruth();
  truth.same_place[5].clear();  // frame 5's place is frame 2's, unknown
  truth.unknown = {0, 0, 1, 0, 0, 0, 0};
  EXPECT_EQ(truth.NumUnknown(), 1);
  EXPECT_EQ(truth.NumRevisits(), 3);  // 3, 4, 6
  const PrecisionRecallPoint at = EvaluateAtThreshold(HandQueries(), truth, 0.05);
  EXPECT_EQ(at.true_positives, 2);   // 3 -> 0, 6 -> 1
  EXPECT_EQ(at.false_positives, 1);  // 1 -> 0 only; 4 -> 2 is unknown
  EXPECT_EQ(at.undetermined, 1);     // 4 -> 2
  EXPECT_DOUBLE_EQ(at.recall, 1.0);  // 2 of the 2 judged revisits
  // Above query 4's score (0.8) it claims nothing: a revisit missed.
  const PrecisionRecallPoint high = EvaluateAtThreshold(HandQueries(), truth, 0.85);
  EXPECT_EQ(high.undetermined, 0);
  EXPECT_DOUBLE_EQ(high.recall, 2.0 / 3.0);
  const PrecisionRecallCurve curve = SweepPrecisionRecall(HandQueries(), truth);
  // Scores 0.95 (true), 0.9 (true), 0.8 (query 4: undetermined), 0.1 (false).
  ASSERT_EQ(curve.points.size(), 4u);
  EXPECT_DOUBLE_EQ(curve.points[1].recall, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(curve.points[2].recall, 1.0);
  EXPECT_EQ(curve.points[2].undetermined, 1);
  EXPECT_DOUBLE_EQ(curve.recall_at_full_precision, 1.0);
  EXPECT_DOUBLE_EQ(curve.threshold_at_full_precision, 0.8);
  // Without the mark the two loops to frame 2 count as false, query 4 as missed.
  PlaceTruth known = truth;
  known.unknown.clear();
  const PrecisionRecallPoint judged = EvaluateAtThreshold(HandQueries(), known, 0.05);
  EXPECT_EQ(judged.false_positives, 3);
  EXPECT_EQ(judged.undetermined, 0);
  EXPECT_DOUBLE_EQ(judged.recall, 2.0 / 3.0);
}

// A revisit's loop into the tolerance band stays a miss (the band lies beyond the revisit
// bounds; only an unknown frame leaves the revisit undetermined), and a query without ground
// truth is no revisit whatever it claims.
TEST(PrecisionRecallTest, OnlyALoopToAFrameWithoutGroundTruthLeavesRecall) {
  PlaceTruth truth = HandTruth();
  truth.ambiguous = {{}, {}, {}, {}, {2}, {}, {}};
  const PrecisionRecallPoint band = EvaluateAtThreshold(HandQueries(), truth, 0.05);
  EXPECT_EQ(band.undetermined, 0);
  EXPECT_DOUBLE_EQ(band.recall, 0.75);
  PlaceTruth query_unknown = HandTruth();
  query_unknown.same_place[4].clear();
  query_unknown.unknown = {0, 0, 0, 0, 1, 0, 0};
  const PrecisionRecallPoint at = EvaluateAtThreshold(HandQueries(), query_unknown, 0.05);
  EXPECT_EQ(at.undetermined, 0);
  EXPECT_EQ(at.false_positives, 1);  // 1 -> 0; 4 -> 2 counts neither way
  EXPECT_DOUBLE_EQ(at.recall, 1.0);  // 3, 5, 6 of revisits 3, 5, 6
}

// A loop into the tolerance band counts neither way. Query 4's loop to frame 2 (false in
// HandTruth) marked ambiguous: at 0.05 one false loop less; along the curve the best scores run
// 0.95, 0.9 (true), 0.7 (true), 0.1 (false), so recall at 100 % precision rises from 0.5 to 0.75.
TEST(PrecisionRecallTest, LoopsIntoTheToleranceBandCountNeitherWay) {
  PlaceTruth truth = HandTruth();
  truth.ambiguous = {{}, {}, {}, {}, {2}, {}, {}};
  EXPECT_EQ(truth.NumAmbiguousPairs(), 1);
  const PrecisionRecallPoint at = EvaluateAtThreshold(HandQueries(), truth, 0.05);
  EXPECT_EQ(at.true_positives, 3);
  EXPECT_EQ(at.false_positives, 1);   // 1 -> 0
  EXPECT_DOUBLE_EQ(at.recall, 0.75);  // query 4 is still a revisit not recalled
  const PrecisionRecallCurve curve = SweepPrecisionRecall(HandQueries(), truth);
  EXPECT_DOUBLE_EQ(curve.recall_at_full_precision, 0.75);
  EXPECT_DOUBLE_EQ(curve.threshold_at_full_precision, 0.7);
  EXPECT_DOUBLE_EQ(SweepPrecisionRecall(HandQueries(), HandTruth()).recall_at_full_precision, 0.5);
}

TEST(PrecisionRecallTest, SingleThresholdAgreesWithSweep) {
  const PrecisionRecallPoint p = EvaluateAtThreshold(HandQueries(), HandTruth(), 0.75);
  EXPECT_EQ(p.true_positives, 2);
  EXPECT_EQ(p.false_positives, 1);
  EXPECT_NEAR(p.precision, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(p.recall, 0.5, 1e-12);
  // Above every score nothing is claimed: precision 1 by convention, recall 0.
  const PrecisionRecallPoint none = EvaluateAtThreshold(HandQueries(), HandTruth(), 2.0);
  EXPECT_EQ(none.true_positives + none.false_positives, 0);
  EXPECT_DOUBLE_EQ(none.precision, 1.0);
  EXPECT_DOUBLE_EQ(none.recall, 0.0);
}

TEST(PrecisionRecallTest, TiedScoresShareOneThreshold) {
  const std::vector<PlaceQuery> q = {{3, 0, 0.5}, {4, 2, 0.5}, {5, 2, 0.4}};
  const PrecisionRecallCurve c = SweepPrecisionRecall(q, HandTruth());
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[0].true_positives, 1);
  EXPECT_EQ(c.points[0].false_positives, 1);
  // The first threshold already has a false positive: no recall at 100 % precision.
  EXPECT_DOUBLE_EQ(c.recall_at_full_precision, 0.0);
  EXPECT_TRUE(std::isinf(c.threshold_at_full_precision));
}

TEST(PrecisionRecallTest, PerfectRecognizerAndEmptyInput) {
  const std::vector<PlaceQuery> q = {{3, 0, 0.3}, {4, 1, 0.2}, {5, 2, 0.9}, {6, 0, 0.4}};
  const PrecisionRecallCurve c = SweepPrecisionRecall(q, HandTruth());
  EXPECT_DOUBLE_EQ(c.recall_at_full_precision, 1.0);
  EXPECT_DOUBLE_EQ(c.threshold_at_full_precision, 0.2);
  const PrecisionRecallCurve empty = SweepPrecisionRecall({}, HandTruth());
  EXPECT_TRUE(empty.points.empty());
  EXPECT_DOUBLE_EQ(empty.recall_at_full_precision, 0.0);
}

TEST(PrecisionRecallPlotTest, DrawsCurveAndWritesPng) {
  const PrecisionRecallCurve c = SweepPrecisionRecall(HandQueries(), HandTruth());
  const cv::Mat img = RenderPrecisionRecallPlot(c, "hand-built", 640);
  ASSERT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(img.cols, 640);
  // The curve colour (blue) is drawn.
  cv::Mat blue;
  cv::inRange(img, cv::Scalar(150, 90, 0), cv::Scalar(210, 150, 60), blue);
  EXPECT_GT(cv::countNonZero(blue), 100);
  const std::string path =
      (std::filesystem::temp_directory_path() / "icgm_pr_plot_test.png").string();
  ASSERT_TRUE(WritePrecisionRecallPlot(path, c, "hand-built").ok());
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
  std::filesystem::remove(path);
  EXPECT_FALSE(WritePrecisionRecallPlot("/nonexistent_dir/x.png", c, "x").ok());
}

}  // namespace
}  // namespace icgm
