// Ground-truth revisits on a hand-built trajectory (distance, viewing angle, frame gap, missing
// poses) and from a hand-built ground-truth matrix image.
#include "core/eval/place_truth.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

std::optional<Pose3> At(double x, double y, double yaw_deg) {
  Pose3 p = Pose3::Identity();
  p.translation() = Eigen::Vector3d(x, y, 0.0);
  p.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).matrix();
  return p;
}

// The tolerance band: pairs beyond the revisit bounds (0.25 m, 15 deg) but within the soft ones
// (0.5 m, 30 deg) are ambiguous, not revisits; pairs beyond the soft bounds stay different places.
TEST(PlaceTruthTest, ToleranceBandMarksNearMissesAmbiguous) {
  const std::vector<std::optional<Pose3>> poses = {
      At(0, 0, 0),      // 0
      At(3, 0, 0),      // 1: far away
      At(0.1, 0, 6),    // 2: 0.10 m, 6 deg from 0: a revisit
      At(0.3, 0, 0),    // 3: 0.30 m from 0 (band), 0.20 m / 6 deg from 2 (revisit)
      At(0.02, 0, 20),  // 4: turned 20 deg from 0 and 3 (band), 14 deg from 2 (revisit)
      std::nullopt,     // 5: no ground truth
      At(0.65, 0, 0),   // 6: 0.35 m from 3 (band), 0.55 m from 2 and 0.65 m from 0 (beyond)
      At(0.2, 0, 40),   // 7: 20 deg from 4 (band), 34-40 deg from the others (beyond)
  };
  RevisitCriterion criterion;
  criterion.max_distance_m = 0.25;
  criterion.max_angle_deg = 15.0;
  const PlaceTruth strict = RevisitsFromPoses(poses, criterion);
  EXPECT_EQ(strict.NumAmbiguousPairs(), 0);
  criterion.soft_max_distance_m = 0.5;
  criterion.soft_max_angle_deg = 30.0;
  const PlaceTruth truth = RevisitsFromPoses(poses, criterion);
  // The strict revisits do not change.
  EXPECT_EQ(truth.same_place, strict.same_place);
  EXPECT_EQ(truth.same_place[2], std::vector<int>({0}));
  EXPECT_EQ(truth.same_place[3], std::vector<int>({2}));
  EXPECT_EQ(truth.same_place[4], std::vector<int>({2}));
  EXPECT_EQ(truth.ambiguous[3], std::vector<int>({0}));
  EXPECT_EQ(truth.ambiguous[4], std::vector<int>({0, 3}));
  EXPECT_TRUE(truth.ambiguous[5].empty());
  EXPECT_EQ(truth.ambiguous[6], std::vector<int>({3}));
  EXPECT_TRUE(truth.same_place[6].empty());
  EXPECT_EQ(truth.ambiguous[7], std::vector<int>({4}));
  EXPECT_EQ(truth.NumAmbiguousPairs(), 5);
  EXPECT_TRUE(truth.Ambiguous(6, 3));
  EXPECT_FALSE(truth.Judged(6, 3));
  EXPECT_TRUE(truth.Judged(6, 0));   // beyond the band: a false loop if claimed
  EXPECT_TRUE(truth.Judged(3, 2));   // a revisit
  EXPECT_FALSE(truth.Judged(6, 5));  // no ground truth
  // A soft bound below the strict one is the strict one: no band on that axis.
  criterion.soft_max_angle_deg = 10.0;
  const PlaceTruth distance_only = RevisitsFromPoses(poses, criterion);
  EXPECT_EQ(distance_only.ambiguous[3], std::vector<int>({0}));
  EXPECT_EQ(distance_only.ambiguous[6], std::vector<int>({3}));
  EXPECT_TRUE(distance_only.ambiguous[4].empty());
  EXPECT_TRUE(distance_only.ambiguous[7].empty());
}

