#include "core/place/geometric_verification.h"

#include <gtest/gtest.h>

#include "place_views.h"

namespace icgm {
namespace {

TEST(GeometricVerificationTest, SamePlaceFromAnotherPoseIsVerified) {
  test::PlaceViews places(3, 200, 7);
  const FeatureSet a = places.View(1, 0.0, 0.0);
  const FeatureSet b = places.View(1, 0.4, 0.15);
  GeometricVerificationOptions o;
  const GeometricCheck essential = VerifyGeometry(a, b, o, test::PlaceViews::Camera());
  EXPECT_TRUE(essential.status.ok()) << essential.status.reason();
  EXPECT_GE(essential.matches, 80);
  EXPECT_GE(essential.inliers, 0.9 * essential.matches) << "of " << essential.matches;
  const GeometricCheck fundamental = VerifyGeometry(a, b, o, std::nullopt);
  EXPECT_TRUE(fundamental.status.ok()) << fundamental.status.reason();
  EXPECT_GE(fundamental.inliers, 0.8 * fundamental.matches) << "of " << fundamental.matches;
}

TEST(GeometricVerificationTest, LookAlikeWithWrongGeometryIsRejected) {
  test::PlaceViews places(3, 200, 7);
  const FeatureSet a = places.View(1, 0.0, 0.0);
  const FeatureSet look_alike = places.LookAlike(1);
  GeometricVerificationOptions o;
  for (const auto& camera : {std::optional<CameraIntrinsics>(test::PlaceViews::Camera()),
                             std::optional<CameraIntrinsics>()}) {
    const GeometricCheck check = VerifyGeometry(a, look_alike, o, camera);
    // The descriptors match as well as a true revisit's ...
    EXPECT_GE(check.matches, 100);
    // ... but few of them fit one epipolar geometry.
    EXPECT_FALSE(check.status.ok()) << check.inliers << " inliers of " << check.matches;
    EXPECT_LT(check.inliers, o.min_inliers);
    EXPECT_NE(check.status.reason().find("inliers <"), std::string::npos) << check.status.reason();
  }
}

TEST(GeometricVerificationTest, DifferentPlaceHasTooFewMatches) {
  test::PlaceViews places(3, 200, 7);
  const GeometricCheck check = VerifyGeometry(places.View(0, 0.0, 0.0), places.View(2, 0.0, 0.0),
                                              GeometricVerificationOptions(), std::nullopt);
  EXPECT_FALSE(check.status.ok());
  EXPECT_LT(check.matches, 20);
  EXPECT_NE(check.status.reason().find("matches <"), std::string::npos) << check.status.reason();
}

}  // namespace
}  // namespace icgm
