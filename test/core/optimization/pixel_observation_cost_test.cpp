// PixelObservationCost gives exactly (bit for bit) the residuals and derivatives of the
// automatically differentiated RgbdObservationError without depth, on random cameras and
// points and on special ones (identity rotation, camera at the origin), and refuses the same
// points behind the camera.
#if __has_include(<ceres/ceres.h>)
#include "core/optimization/pixel_observation_cost.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "../registration/synthetic_rgbd.h"

namespace icgm {
namespace {

bool SameBits(const double* a, const double* b, int n) {
  return std::memcmp(a, b, sizeof(double) * n) == 0;
}

TEST(PixelObservationCostTest, EqualsAutomaticDerivativesBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const CameraIntrinsics k = test::TumLikeCamera();
  int compared = 0, behind = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector2d pixel(320.0 + 300.0 * u(rng), 240.0 + 200.0 * u(rng));
    const double sigma = 1.0 + 0.5 * (trial % 4);
    Eigen::Vector3d t(u(rng), u(rng), u(rng));
    Eigen::Quaterniond q(Eigen::Vector4d(u(rng), u(rng), u(rng), 1.0 + u(rng)).normalized());
    if (trial % 10 == 0) q = Eigen::Quaterniond::Identity();
    if (trial % 15 == 0) t.setZero();
    const Eigen::Vector3d x = t + q * Eigen::Vector3d(u(rng), u(rng), 2.0 * u(rng) + 1.5);
    const double* parameters[3] = {t.data(), q.coeffs().data(), x.data()};
    PixelObservationCost fast(k, pixel, sigma);
    ceres::AutoDiffCostFunction<RgbdObservationError, 3, 3, 4, 3> automatic(
        new RgbdObservationError(k, pixel, sigma, 0.0, 0.0));
    double r_fast[3], r_auto[3];
    double jf[3][12], ja[3][12];
    double* jacobians_fast[3] = {jf[0], jf[1], jf[2]};
    double* jacobians_auto[3] = {ja[0], ja[1], ja[2]};
    // Values only, then values with derivatives (Ceres asks for both).
    const bool ok_fast = fast.Evaluate(parameters, r_fast, nullptr);
    ASSERT_EQ(ok_fast, automatic.Evaluate(parameters, r_auto, nullptr));
    if (!ok_fast) {
      ++behind;
      continue;
    }
    EXPECT_TRUE(SameBits(r_fast, r_auto, 3)) << trial;
    ASSERT_TRUE(fast.Evaluate(parameters, r_fast, jacobians_fast));
    ASSERT_TRUE(automatic.Evaluate(parameters, r_auto, jacobians_auto));
    EXPECT_TRUE(SameBits(r_fast, r_auto, 3)) << trial;
    EXPECT_TRUE(SameBits(jf[0], ja[0], 9)) << trial;
    EXPECT_TRUE(SameBits(jf[1], ja[1], 12)) << trial;
    EXPECT_TRUE(SameBits(jf[2], ja[2], 9)) << trial;
    // A constant block (no derivative asked for) leaves the others as they are.
    double* some[3] = {nullptr, jf[1], nullptr};
    ASSERT_TRUE(fast.Evaluate(parameters, r_fast, some));
    EXPECT_TRUE(SameBits(jf[1], ja[1], 12)) << trial;
    ++compared;
  }
  EXPECT_GT(compared, 1500);
  EXPECT_GT(behind, 0);
}

}  // namespace
}  // namespace icgm
#else
#include <gtest/gtest.h>
TEST(PixelObservationCostTest, EqualsAutomaticDerivativesBitForBit) {
  GTEST_SKIP() << "SKIPPED: built without Ceres";
}
#endif
