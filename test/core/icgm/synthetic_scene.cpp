#include "synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

namespace icgm::test {

cv::Mat MakeTexture(const cv::Size& size, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> color(0, 255);
  std::uniform_int_distribution<int> x(0, size.width - 1);
  std::uniform_int_distribution<int> y(0, size.height - 1);
  std::uniform_int_distribution<int> extent(4, 40);
  cv::Mat texture(size, CV_8UC3, cv::Scalar(color(rng), color(rng), color(rng)));
  const int area_units = size.area() / 400;
  for (int i = 0; i < area_units; ++i) {
    const cv::Scalar c(color(rng), color(rng), color(rng));
    const cv::Point p(x(rng), y(rng));
    switch (i % 3) {
      case 0:
        cv::rectangle(texture, cv::Rect(p.x, p.y, extent(rng), extent(rng)), c, cv::FILLED);
        break;
      case 1:
        cv::circle(texture, p, extent(rng) / 2, c, cv::FILLED, cv::LINE_AA);
        break;
      default:
        cv::line(texture, p, cv::Point(x(rng), y(rng)), c, 2, cv::LINE_AA);
        break;
    }
  }
  // Seeded pixel noise (not cv::theRNG) so that every render is reproducible.
  cv::RNG noise_rng(seed ^ 0x9e3779b97f4a7c15ULL);
  cv::Mat noise(size, CV_16SC3);
  noise_rng.fill(noise, cv::RNG::NORMAL, 0.0, 12.0);
  cv::Mat noisy;
  cv::add(texture, noise, noisy, cv::noArray(), CV_8UC3);
  return noisy;
}

Eigen::Vector2d ScenePair::MapStatic(const Eigen::Vector2d& pa) const {
  const cv::Vec3d q = homography * cv::Vec3d(pa.x(), pa.y(), 1.0);
  return Eigen::Vector2d(q[0] / q[2], q[1] / q[2]);
}

ScenePair RenderScenePair(const SceneOptions& o) {
  ScenePair scene;
  const cv::Size size = o.image_size;
  Eigen::Matrix3d k;
  k << o.fx, 0, o.cx, 0, o.fy, o.cy, 0, 0, 1;
  const Eigen::Vector3d r = o.rotation_deg * M_PI / 180.0;
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()))
                                       .toRotationMatrix();
  // X_b = R X_a + t for points on the plane n^T X_a = d, n = (0, 0, 1).
  const Eigen::Matrix3d h =
      k * (rotation + o.translation_m * Eigen::Vector3d::UnitZ().transpose() / o.plane_depth_m) *
      k.inverse();
  cv::Matx33d h_cv;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) h_cv(i, j) = h(i, j) / h(2, 2);
  }
  scene.homography = h_cv;

  // The texture extends beyond image a so that image b is fully textured as well.
  const int margin = 200;
  const cv::Mat texture =
      MakeTexture(cv::Size(size.width + 2 * margin, size.height + 2 * margin), o.seed);
  const cv::Matx33d shift(1, 0, -margin, 0, 1, -margin, 0, 0, 1);
  cv::warpPerspective(texture, scene.image_a, shift, size, cv::INTER_LINEAR);
  cv::warpPerspective(texture, scene.image_b, h_cv * shift, size, cv::INTER_LINEAR);

  std::mt19937_64 rng(o.seed * 7919 + 17);
  std::uniform_int_distribution<int> side(o.pedestrian_min_size_px, o.pedestrian_max_size_px);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  std::uniform_real_distribution<double> motion(o.pedestrian_min_motion_px,
                                                o.pedestrian_max_motion_px);
  for (int p = 0; p < o.num_pedestrians; ++p) {
    const int w = side(rng);
    const int hgt = std::min(size.height - 2, side(rng) * 3 / 2);  // upright, like a person
    const cv::Mat patch = MakeTexture(cv::Size(w, hgt), o.seed * 1000 + p + 1);
    // Place so that both positions are inside the image.
    for (int attempt = 0; attempt < 100; ++attempt) {
      const double a = angle(rng);
      const double m = motion(rng);
      const int dx = static_cast<int>(std::lround(m * std::cos(a)));
      const int dy = static_cast<int>(std::lround(m * std::sin(a)));
      std::uniform_int_distribution<int> px(std::max(0, -dx), size.width - w - std::max(0, dx));
      std::uniform_int_distribution<int> py(std::max(0, -dy), size.height - hgt - std::max(0, dy));
      if (px.a() > px.b() || py.a() > py.b()) continue;
      const cv::Rect ra(px(rng), py(rng), w, hgt);
      const cv::Rect rb(ra.x + dx, ra.y + dy, w, hgt);
      patch.copyTo(scene.image_a(ra));
      patch.copyTo(scene.image_b(rb));
      scene.pedestrians_a.push_back(ra);
      scene.pedestrians_b.push_back(rb);
      break;
    }
  }
  return scene;
}

namespace {
bool OnAny(const std::vector<cv::Rect>& rects, const Eigen::Vector2d& p, double margin) {
  for (const cv::Rect& r : rects) {
    if (p.x() >= r.x - margin && p.x() <= r.x + r.width + margin && p.y() >= r.y - margin &&
        p.y() <= r.y + r.height + margin) {
      return true;
    }
  }
  return false;
}
}  // namespace

MatchTruth ClassifyMatch(const ScenePair& scene, const Eigen::Vector2d& pa,
                         const Eigen::Vector2d& pb, double tolerance_px, double margin_px) {
  if (OnAny(scene.pedestrians_a, pa, margin_px) || OnAny(scene.pedestrians_b, pb, margin_px)) {
    return MatchTruth::kDynamic;
  }
  return (scene.MapStatic(pa) - pb).norm() <= tolerance_px ? MatchTruth::kStatic
                                                           : MatchTruth::kWrong;
}

}  // namespace icgm::test
