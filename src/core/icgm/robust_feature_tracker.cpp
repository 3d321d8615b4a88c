#include "core/icgm/robust_feature_tracker.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "core/common/option_reader.h"

namespace icgm {

int MinWindowSize(TrackerMode mode) { return mode == TrackerMode::kDouble ? 3 : 2; }

void ReadOptions(const OptionReader& root, TrackerOptions* options) {
  const OptionReader tracker = root.Section("tracker");
  tracker.ReadEnum("mode", &options->mode);
  tracker.Read("window_size", &options->window_size, 2, 100);
  if (options->window_size < MinWindowSize(options->mode)) {
    throw LoadError("tracker.window_size: " + std::string(NameOf(options->mode)) +
                    "-directional ICGM needs S >= " + std::to_string(MinWindowSize(options->mode)) +
                    " (the frames I_t-1, I_t, I_t+1), not " + std::to_string(options->window_size));
  }
  const OptionReader features = root.Section("features");
  const OptionReader matcher = root.Section("matcher");
  const OptionReader icgm = root.Section("icgm");
  ReadOptions(features, &options->features);
  ReadOptions(matcher, &options->matcher);
  ReadOptions(icgm, &options->icgm);
  OptionReader::RejectUnknownKeys({&tracker, &features, &matcher, &icgm, &root});
}

size_t TrackedFrame::NumRobust() const {
  return static_cast<size_t>(std::count(robust.begin(), robust.end(), uint8_t{1}));
}

RobustFeatureTracker::RobustFeatureTracker(const TrackerOptions& options)
    : options_(options),
      extractor_(FeatureExtractor::Create(options.features)),
      matcher_(options.matcher) {
  options_.window_size = std::max(MinWindowSize(options_.mode), options_.window_size);
}

RobustFeatureTracker::~RobustFeatureTracker() = default;

void RobustFeatureTracker::Reset() {
  last_.reset();
  last_forward_.clear();
  frame_count_ = 0;
}

std::optional<TrackedFrame> RobustFeatureTracker::AddImage(const Time& stamp,
                                                           const cv::Mat& image_bgr_or_gray) {
  FeatureSet features;
  if (extractor_) features = extractor_->Extract(image_bgr_or_gray);
  return AddFeatures(stamp, std::move(features));
}

namespace {

// Robust flags from backward chains (and, for kDouble, a kept forward link). kSingle, kPirf:
// the keypoint is tracked through the S frames ending at t (S-1 links). kDouble: through the
// S-1 frames ending at t (S-2 links), or through the S-2 frames ending at t plus t+1.
void ComputeRobust(TrackerMode mode, int window, const std::vector<uint8_t>* forward,
                   TrackedFrame* frame) {
  const int backward_links = mode == TrackerMode::kDouble ? window - 2 : window - 1;
  frame->robust.assign(frame->features.size(), 0);
  for (size_t k = 0; k < frame->robust.size(); ++k) {
    const int length = frame->track_length[k];
    bool robust = length >= backward_links;
    if (!robust && mode == TrackerMode::kDouble && forward && (*forward)[k]) {
      robust = length >= backward_links - 1;
    }
    frame->robust[k] = robust ? 1 : 0;
  }
}

}  // namespace

std::optional<TrackedFrame> RobustFeatureTracker::AddFeatures(const Time& stamp,
                                                              FeatureSet features) {
  TrackedFrame frame;
  frame.stamp = stamp;
  frame.features = std::move(features);
  frame.track_length.assign(frame.features.size(), 0);

  if (last_) {
    frame.matches_to_previous = matcher_.Match(frame.features, last_->features);
    frame.match_kept.assign(frame.matches_to_previous.size(), 0);
    if (options_.mode == TrackerMode::kPirf) {
      std::fill(frame.match_kept.begin(), frame.match_kept.end(), uint8_t{1});
    } else {
      // a: the previous frame (train side), b: this frame (query side).
      std::vector<Eigen::Vector2d> a;
      std::vector<Eigen::Vector2d> b;
      MatchedPoints(frame.features.keypoints, last_->features.keypoints,
                    frame.matches_to_previous, &b, &a);
      IcgmOptions icgm = options_.icgm;
      // A different draw sequence per frame pair, still reproducible from rng_seed.
      icgm.rng_seed = options_.icgm.rng_seed + frame_count_;
      IcgmResult result = RunIcgm(a, b, icgm);
      frame.match_kept = std::move(result.kept);
      frame.icgm_status = std::move(result.status);
      frame.icgm_threshold_used = result.threshold_used;
    }
    if (last_forward_.size() != last_->features.size()) {
      last_forward_.assign(last_->features.size(), 0);
    }
    for (size_t m = 0; m < frame.matches_to_previous.size(); ++m) {
      if (!frame.match_kept[m]) continue;
      const cv::DMatch& match = frame.matches_to_previous[m];
      const int previous_length = last_->track_length[match.trainIdx];
      frame.track_length[match.queryIdx] =
          std::min(previous_length, std::numeric_limits<int>::max() - 1) + 1;
      last_forward_[match.trainIdx] = 1;
    }
  }
  ++frame_count_;

  std::optional<TrackedFrame> out;
  if (options_.mode == TrackerMode::kDouble) {
    if (last_) {
      ComputeRobust(options_.mode, options_.window_size, &last_forward_, &*last_);
      out = std::move(*last_);
    }
  } else {
    ComputeRobust(options_.mode, options_.window_size, nullptr, &frame);
    out = frame;
  }
  last_ = std::move(frame);
  last_forward_.assign(last_->features.size(), 0);
  return out;
}

std::optional<TrackedFrame> RobustFeatureTracker::Flush() {
  std::optional<TrackedFrame> out;
  if (options_.mode == TrackerMode::kDouble && last_) {
    ComputeRobust(options_.mode, options_.window_size, nullptr, &*last_);
    out = std::move(*last_);
  }
  Reset();
  return out;
}

std::optional<TrackedFrame> RobustFeatureTracker::PeekLast() const {
  if (options_.mode != TrackerMode::kDouble || !last_) return std::nullopt;
  TrackedFrame out = *last_;
  ComputeRobust(options_.mode, options_.window_size, nullptr, &out);
  return out;
}

}  // namespace icgm