TEST(PlaceTruthTest, RevisitsFromHandBuiltTrajectory) {
  // A loop around a 2 m square coming back to its start, then a turn on the spot.
  const std::vector<std::optional<Pose3>> poses = {
      At(0, 0, 0),        // 0
      At(1, 0, 0),        // 1
      At(2, 0, 90),       // 2
      At(2, 2, 180),      // 3
      At(0, 2, 270),      // 4
      At(0.1, 0.2, 350),  // 5: 0.22 m and 10 degrees from 0
      At(0.1, 0.2, 260),  // 6: at 0 and 5 but turned 100 / 90 degrees: a different view
      std::nullopt,       // 7: no ground truth
      At(1.3, 0.1, 10),   // 8: 0.32 m, 10 degrees from 1
      At(1.3, 0.1, 10),   // 9: same pose as 8
  };
  RevisitCriterion criterion;
  criterion.max_distance_m = 0.5;
  criterion.max_angle_deg = 30.0;
  criterion.min_frame_gap = 1;
  PlaceTruth truth = RevisitsFromPoses(poses, criterion);
  ASSERT_EQ(truth.num_frames(), 10);
  EXPECT_EQ(truth.NumUnknown(), 1);
  EXPECT_FALSE(truth.Known(7));
  EXPECT_TRUE(truth.Known(6));
  EXPECT_EQ(truth.same_place[5], std::vector<int>({0}));
  EXPECT_TRUE(truth.same_place[6].empty());
  EXPECT_TRUE(truth.same_place[7].empty());
  EXPECT_EQ(truth.same_place[8], std::vector<int>({1}));
  EXPECT_EQ(truth.same_place[9], std::vector<int>({1, 8}));
  for (int i : {0, 1, 2, 3, 4}) EXPECT_TRUE(truth.same_place[i].empty()) << i;
  EXPECT_EQ(truth.NumRevisits(), 3);
  EXPECT_TRUE(truth.SamePlace(9, 8));
  EXPECT_FALSE(truth.SamePlace(9, 0));
  EXPECT_FALSE(truth.IsRevisit(6));
  EXPECT_FALSE(truth.IsRevisit(42));

  // Frames less than 2 apart do not count: 9 loses 8.
  criterion.min_frame_gap = 2;
  truth = RevisitsFromPoses(poses, criterion);
  EXPECT_EQ(truth.same_place[9], std::vector<int>({1}));
  // A tighter distance drops 8 and 9 (0.32 m from 1); a tighter angle drops 5 (10 degrees).
  criterion.max_distance_m = 0.3;
  EXPECT_EQ(RevisitsFromPoses(poses, criterion).NumRevisits(), 1);
  criterion.max_angle_deg = 5.0;
  EXPECT_EQ(RevisitsFromPoses(poses, criterion).NumRevisits(), 0);
}

TEST(PlaceTruthTest, FromMatrixImage) {
  cv::Mat m = cv::Mat::zeros(6, 6, CV_8U);
  m.at<uchar>(3, 1) = 255;  // lower triangle
  m.at<uchar>(0, 4) = 1;    // upper triangle counts the same
  m.at<uchar>(2, 2) = 255;  // a frame with itself is never a revisit
  m.at<uchar>(5, 4) = 255;  // consecutive frames
  PlaceTruth truth;
  ASSERT_TRUE(PlaceTruthFromMatrix(m, 6, 1, &truth).ok());
  EXPECT_EQ(truth.same_place[3], std::vector<int>({1}));
  EXPECT_EQ(truth.same_place[4], std::vector<int>({0}));
  EXPECT_EQ(truth.same_place[5], std::vector<int>({4}));
  EXPECT_TRUE(truth.same_place[2].empty());
  EXPECT_EQ(truth.NumRevisits(), 3);
  // With a gap of 2 the consecutive pair goes.
  ASSERT_TRUE(PlaceTruthFromMatrix(m, 6, 2, &truth).ok());
  EXPECT_EQ(truth.NumRevisits(), 2);
  // Colour images: any channel.
  cv::Mat colour = cv::Mat::zeros(6, 6, CV_8UC3);
  colour.at<cv::Vec3b>(3, 1) = cv::Vec3b(0, 0, 9);
  ASSERT_TRUE(PlaceTruthFromMatrix(colour, 6, 1, &truth).ok());
  EXPECT_EQ(truth.same_place[3], std::vector<int>({1}));
  EXPECT_EQ(truth.NumRevisits(), 1);
  // Smaller than the sequence: an error naming the sizes.
  const Status s = PlaceTruthFromMatrix(m, 7, 1, &truth);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("6x6"), std::string::npos) << s.reason();
  EXPECT_FALSE(PlaceTruthFromMatrix(cv::Mat(), 1, 1, &truth).ok());
}

}  // namespace
}  // namespace icgm
