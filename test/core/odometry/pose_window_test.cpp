#include "core/odometry/pose_window.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace icgm {
namespace {

Time WindowFrame(int i) { return Time::FromNanoseconds(1'000'000'000LL + i * 33'333'333LL); }

// A hand-held camera moving about 3 mm and 0.1 deg per frame (30 Hz), slowly changing velocity.
Pose3 WindowTruth(int i) {
  const Vec3 axis = Vec3(0.2, 1.0, 0.1).normalized();
  const double s = i + 0.002 * i * i;
  return MakePose(Vec3(0.003, -0.001, 0.0005) * s,
                  Quat(Eigen::AngleAxisd(0.1 * M_PI / 180.0 * s, axis)));
}

Mat6 WindowCovariance(double sigma_m, double sigma_deg) {
  const double r = sigma_deg * M_PI / 180.0;
  Vec6 d;
  d << sigma_m * sigma_m, sigma_m * sigma_m, sigma_m * sigma_m, r * r, r * r, r * r;
  return Mat6(d.asDiagonal());
}

PoseWindowOptions WindowOptions() {
  PoseWindowOptions o;
  o.frames = 20;
  o.acceleration_sigma_m = 0.0007;
  o.acceleration_sigma_deg = 0.1;
  o.robust_sigmas = 3.0;
  return o;
}

TEST(PoseWindowTest, ExactMeasurementsAreKept) {
  PoseWindow window(WindowOptions(), 0.5);
  window.Add(WindowFrame(0), {}, WindowTruth(0));
  for (int i = 1; i < 30; ++i) {
    const Pose3 out = window.Add(WindowFrame(i), {{WindowTruth(i), WindowCovariance(0.01, 0.5)}},
                                 WindowTruth(i) * ExpSE3(Vec6::Constant(0.002)));
    // The truth's slight acceleration against the stiff constant-velocity term: within
    // 0.3 mm / 0.006 deg of links that claim 1 cm / 0.5 deg.
    EXPECT_LT(TranslationNorm(Between(WindowTruth(i), out)), 3e-4) << "frame " << i;
    EXPECT_LT(RotationAngleRad(Between(WindowTruth(i), out)), 1e-4) << "frame " << i;
  }
  EXPECT_EQ(window.size(), 20u);
}

// Each frame registered to two keyframes with 1 cm / 0.4 deg noise (what a registration among
// walkers gives while the camera moves 3 mm per frame); in every fifth frame one link follows a
// walker, 4 cm off. The window's poses (causal: each frame's pose as handed out when it comes)
// err far less than the information-weighted mean of each frame's links.
TEST(PoseWindowTest, NoisyLinksWithWalkerOutliersAreSmoothedAndRejected) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  const auto noisy = [&](const Pose3& truth, double sigma_m, double sigma_deg) {
    Vec6 d;
    for (int k = 0; k < 3; ++k) d[k] = sigma_m * noise(rng);
    for (int k = 3; k < 6; ++k) d[k] = sigma_deg * M_PI / 180.0 * noise(rng);
    return truth * ExpSE3(d);
  };
  const Mat6 cov = WindowCovariance(0.01, 0.4);
  PoseWindow window(WindowOptions(), 0.5);
  window.Add(WindowFrame(0), {}, WindowTruth(0));
  double window_sq = 0.0, mean_sq = 0.0;
  int outlier_frames = 0;
  double outlier_weight = 0.0;
  const int frames = 150;
  for (int i = 1; i < frames; ++i) {
    std::vector<PoseLink> links = {{noisy(WindowTruth(i), 0.01, 0.4), cov},
                                   {noisy(WindowTruth(i), 0.01, 0.4), cov}};
    if (i % 5 == 0) links[1].odom_camera = WindowTruth(i) * MakePose(Vec3(0.04, 0.0, 0.0), Quat::Identity());
    // Plain mean of the two links (equal covariances): the midpoint.
    const Pose3 mean = Interpolate(links[0].odom_camera, links[1].odom_camera, 0.5);
    const Pose3 out = window.Add(WindowFrame(i), links, mean);
    if (i % 5 == 0 && i > 20) {
      ++outlier_frames;
      outlier_weight += window.last_link_weights()[1];
    }
    if (i < 10) continue;  // the window fills
    window_sq += std::pow(TranslationNorm(Between(WindowTruth(i), out)), 2);
    mean_sq += std::pow(TranslationNorm(Between(WindowTruth(i), mean)), 2);
  }
  const double window_rms = std::sqrt(window_sq / (frames - 10));
  const double mean_rms = std::sqrt(mean_sq / (frames - 10));
  std::printf("link mean rms %.4f m, window rms %.4f m, outlier link weight %.3f\n", mean_rms,
              window_rms, outlier_weight / outlier_frames);
  EXPECT_LT(window_rms, 0.5 * mean_rms);
  EXPECT_LT(window_rms, 0.008);
  // The walker's links weigh far less than the good ones.
  EXPECT_LT(outlier_weight / outlier_frames, 0.5);
}

TEST(PoseWindowTest, FrameWithoutLinksIsHeldAndAGapRestarts) {
  PoseWindow window(WindowOptions(), 0.5);
  window.Add(WindowFrame(0), {}, WindowTruth(0));
  window.Add(WindowFrame(1), {{WindowTruth(1), WindowCovariance(0.01, 0.5)}}, WindowTruth(1));
  const Pose3 held = WindowTruth(2) * MakePose(Vec3(0.05, 0, 0), Quat::Identity());
  const Pose3 out = window.Add(WindowFrame(2), {}, held);
  EXPECT_LT(TranslationNorm(Between(held, out)), 1e-12);
  EXPECT_EQ(window.size(), 3u);
  window.Add(WindowFrame(40), {{WindowTruth(40), WindowCovariance(0.01, 0.5)}}, WindowTruth(40));
  EXPECT_EQ(window.size(), 1u);
}

}  // namespace
}  // namespace icgm
