#include "core/odometry/anchor_keyframes.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

// A chained estimate that drifted 4 cm sideways and 2 deg in pan from the anchor's estimate.
Pose3 Drifted() {
  Pose3 p = Pose3::Identity();
  p.translate(Vec3(0.04, 0.0, 0.0));
  p.rotate(Eigen::AngleAxisd(2.0 * M_PI / 180.0, Vec3::UnitY()));
  return p;
}

TEST(AnchorKeyframesTest, MovesTheShareOfTheWayTowardsTheAnchor) {
  const Pose3 chained = Drifted(), anchored = Pose3::Identity();
  AnchorOptions options;
  options.gain = 0.25;
  const AnchorCorrection r = CorrectByAnchor(chained, anchored, 100, options);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  EXPECT_NEAR(RotationAngleRad(Between(chained, r.odom_camera)) * 180.0 / M_PI, 0.5, 1e-6);
  EXPECT_NEAR(RotationAngleRad(Between(anchored, r.odom_camera)) * 180.0 / M_PI, 1.5, 1e-6);
  EXPECT_NEAR(TranslationNorm(Between(anchored, r.odom_camera)), 0.75 * 0.04, 1e-3);
  // Gain 1: the anchor's estimate; gain 0: the chained one.
  options.gain = 1.0;
  EXPECT_TRUE(CorrectByAnchor(chained, anchored, 100, options).odom_camera.isApprox(anchored));
  options.gain = 0.0;
  EXPECT_TRUE(CorrectByAnchor(chained, anchored, 100, options).odom_camera.isApprox(chained));
}

TEST(AnchorKeyframesTest, RefusedWithReasons) {
  const Pose3 chained = Drifted(), anchored = Pose3::Identity();
  AnchorOptions options;
  options.min_inliers = 40;
  AnchorCorrection r = CorrectByAnchor(chained, anchored, 12, options);
  EXPECT_FALSE(r.status.ok());
  EXPECT_NE(r.status.reason().find("12 inliers < 40"), std::string::npos) << r.status.reason();
  EXPECT_TRUE(r.odom_camera.isApprox(chained));
  options.max_correction_deg = 1.5;
  r = CorrectByAnchor(chained, anchored, 100, options);
  EXPECT_FALSE(r.status.ok());
  EXPECT_NE(r.status.reason().find("beyond"), std::string::npos) << r.status.reason();
  options.max_correction_deg = 2.5;
  EXPECT_TRUE(CorrectByAnchor(chained, anchored, 100, options).status.ok());
  options.max_correction_m = 0.03;
  EXPECT_FALSE(CorrectByAnchor(chained, anchored, 100, options).status.ok());
}

TEST(AnchorKeyframesTest, AnchorsAreTheFirstWellSupportedKeyframes) {
  AnchorOptions options;
  EXPECT_FALSE(QualifiesAsAnchor(options, 0, nullptr));  // off
  options.keyframes = 2;
  options.keyframe_min_inliers = 150;
  EXPECT_TRUE(QualifiesAsAnchor(options, 0, nullptr));  // the run's first keyframe
  const int many = 180, few = 90;
  EXPECT_TRUE(QualifiesAsAnchor(options, 1, &many));
  EXPECT_FALSE(QualifiesAsAnchor(options, 1, &few));
  EXPECT_FALSE(QualifiesAsAnchor(options, 2, &many));  // full
  EXPECT_FALSE(QualifiesAsAnchor(options, 1, nullptr));
}

}  // namespace
}  // namespace icgm
