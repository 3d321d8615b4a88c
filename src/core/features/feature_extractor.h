// Local visual features behind one interface: ORB, SIFT, AKAZE and GFTT corners described by
// ORB (OpenCV 4.6 main modules), and SURF, the thesis's feature (ch. 3, ch. 4.1), implemented
// in this project (surf.h; OpenCV's is in the non-free contrib module). The descriptor type is
// a policy carried by the output: float descriptors (SIFT, SURF, CV_32F) are matched with a
// FLANN kd-tree, binary ones (ORB, AKAZE, GFTT+ORB, CV_8U) with Hamming distance (see
// descriptor_matcher.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/enum_names.h"

namespace icgm {

class OptionReader;

// The keypoint detector and descriptor (`features.detector`).
enum class Detector { kOrb, kSift, kAkaze, kGfttOrb, kSurf };

template <>
struct EnumNames<Detector> {
  static constexpr EnumName<Detector> kNames[] = {{Detector::kOrb, "orb"},
                                                  {Detector::kSift, "sift"},
                                                  {Detector::kAkaze, "akaze"},
                                                  {Detector::kGfttOrb, "gftt_orb"},
                                                  {Detector::kSurf, "surf"}};
};

struct FeatureOptions {
  Detector detector = Detector::kOrb;
  // Upper bound on keypoints per image; the strongest responses are kept.
  int max_features = 1000;
  // ORB / GFTT+ORB image pyramid.
  double orb_scale_factor = 1.2;
  int orb_levels = 8;
  int orb_fast_threshold = 20;
  // GFTT corner quality (fraction of the best corner response) and spacing.
  double gftt_quality = 0.01;
  double gftt_min_distance_px = 7.0;
  // AKAZE detector response threshold.
  double akaze_threshold = 0.001;
  // SIFT contrast threshold.
  double sift_contrast_threshold = 0.04;
  // SURF: minimum determinant of the box-filter Hessian (intensities 0-255, responses divided
  // by the filter area), scale-space octaves and intervals per octave, upright (U-SURF: no
  // orientation, for cameras that do not roll).
  double surf_hessian_threshold = 100.0;
  int surf_octaves = 4;
  int surf_intervals = 4;
  bool surf_upright = false;
  // Spread over the image (ORB; 0: off): the detector proposes spread_candidates_factor x
  // max_features keypoints, and the budget is filled in rounds over square cells of
  // spread_cell_px, each round taking every cell's strongest keypoint not yet taken. Without it,
  // a strongly textured region (a walker's clothing near the camera) takes most of the budget
  // and the plainer room behind keeps few keypoints.
  int spread_cell_px = 0;
  int spread_candidates_factor = 3;
};

// Fills `options` from a `features:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, FeatureOptions* options);

// Keypoints and their descriptors, one descriptor row per keypoint.
struct FeatureSet {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  // true: CV_8U descriptors compared with Hamming distance; false: CV_32F, L2 distance.
  bool binary = true;

  size_t size() const { return keypoints.size(); }
  bool empty() const { return keypoints.empty(); }
};

class FeatureExtractor {
 public:
  static std::unique_ptr<FeatureExtractor> Create(const FeatureOptions& options);

  virtual ~FeatureExtractor() = default;

  // Accepts 8-bit gray, BGR or BGRA images. An empty image or an unsupported type (not 8-bit,
  // 1/3/4 channels) gives an empty FeatureSet. At most max_features keypoints are returned and
  // keypoints.size() == descriptors.rows always holds.
  virtual FeatureSet Extract(const cv::Mat& image_bgr_or_gray) = 0;

  // True when this extractor produces binary (Hamming) descriptors.
  virtual bool binary() const = 0;
  virtual const std::string& name() const = 0;
};

// Position uncertainty of a keypoint detected on pyramid level k.octave: scale_factor^octave
// pixels (1 for level 0, negative octaves, or scale_factor <= 1).
double PyramidPixelSigma(const cv::KeyPoint& keypoint, double scale_factor);

}  // namespace icgm
