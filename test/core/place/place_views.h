// Synthetic places for place-recognition tests: each place is a set of 3D points in front of
// the camera, each point with its own random ORB-like descriptor (32 bytes). A view projects
// the points through a pinhole camera at a small offset from the place's reference pose, keeps
// most of them and flips a few descriptor bits, as a revisit would. A look-alike view has the
// same descriptors at random pixels: the same appearance without one rigid scene. A replica is
// the place built `scale` times larger, seen from `scale` times farther: the same pixels (one
// valid epipolar geometry with the original) but other 3-D distances. Views can return each
// keypoint's 3-D point in the camera frame (what a depth camera would measure).
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/features/feature_extractor.h"

namespace icgm::test {

class PlaceViews {
 public:
  PlaceViews(int places, int points_per_place, unsigned seed)
      : rng_(seed),
        points_(static_cast<size_t>(places)),
        descriptors_(static_cast<size_t>(places)) {
    std::uniform_real_distribution<double> x(-3.0, 3.0), y(-1.5, 1.5), z(2.0, 8.0);
    std::uniform_int_distribution<int> byte(0, 255);
    for (size_t p = 0; p < points_.size(); ++p) {
      descriptors_[p].create(points_per_place, 32, CV_8U);
      for (int i = 0; i < points_per_place; ++i) {
        points_[p].emplace_back(x(rng_), y(rng_), z(rng_));
        for (int c = 0; c < 32; ++c) {
          descriptors_[p].at<uint8_t>(i, c) = static_cast<uint8_t>(byte(rng_));
        }
      }
    }
  }

  static CameraIntrinsics Camera() { return CameraIntrinsics(); }

  // The place seen from `sideways_m` to the right and `yaw_rad` turned; `keep`: share of the
  // points kept.
  FeatureSet View(int place, double sideways_m, double yaw_rad, double keep = 0.85,
                  int flipped_bits = 4, std::vector<Eigen::Vector3d>* points_m = nullptr) {
    return Make(place, sideways_m, yaw_rad, keep, flipped_bits, false, 1.0, points_m);
  }
  FeatureSet Replica(int place, double scale, double sideways_m, double yaw_rad,
                     std::vector<Eigen::Vector3d>* points_m) {
    return Make(place, sideways_m, yaw_rad, 0.85, 4, false, scale, points_m);
  }
  // Same descriptors as View, at random pixels.
  FeatureSet LookAlike(int place, double keep = 0.85, int flipped_bits = 4) {
    return Make(place, 0.0, 0.0, keep, flipped_bits, true);
  }

 private:
  FeatureSet Make(int place, double sideways_m, double yaw_rad, double keep, int flipped_bits,
                  bool scramble, double scale = 1.0,
                  std::vector<Eigen::Vector3d>* points_m = nullptr) {
    if (points_m) points_m->clear();
    const CameraIntrinsics k = Camera();
    std::bernoulli_distribution keep_it(keep);
    std::uniform_int_distribution<int> bit(0, 255);
    std::uniform_real_distribution<double> px(0.0, k.width_px - 1), py(0.0, k.height_px - 1);
    std::normal_distribution<double> pixel_noise(0.0, 0.3);
    FeatureSet out;
    const auto& pts = points_.at(static_cast<size_t>(place));
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    for (size_t i = 0; i < pts.size(); ++i) {
      if (!keep_it(rng_)) continue;
      // Camera at (sideways_m, 0, 0), turned by yaw about its y axis (optical frame).
      const Eigen::Vector3d d = pts[i] - Eigen::Vector3d(sideways_m, 0.0, 0.0);
      const Eigen::Vector3d cam(c * d.x() - s * d.z(), d.y(), s * d.x() + c * d.z());
      if (cam.z() < 0.5) continue;
      double u = k.fx_px * cam.x() / cam.z() + k.cx_px + pixel_noise(rng_);
      double v = k.fy_px * cam.y() / cam.z() + k.cy_px + pixel_noise(rng_);
      if (scramble) {
        u = px(rng_);
        v = py(rng_);
      }
      if (u < 0 || v < 0 || u >= k.width_px || v >= k.height_px) continue;
      cv::Mat row = descriptors_[static_cast<size_t>(place)].row(static_cast<int>(i)).clone();
      for (int b = 0; b < flipped_bits; ++b) {
        const int n = bit(rng_);
        row.at<uint8_t>(0, n / 8) ^= static_cast<uint8_t>(1u << (n % 8));
      }
      out.keypoints.emplace_back(static_cast<float>(u), static_cast<float>(v), 7.f);
      out.descriptors.push_back(row);
      if (points_m) points_m->push_back(scale * cam);
    }
    out.binary = true;
    return out;
  }

  std::mt19937 rng_;
  std::vector<std::vector<Eigen::Vector3d>> points_;
  std::vector<cv::Mat> descriptors_;
};

}  // namespace icgm::test
