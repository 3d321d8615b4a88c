// Test-only renderer of image pairs with known ground truth for ICGM: a textured plane seen by
// a camera under a known motion (the plane-induced homography H = K (R + t n^T / d) K^-1 maps
// static pixels of image a to image b) plus independently moving textured patches
// ("pedestrians") pasted at different places in the two images.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace icgm::test {

// Procedural texture rich in corners: random rectangles, circles, lines and pixel noise.
cv::Mat MakeTexture(const cv::Size& size, uint64_t seed);

struct SceneOptions {
  cv::Size image_size{640, 480};
  double fx = 517.3, fy = 516.5, cx = 318.6, cy = 255.3;
  // Camera b relative to camera a: small rotation (degrees about x, y, z) and translation (m).
  Eigen::Vector3d rotation_deg{1.0, -1.5, 2.0};
  Eigen::Vector3d translation_m{0.05, -0.03, 0.04};
  // Fronto-parallel plane at this depth in camera a.
  double plane_depth_m = 2.5;
  // Pedestrians: count, side length range and image motion range (pixels).
  int num_pedestrians = 3;
  int pedestrian_min_size_px = 70;
  int pedestrian_max_size_px = 120;
  double pedestrian_min_motion_px = 80.0;
  double pedestrian_max_motion_px = 120.0;
  uint64_t seed = 1;
};

struct ScenePair {
  cv::Mat image_a;
  cv::Mat image_b;
  // Static pixel in a -> static pixel in b.
  cv::Matx33d homography;
  // Pedestrian regions in a and b.
  std::vector<cv::Rect> pedestrians_a;
  std::vector<cv::Rect> pedestrians_b;

  Eigen::Vector2d MapStatic(const Eigen::Vector2d& pa) const;
};

ScenePair RenderScenePair(const SceneOptions& options);

enum class MatchTruth { kStatic, kDynamic, kWrong };

// kDynamic when either end lies on a pedestrian (rectangles grown by margin_px); kStatic when
// both ends are off pedestrians and |H pa - pb| <= tolerance_px; kWrong otherwise.
MatchTruth ClassifyMatch(const ScenePair& scene, const Eigen::Vector2d& pa,
                         const Eigen::Vector2d& pb, double tolerance_px = 2.5,
                         double margin_px = 4.0);

}  // namespace icgm::test
