// Robust features from an image sequence (thesis ch. 4.1.3-4.1.5): each frame is matched to the
// previous one and the putative matches are filtered with ICGM (icgm_matcher.h).
//
// A keypoint of frame t is robust when a chain of kept matches links it through the frames of
// the window S (`window_size`), counted as the thesis counts them:
//  - kSingle (single-directional ICGM, Fig. 4.2): S frames ending at t, [t-S+1, t]; output at
//    once. S = 2 is ICGM between I_t-1 and I_t (with Thr -> infinity, PIRF with window 2,
//    thesis 4.1.5).
//  - kDouble (double-directional ICGM, Fig. 4.3): the window spans S frames from the past
//    through I_t to the future one, [t-S+2, t+1], and the keypoint is robust when its chain
//    covers the past part [t-S+2, t] or the part [t-S+3, t+1] that includes I_t+1. S = 3 (the
//    thesis's choice, 6.1.3.1: I_t-1, I_t, I_t+1) gives the union of the ICGM sets of
//    (I_t-1, I_t) and (I_t, I_t+1). S >= 3. Frame t is output when frame t+1 arrives (one
//    frame of delay), Flush() outputs the last.
//  - kPirf (PIRF baseline, Kawewong et al. 2010; thesis ch. 4.1.5: ICGM with Thr -> infinity):
//    plain descriptor matches, window [t-S+1, t].
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/time.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/icgm_matcher.h"

namespace icgm {

class OptionReader;

// Robust feature tracking (`tracker.mode`, the feature_extraction nodelet's `~mode`).
enum class TrackerMode { kSingle, kDouble, kPirf };

template <>
struct EnumNames<TrackerMode> {
  static constexpr EnumName<TrackerMode> kNames[] = {{TrackerMode::kSingle, "single"},
                                                     {TrackerMode::kDouble, "double"},
                                                     {TrackerMode::kPirf, "pirf"}};
};

struct TrackerOptions {
  TrackerMode mode = TrackerMode::kDouble;
  // Window S in frames, as the thesis counts it (above): >= 2, and >= 3 for kDouble (the
  // tracker raises a smaller value to its mode's minimum; ReadOptions rejects it).
  int window_size = 3;
  FeatureOptions features;
  MatcherOptions matcher;
  IcgmOptions icgm;
};

// Smallest window S of a mode: 3 for kDouble (I_t-1, I_t, I_t+1), else 2.
int MinWindowSize(TrackerMode mode);

// Fills `options` from a `tracker:` section (mode, window_size) and the sibling sections of
// `root` (`features:`, `matcher:`, `icgm:`); throws LoadError on bad values.
void ReadOptions(const OptionReader& root, TrackerOptions* options);

struct TrackedFrame {
  Time stamp;
  FeatureSet features;
  // query = this frame, train = previous frame. Empty for the first frame.
  std::vector<cv::DMatch> matches_to_previous;
  // Per entry of matches_to_previous, 1 = kept by ICGM (all 1 in kPirf mode).
  std::vector<uint8_t> match_kept;
  // Per keypoint, 1 = robust in the sense of the tracker mode and window.
  std::vector<uint8_t> robust;
  // Per keypoint, number of consecutive kept links backwards (0: not matched to previous).
  std::vector<int> track_length;
  // Outcome of ICGM against the previous frame (ok for the first frame) and the Thr it used
  // (differs from the configured one with icgm.auto_threshold; 0 for the first frame / PIRF).
  Status icgm_status = Status::Ok();
  double icgm_threshold_used = 0.0;

  size_t NumRobust() const;
};

class RobustFeatureTracker {
 public:
  explicit RobustFeatureTracker(const TrackerOptions& options);
  ~RobustFeatureTracker();

  // Extracts features and adds the frame. Returns the frame that became complete: this frame
  // (kSingle, kPirf) or the previous one (kDouble; nothing after the first call).
  std::optional<TrackedFrame> AddImage(const Time& stamp, const cv::Mat& image_bgr_or_gray);
  // Same with features computed elsewhere.
  std::optional<TrackedFrame> AddFeatures(const Time& stamp, FeatureSet features);
  // Ends the sequence (the next frame starts a new one, as after Reset). kDouble: returns the
  // held-back last frame, robust from the backward window only; other modes return nothing.
  std::optional<TrackedFrame> Flush();
  // kDouble: the held-back last frame as Flush returns it (robust from the backward window
  // only), but the sequence goes on: the next frame still links to it. Other modes: nothing.
  std::optional<TrackedFrame> PeekLast() const;
  // Forgets all frames (e.g. after a sequence break).
  void Reset();

  const TrackerOptions& options() const { return options_; }

 private:
  TrackerOptions options_;
  std::unique_ptr<FeatureExtractor> extractor_;
  DescriptorMatcher matcher_;
  // Last frame received and, in kDouble mode, whether it has been output.
  std::optional<TrackedFrame> last_;
  // kDouble: per keypoint of last_, kept forward link to the next frame.
  std::vector<uint8_t> last_forward_;
  uint64_t frame_count_ = 0;
};

}  // namespace icgm
