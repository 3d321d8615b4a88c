// icgm_benchmark --features: detectors compared on TUM RGB-D frame pairs with ground truth.
// For each detector (ORB, SIFT, the project's SURF and U-SURF) and each pair (i, i + gap):
// detect+describe time per frame (thread CPU time and wall time, one thread), ratio-test
// matches, and their precision: a match with depth in the first frame is correct when the
// back-projected point, moved by the ground-truth relative pose, reprojects within `correct_px`
// of the second frame's keypoint (core/eval/match_reprojection.h).
#pragma once

#include <string>

#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"

namespace icgm::tools {

struct FeaturePrecisionSettings {
  std::string tum_dir;
  std::string camera_yaml;
  int frames = 200;  // frames read from the start of the sequence
  int gap = 1;
  double correct_px = 3.0;
  FeatureOptions features;  // per-detector options; `detector` is overridden
  MatcherOptions matcher;
};

// Prints the comparison to stdout; throws LoadError / std::runtime_error on input failures.
void RunFeaturePrecisionBenchmark(const FeaturePrecisionSettings& settings);

}  // namespace icgm::tools
