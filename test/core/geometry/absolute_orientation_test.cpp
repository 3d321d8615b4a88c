#include "core/geometry/absolute_orientation.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace icgm {
namespace {

struct Problem {
  std::vector<Eigen::Vector3d> src;
  std::vector<Eigen::Vector3d> dst;
  SimilarityTransform truth;
};

SimilarityTransform RandomTransform(std::mt19937* rng, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SimilarityTransform t;
  const Eigen::Vector4d q(u(*rng), u(*rng), u(*rng), u(*rng));
  t.rotation = Eigen::Quaterniond(q.normalized()).toRotationMatrix();
  t.translation = Eigen::Vector3d(u(*rng), u(*rng), u(*rng)) * 5.0;
  t.scale = scale;
  return t;
}

Problem MakeProblem(std::mt19937* rng, int n, double scale, double noise_sigma = 0.0) {
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::normal_distribution<double> g(0.0, noise_sigma > 0 ? noise_sigma : 1.0);
  Problem p;
  p.truth = RandomTransform(rng, scale);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d s(u(*rng), u(*rng), u(*rng));
    Eigen::Vector3d d = p.truth.Apply(s);
    if (noise_sigma > 0) d += Eigen::Vector3d(g(*rng), g(*rng), g(*rng)) * noise_sigma;
    p.src.push_back(s);
    p.dst.push_back(d);
  }
  return p;
}

double Residual(const Problem& p, const SimilarityTransform& t) {
  double r = 0.0;
  for (size_t i = 0; i < p.src.size(); ++i) r += (p.dst[i] - t.Apply(p.src[i])).squaredNorm();
  return r;
}

TEST(HornAlignTest, RecoversRigidTransformExactly) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Problem p = MakeProblem(&rng, 3 + trial, 1.0);
    SimilarityTransform est;
    const Status s = HornAlign(p.src, p.dst, false, &est);
    ASSERT_TRUE(s.ok()) << s.reason();
    EXPECT_LT((est.rotation - p.truth.rotation).norm(), 1e-9);
    EXPECT_LT((est.translation - p.truth.translation).norm(), 1e-9);
    EXPECT_EQ(est.scale, 1.0);
    EXPECT_NEAR(est.rotation.determinant(), 1.0, 1e-12);
  }
}

TEST(HornAlignTest, HalfTurnRotations) {
  // Rotations by pi have a zero quaternion scalar part: the eigenvector must still be found.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (const Eigen::Vector3d& axis :
       std::vector<Eigen::Vector3d>{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(),
                                    Eigen::Vector3d(1, -2, 0.5).normalized()}) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(M_PI, axis).toRotationMatrix();
    std::vector<Eigen::Vector3d> src, dst;
    for (int i = 0; i < 10; ++i) {
      src.emplace_back(u(rng), u(rng), u(rng));
      dst.push_back(r * src.back() + Eigen::Vector3d(0.1, 0.2, 0.3));
    }
    SimilarityTransform est;
    ASSERT_TRUE(HornAlign(src, dst, false, &est).ok());
    EXPECT_LT((est.rotation - r).norm(), 1e-9);
  }
}

TEST(HornAlignTest, CoplanarPointsAreEnough) {
  std::mt19937 rng(3);
  Problem p = MakeProblem(&rng, 0, 1.0);
  for (double x : {0.0, 1.0, 2.5}) {
    for (double y : {0.0, 0.7}) {
      p.src.emplace_back(x, y, 0.0);
      p.dst.push_back(p.truth.Apply(p.src.back()));
    }
  }
  SimilarityTransform est;
  ASSERT_TRUE(HornAlign(p.src, p.dst, false, &est).ok());
  EXPECT_LT((est.rotation - p.truth.rotation).norm(), 1e-9);
  EXPECT_LT((est.translation - p.truth.translation).norm(), 1e-9);
}

TEST(HornAlignTest, Sim3RecoversScale) {
  std::mt19937 rng(11);
  for (double scale : {0.05, 0.5, 1.0, 3.7, 40.0}) {
    const Problem p = MakeProblem(&rng, 20, scale);
    SimilarityTransform est;
    ASSERT_TRUE(HornAlign(p.src, p.dst, true, &est).ok());
    EXPECT_NEAR(est.scale, scale, 1e-9 * scale);
    EXPECT_LT((est.rotation - p.truth.rotation).norm(), 1e-9);
    EXPECT_LT((est.translation - p.truth.translation).norm(), 1e-8);
    // SE(3) on scaled data keeps scale 1 and cannot fit exactly.
    SimilarityTransform rigid;
    ASSERT_TRUE(HornAlign(p.src, p.dst, false, &rigid).ok());
    EXPECT_EQ(rigid.scale, 1.0);
    if (std::abs(scale - 1.0) > 0.1) {
      EXPECT_GT(Residual(p, rigid), 1e-3);
    }
  }
}

TEST(HornAlignTest, NoisyResultIsLeastSquaresOptimal) {
  std::mt19937 rng(5);
  const Problem p = MakeProblem(&rng, 200, 1.0, 0.01);
  SimilarityTransform est;
  ASSERT_TRUE(HornAlign(p.src, p.dst, false, &est).ok());
  const double best = Residual(p, est);
  EXPECT_LE(best, Residual(p, p.truth));
  // Any small rigid perturbation of the estimate must not lower the residual.
  std::normal_distribution<double> g(0.0, 1e-3);
  for (int k = 0; k < 100; ++k) {
    Eigen::Matrix<double, 6, 1> d;
    for (int j = 0; j < 6; ++j) d(j) = g(rng);
    const Pose3 perturbed = ExpSE3(d) * est.AsPose();
    SimilarityTransform t;
    t.rotation = perturbed.linear();
    t.translation = perturbed.translation();
    EXPECT_GE(Residual(p, t), best - 1e-12);
  }
  EXPECT_LT((est.rotation - p.truth.rotation).norm(), 5e-3);
}

