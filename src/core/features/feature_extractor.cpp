#include "core/features/feature_extractor.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/option_reader.h"
#include "core/features/surf.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, FeatureOptions* options) {
  reader.ReadEnum("detector", &options->detector);
  reader.Read("max_features", &options->max_features, 1, 100000);
  reader.Read("orb_scale_factor", &options->orb_scale_factor, 1.01, 2.0);
  reader.Read("orb_levels", &options->orb_levels, 1, 16);
  reader.Read("orb_fast_threshold", &options->orb_fast_threshold, 1, 255);
  reader.Read("gftt_quality", &options->gftt_quality, 1e-6, 1.0);
  reader.Read("gftt_min_distance_px", &options->gftt_min_distance_px, 0.0, 100.0);
  reader.Read("akaze_threshold", &options->akaze_threshold, 1e-6, 1.0);
  reader.Read("sift_contrast_threshold", &options->sift_contrast_threshold, 1e-6, 1.0);
  reader.Read("surf_hessian_threshold", &options->surf_hessian_threshold, 0.0, 1e6);
  reader.Read("surf_octaves", &options->surf_octaves, 1, 6);
  reader.Read("surf_intervals", &options->surf_intervals, 3, 8);
  reader.Read("surf_upright", &options->surf_upright);
  reader.Read("spread_cell_px", &options->spread_cell_px, 0, 1000);
  reader.Read("spread_candidates_factor", &options->spread_candidates_factor, 1, 20);
}

namespace {

// 8-bit single-channel view of the input; empty for unsupported inputs.
cv::Mat ToGray(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U) return cv::Mat();
  switch (image.channels()) {
    case 1:
      return image;
    case 3: {
      cv::Mat gray;
      cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
      return gray;
    }
    case 4: {
      cv::Mat gray;
      cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
      return gray;
    }
    default:
      return cv::Mat();
  }
}

// Indices of at most `budget` keypoints spread over cells of `cell_px`: in rounds, every cell's
// strongest keypoint not yet taken (cells in row-major order, ties by index), in taking order.
std::vector<int> SpreadOverCells(const std::vector<cv::KeyPoint>& keypoints, int cell_px,
                                 int budget) {
  std::map<std::pair<int, int>, std::vector<int>> cells;
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::Point2f& p = keypoints[i].pt;
    cells[{static_cast<int>(p.y) / cell_px, static_cast<int>(p.x) / cell_px}].push_back(
        static_cast<int>(i));
  }
  std::vector<std::vector<int>*> order;
  for (auto& [cell, members] : cells) {
    std::stable_sort(members.begin(), members.end(),
                     [&](int a, int b) { return keypoints[a].response > keypoints[b].response; });
    order.push_back(&members);
  }
  std::vector<int> taken;
  for (size_t round = 0; static_cast<int>(taken.size()) < budget; ++round) {
    bool any = false;
    for (const std::vector<int>* members : order) {
      if (round >= members->size()) continue;
      any = true;
      taken.push_back((*members)[round]);
      if (static_cast<int>(taken.size()) == budget) break;
    }
    if (!any) break;
  }
  return taken;
}

// Detector and descriptor given by OpenCV Feature2D objects (possibly the same object).
class OpenCvExtractor : public FeatureExtractor {
 public:
  OpenCvExtractor(std::string name, cv::Ptr<cv::Feature2D> detector,
                  cv::Ptr<cv::Feature2D> descriptor, bool binary, int max_features,
                  int spread_cell_px = 0)
      : name_(std::move(name)),
        detector_(std::move(detector)),
        descriptor_(std::move(descriptor)),
        binary_(binary),
        max_features_(max_features),
        spread_cell_px_(spread_cell_px) {}

