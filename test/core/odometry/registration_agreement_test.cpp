#include "core/odometry/registration_agreement.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

// A camera 3 m from a wall, turned 5 deg about y; registrations of it a few mm apart.
Pose3 TruePose() {
  return MakePose(Vec3(0.4, -0.1, 1.2), Quat(Eigen::AngleAxisd(5.0 * M_PI / 180.0, Vec3::UnitY())));
}
Pose3 Moved(const Pose3& p, const Vec3& camera_frame_m, double yaw_deg = 0.0) {
  return p * MakePose(camera_frame_m, Quat(Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Vec3::UnitY())));
}
// Claimed covariance: 1 mm and 0.05 deg (what a registration with many inliers claims).
Mat6 Claimed(double scale = 1.0) {
  Mat6 c = Mat6::Zero();
  const double r = 0.05 * M_PI / 180.0;
  c.diagonal() << 1e-6, 1e-6, 1e-6, r * r, r * r, r * r;
  return c * scale;
}
// The comparison when the registrations agree, else nullopt.
std::optional<RegistrationAgreement> Agreeing(const std::vector<PoseLink>& links,
                                              const RegistrationAgreementOptions& options) {
  std::optional<RegistrationAgreement> a = CompareRegistrations(links, options);
  if (a && !a->agree) return std::nullopt;
  return a;
}
RegistrationAgreementOptions Options() {
  RegistrationAgreementOptions o;
  o.covariance_scale = 10.0;
  o.spread_weight = 1.0;
  o.max_m = 0.01;
  o.max_deg = 0.5;
  return o;
}

// Two registrations 4 mm apart along x, equally certain: they agree; the mean lies between them
// and the covariance is the combined claim x 10 plus their spread along x (a 4 mm gap: sample
// variance 2 * (2 mm)^2), nothing added along y and z.
TEST(RegistrationAgreementTest, AgreeingRegistrationsGiveTheirMeanAndSpread) {
  const Pose3 truth = TruePose();
  const std::vector<PoseLink> links = {{Moved(truth, Vec3(0.002, 0, 0)), Claimed()},
                                       {Moved(truth, Vec3(-0.002, 0, 0)), Claimed()}};
  const std::optional<RegistrationAgreement> a = Agreeing(links, Options());
  ASSERT_TRUE(a.has_value());
  EXPECT_LT(TranslationNorm(Between(truth, a->mean)), 1e-9);
  EXPECT_NEAR(a->spread_m, 0.002, 1e-9);
  EXPECT_NEAR(a->spread_deg, 0.0, 1e-9);
  EXPECT_NEAR(a->covariance(0, 0), 10.0 * 0.5e-6 + 2.0 * 0.002 * 0.002, 1e-12);
  EXPECT_NEAR(a->covariance(1, 1), 10.0 * 0.5e-6, 1e-12);
  EXPECT_NEAR(a->covariance(2, 2), 10.0 * 0.5e-6, 1e-12);
  // The more certain registration pulls the mean: claims 1 and 4 times the variance.
  const std::vector<PoseLink> unequal = {{Moved(truth, Vec3(0.002, 0, 0)), Claimed()},
                                         {Moved(truth, Vec3(-0.002, 0, 0)), Claimed(4.0)}};
  const std::optional<RegistrationAgreement> u = Agreeing(unequal, Options());
  ASSERT_TRUE(u.has_value());
  EXPECT_NEAR(Between(truth, u->mean).translation().x(), 0.002 * (1.0 - 0.25) / 1.25, 1e-6);
  // Without a spread weight only the scaled claim remains.
  RegistrationAgreementOptions no_spread = Options();
  no_spread.spread_weight = 0.0;
  EXPECT_NEAR(Agreeing(links, no_spread)->covariance(0, 0), 10.0 * 0.5e-6, 1e-12);
}

// Registrations 3 cm apart (one followed a walker) or 1.2 deg apart do not agree; one registration
// alone, or fewer than min_registrations, cannot; a covariance that is no covariance neither.
TEST(RegistrationAgreementTest, PartedOrSingleRegistrationsDoNotAgree) {
  const Pose3 truth = TruePose();
  const std::vector<PoseLink> parted = {{truth, Claimed()},
                                        {Moved(truth, Vec3(0.03, 0, 0)), Claimed()}};
  EXPECT_FALSE(Agreeing(parted, Options()).has_value());
  ASSERT_TRUE(CompareRegistrations(parted, Options()).has_value());
  EXPECT_NEAR(CompareRegistrations(parted, Options())->spread_m, 0.015, 1e-9);
  RegistrationAgreementOptions wide = Options();
  wide.max_m = 0.02;
  EXPECT_TRUE(Agreeing(parted, wide).has_value());  // each 1.5 cm from the mean
  const std::vector<PoseLink> turned = {{truth, Claimed()},
                                        {Moved(truth, Vec3::Zero(), 1.2), Claimed()}};
  EXPECT_FALSE(Agreeing(turned, Options()).has_value());
  EXPECT_FALSE(CompareRegistrations({{truth, Claimed()}}, Options()).has_value());
  EXPECT_FALSE(Agreeing({}, Options()).has_value());
  const std::vector<PoseLink> three = {{truth, Claimed()},
                                       {Moved(truth, Vec3(0.001, 0, 0)), Claimed()},
                                       {Moved(truth, Vec3(0, 0.001, 0)), Claimed()}};
  RegistrationAgreementOptions need_three = Options();
  need_three.min_registrations = 3;
  EXPECT_TRUE(Agreeing(three, need_three).has_value());
  EXPECT_FALSE(
      Agreeing({three[0], three[1]}, need_three).has_value());
  Mat6 broken = Claimed();
  broken(0, 0) = std::nan("");
  EXPECT_FALSE(Agreeing({{truth, Claimed()}, {truth, broken}}, Options()).has_value());
}

}  // namespace
}  // namespace icgm