TEST(HornAlignTest, ZeroWeightsIgnoreOutliers) {
  std::mt19937 rng(13);
  Problem p = MakeProblem(&rng, 10, 1.0);
  std::vector<double> w(p.src.size(), 1.0);
  for (int k = 0; k < 5; ++k) {
    p.src.emplace_back(k, -k, 2.0 * k);
    p.dst.emplace_back(100.0 + k, 3.0, -50.0 * k);  // gross outliers
    w.push_back(0.0);
  }
  SimilarityTransform est;
  ASSERT_TRUE(HornAlign(p.src, p.dst, false, &est, &w).ok());
  EXPECT_LT((est.rotation - p.truth.rotation).norm(), 1e-9);
  EXPECT_LT((est.translation - p.truth.translation).norm(), 1e-9);
  // Without weights the outliers pull the estimate away.
  SimilarityTransform unweighted;
  ASSERT_TRUE(HornAlign(p.src, p.dst, false, &unweighted).ok());
  EXPECT_GT((unweighted.translation - p.truth.translation).norm(), 1e-2);
}

TEST(HornAlignTest, IntegerWeightEqualsRepeatedPoint) {
  std::mt19937 rng(17);
  const Problem p = MakeProblem(&rng, 12, 1.0, 0.05);
  std::vector<double> w(p.src.size(), 1.0);
  w[0] = 3.0;
  w[4] = 2.0;
  Problem repeated = p;
  for (int k = 0; k < 2; ++k) repeated.src.push_back(p.src[0]), repeated.dst.push_back(p.dst[0]);
  repeated.src.push_back(p.src[4]);
  repeated.dst.push_back(p.dst[4]);
  SimilarityTransform a, b;
  ASSERT_TRUE(HornAlign(p.src, p.dst, true, &a, &w).ok());
  ASSERT_TRUE(HornAlign(repeated.src, repeated.dst, true, &b).ok());
  EXPECT_LT((a.rotation - b.rotation).norm(), 1e-9);
  EXPECT_LT((a.translation - b.translation).norm(), 1e-9);
  EXPECT_NEAR(a.scale, b.scale, 1e-9);
}

void ExpectFailure(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                   const std::string& reason_part, const std::vector<double>* w = nullptr) {
  SimilarityTransform est;
  est.scale = 42.0;
  const Status s = HornAlign(src, dst, true, &est, w);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find(reason_part), std::string::npos) << s.reason();
  EXPECT_EQ(est.scale, 42.0) << "output must be untouched on failure";
}

TEST(HornAlignTest, DegenerateInputsFailWithReason) {
  using V = Eigen::Vector3d;
  const std::vector<V> three = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)};
  ExpectFailure({}, {}, "at least 3");
  ExpectFailure({V(1, 2, 3)}, {V(1, 2, 3)}, "at least 3");
  ExpectFailure({V(1, 2, 3), V(0, 0, 1)}, {V(1, 2, 3), V(0, 0, 1)}, "at least 3");
  ExpectFailure(three, {V(0, 0, 0), V(1, 0, 0)}, "size mismatch");
  const std::vector<V> line = {V(0, 0, 0), V(1, 1, 1), V(2, 2, 2), V(-3, -3, -3)};
  ExpectFailure(line, line, "collinear");
  const std::vector<V> same = {V(1, 1, 1), V(1, 1, 1), V(1, 1, 1)};
  ExpectFailure(same, same, "coincident");
  ExpectFailure(three, line, "size mismatch");
  ExpectFailure(three, {V(0, 0, 0), V(1, 0, 0), V(2, 0, 0)}, "destination");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  ExpectFailure({V(0, 0, 0), V(1, 0, 0), V(0, nan, 0)}, three, "not finite");
  ExpectFailure(three, {V(0, 0, 0), V(inf, 0, 0), V(0, 1, 0)}, "not finite");
  const std::vector<double> short_w = {1.0, 1.0};
  ExpectFailure(three, three, "weights", &short_w);
  const std::vector<double> neg_w = {1.0, -1.0, 1.0};
  ExpectFailure(three, three, "negative", &neg_w);
  const std::vector<double> zero_w = {0.0, 0.0, 0.0};
  ExpectFailure(three, three, "sum to zero", &zero_w);
  // Only two points carry weight: as degenerate as two points.
  const std::vector<double> two_w = {1.0, 1.0, 0.0};
  ExpectFailure(three, three, "collinear", &two_w);
}

TEST(SimilarityTransformTest, AsPoseDropsScale) {
  SimilarityTransform t;
  t.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation = Eigen::Vector3d(1, 2, 3);
  t.scale = 2.0;
  const Eigen::Vector3d p(0.5, -1.0, 4.0);
  EXPECT_LT((t.Apply(p) - (2.0 * t.rotation * p + t.translation)).norm(), 1e-15);
  EXPECT_LT((t.AsPose() * p - (t.rotation * p + t.translation)).norm(), 1e-15);
}

}  // namespace
}  // namespace icgm
