#include "core/odometry/prior_reset.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace icgm {
namespace {

Time ResetStamp(int i) { return Time::FromNanoseconds(1'000'000'000LL + i * 33'333'333LL); }

// The hand moves the camera 2 mm per frame along x.
Pose3 HandPose(int i) { return MakePose(Vec3(0.002 * i, 0.0, 0.0), Quat::Identity()); }
Pose3 ShiftedBy(const Pose3& p, const Vec3& by) {
  return MakePose(p.translation() + by, Quat(p.rotation()));
}

PriorResetOptions ResetOptions() {
  PriorResetOptions o;
  o.disagreement_m = 0.015;
  o.frames = 3;
  o.self_agreement_m = 0.01;
  o.max_speed_mps = 0.5;
  return o;
}

// The prediction runs 2 cm ahead of the registrations, which agree with each other: after three
// frames the prior is reset, and the streak starts over.
TEST(PriorResetTest, ResetsAfterFramesOfConsistentDisagreement) {
  PriorResetDetector d(ResetOptions());
  const Vec3 ahead(0.02, 0.005, 0.0);
  std::vector<int> resets;
  for (int i = 0; i < 7; ++i) {
    if (d.Observe(ResetStamp(i), HandPose(i), ShiftedBy(HandPose(i), ahead))) resets.push_back(i);
  }
  EXPECT_EQ(resets, (std::vector<int>{2, 5}));
  // One frame that agrees breaks the streak.
  PriorResetDetector broken(ResetOptions());
  EXPECT_FALSE(broken.Observe(ResetStamp(0), HandPose(0), ShiftedBy(HandPose(0), ahead)));
  EXPECT_FALSE(broken.Observe(ResetStamp(1), HandPose(1), ShiftedBy(HandPose(1), ahead)));
  EXPECT_FALSE(
      broken.Observe(ResetStamp(2), HandPose(2), ShiftedBy(HandPose(2), Vec3(0.005, 0.0, 0.0))));
  EXPECT_EQ(broken.streak(), 0u);
  EXPECT_FALSE(broken.Observe(ResetStamp(3), HandPose(3), ShiftedBy(HandPose(3), ahead)));
  broken.Break();
  EXPECT_FALSE(broken.Observe(ResetStamp(4), HandPose(4), ShiftedBy(HandPose(4), ahead)));
  EXPECT_FALSE(broken.Observe(ResetStamp(5), HandPose(5), ShiftedBy(HandPose(5), ahead)));
  EXPECT_TRUE(broken.Observe(ResetStamp(6), HandPose(6), ShiftedBy(HandPose(6), ahead)));
  // Off: never.
  PriorResetDetector off{PriorResetOptions()};
  for (int i = 0; i < 5; ++i)
    EXPECT_FALSE(off.Observe(ResetStamp(i), HandPose(i), ShiftedBy(HandPose(i), ahead)));
}

// Registrations scattered 2-4 cm about a right prediction (noise where walkers fill the view)
// disagree with it every frame but not alike: no reset. Registrations that follow a walker at
// 1.5 m/s agree with each other but move faster than a hand: no reset either.
TEST(PriorResetTest, ScatterAndWalkerSpeedDoNotReset) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), norm(0.02, 0.04);
  // Each check alone: the offsets' spread (speed unchecked) and the registered poses' speed
  // (2-8 cm apart per frame; spread unchecked); neither: a reset every third frame.
  const auto resets_over_scatter = [&](double self_agreement_m, double max_speed_mps) {
    PriorResetOptions o = ResetOptions();
    o.self_agreement_m = self_agreement_m;
    o.max_speed_mps = max_speed_mps;
    PriorResetDetector d(o);
    int resets = 0;
    for (int i = 0; i < 300; ++i) {
      const double a = angle(rng), n = norm(rng);
      resets += d.Observe(ResetStamp(i),
                          ShiftedBy(HandPose(i), Vec3(n * std::cos(a), n * std::sin(a), 0.0)),
                          HandPose(i));
    }
    return resets;
  };
  // Three offsets within 1 cm of their mean happen now and then by chance; rarely.
  EXPECT_LT(resets_over_scatter(0.01, 0.0), 10);
  EXPECT_LT(resets_over_scatter(0.0, 0.5), 10);
  EXPECT_EQ(resets_over_scatter(0.0, 0.0), 100);
  // A walker: registered poses 5 cm apart per frame, always 2-3 cm off a prediction that keeps
  // up with the hand.
  PriorResetDetector walker(ResetOptions());
  for (int i = 0; i < 10; ++i) {
    const Pose3 registered = MakePose(Vec3(0.05 * i, 0.0, 0.0), Quat::Identity());
    const Pose3 predicted = ShiftedBy(registered, Vec3(0.0, 0.025, 0.0));
    EXPECT_FALSE(walker.Observe(ResetStamp(i), registered, predicted)) << "frame " << i;
  }
}

}  // namespace
}  // namespace icgm