  FeatureSet Extract(const cv::Mat& image_bgr_or_gray) override {
    FeatureSet out;
    out.binary = binary_;
    const cv::Mat gray = ToGray(image_bgr_or_gray);
    if (gray.empty()) return out;
    if (detector_ == descriptor_ && !NeedsRetain()) {
      detector_->detectAndCompute(gray, cv::noArray(), out.keypoints, out.descriptors);
      if (spread_cell_px_ > 0 && out.descriptors.rows == static_cast<int>(out.keypoints.size())) {
        const std::vector<int> taken =
            SpreadOverCells(out.keypoints, spread_cell_px_, max_features_);
        FeatureSet spread;
        spread.binary = binary_;
        spread.descriptors.create(static_cast<int>(taken.size()), out.descriptors.cols,
                                  out.descriptors.type());
        for (size_t k = 0; k < taken.size(); ++k) {
          spread.keypoints.push_back(out.keypoints[taken[k]]);
          out.descriptors.row(taken[k]).copyTo(spread.descriptors.row(static_cast<int>(k)));
        }
        out = std::move(spread);
      }
    } else {
      detector_->detect(gray, out.keypoints);
      // Detectors without a feature budget (AKAZE) keep their strongest responses.
      cv::KeyPointsFilter::retainBest(out.keypoints, max_features_);
      descriptor_->compute(gray, out.keypoints, out.descriptors);
    }
    // Some detectors may exceed the budget slightly (ties in retainBest, ORB per-level quotas).
    if (static_cast<int>(out.keypoints.size()) > max_features_) {
      out.keypoints.resize(max_features_);
      out.descriptors = out.descriptors.rowRange(0, max_features_).clone();
    }
    if (out.descriptors.rows != static_cast<int>(out.keypoints.size())) {
      // Defensive: a descriptor failure must not produce misaligned rows.
      out.keypoints.clear();
      out.descriptors.release();
    }
    return out;
  }

  bool binary() const override { return binary_; }
  const std::string& name() const override { return name_; }

 private:
  bool NeedsRetain() const { return name_ == "akaze"; }

  std::string name_;
  cv::Ptr<cv::Feature2D> detector_;
  cv::Ptr<cv::Feature2D> descriptor_;
  bool binary_;
  int max_features_;
  int spread_cell_px_;  // 0: the detector's own selection
};

// The project's SURF (surf.h): float descriptors, at most max_features strongest blobs.
class SurfExtractor : public FeatureExtractor {
 public:
  explicit SurfExtractor(SurfOptions options) : options_(options) {}

  FeatureSet Extract(const cv::Mat& image_bgr_or_gray) override {
    FeatureSet out;
    out.binary = false;
    const cv::Mat gray = ToGray(image_bgr_or_gray);
    if (gray.empty()) return out;
    ExtractSurf(gray, options_, &out.keypoints, &out.descriptors, &buffers_);
    return out;
  }

  bool binary() const override { return false; }
  const std::string& name() const override { return name_; }

 private:
  SurfOptions options_;
  SurfBuffers buffers_;  // reused frame to frame: Extract is not for concurrent calls
  std::string name_ = "surf";
};

}  // namespace

std::unique_ptr<FeatureExtractor> FeatureExtractor::Create(const FeatureOptions& o) {
  const int n = std::max(1, o.max_features);
  switch (o.detector) {
    case Detector::kOrb: {
      const int candidates = o.spread_cell_px > 0 ? n * std::max(1, o.spread_candidates_factor) : n;
      auto orb = cv::ORB::create(candidates, static_cast<float>(o.orb_scale_factor), o.orb_levels,
                                 31, 0, 2, cv::ORB::HARRIS_SCORE, 31, o.orb_fast_threshold);
      return std::make_unique<OpenCvExtractor>("orb", orb, orb, true, n, o.spread_cell_px);
    }
    case Detector::kSift: {
      auto sift = cv::SIFT::create(n, 3, o.sift_contrast_threshold);
      return std::make_unique<OpenCvExtractor>("sift", sift, sift, false, n);
    }
    case Detector::kAkaze: {
      auto akaze = cv::AKAZE::create(cv::AKAZE::DESCRIPTOR_MLDB, 0, 3,
                                     static_cast<float>(o.akaze_threshold));
      return std::make_unique<OpenCvExtractor>("akaze", akaze, akaze, true, n);
    }
    case Detector::kGfttOrb: {
      auto gftt = cv::GFTTDetector::create(n, o.gftt_quality, o.gftt_min_distance_px, 3, false);
      auto orb = cv::ORB::create(n, static_cast<float>(o.orb_scale_factor), o.orb_levels, 31, 0, 2,
                                 cv::ORB::HARRIS_SCORE, 31, o.orb_fast_threshold);
      return std::make_unique<OpenCvExtractor>("gftt_orb", gftt, orb, true, n);
    }
    case Detector::kSurf: {
      SurfOptions surf;
      surf.detector.hessian_threshold = o.surf_hessian_threshold;
      surf.detector.octaves = o.surf_octaves;
      surf.detector.intervals = o.surf_intervals;
      surf.upright = o.surf_upright;
      surf.max_keypoints = n;
      return std::make_unique<SurfExtractor>(surf);
    }
  }
  return nullptr;  // unreachable: every Detector is handled above
}

double PyramidPixelSigma(const cv::KeyPoint& k, double scale_factor) {
  if (scale_factor <= 1.0 || k.octave <= 0) return 1.0;
  return std::pow(scale_factor, std::min(k.octave, 16));
}

}  // namespace icgm
