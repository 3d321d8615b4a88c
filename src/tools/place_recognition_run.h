// One run of appearance-only place recognition over an image sequence, shared by the modes of
// icgm_place_recognition (one run, or a table of runs over tracker modes, ICGM thresholds or
// the recognizer's checks): each image's features, with the ICGM verification of the tracker
// mode (double, single, pirf; none: plain features), go through core/place's PlaceRecognizer.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/eval/precision_recall.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/map/visual_dictionary.h"
#include "core/place/place_recognizer.h"

namespace icgm::tools {

struct PlaceRunSettings {
  std::string robust = "double";  // double | single | pirf | none
  TrackerOptions tracker;
  DictionaryOptions dictionary;
  PlaceRecognitionOptions place;
  bool keep_scores = false;  // decisions carry every earlier image's score (diagnostics)
  std::optional<CameraIntrinsics> camera;  // essential-matrix check when known; with depth and
                                           // place.geometry.rgbd, lifts keypoints to 3-D
};

struct PlaceRunResult {
  std::vector<PlaceDecision> decisions;  // one per image, in order
  std::vector<PlaceQuery> queries;       // the accepted loops (candidate -1: none), for P/R
  int words = 0;
  double verified_share = 0.0;  // ICGM-verified share of all features
  double mean_query_ms = 0.0;   // thread CPU of the query and its checks per image (not
                                // features, ICGM or the insertion)
  std::string detector;
};

// Image i of `count` (BGR); empty with *error set when it cannot be had. `depth_m` (may be
// null): receives the registered depth image (CV_32FC1 metres, NaN = none) when there is one.
using ImageSource = std::function<cv::Mat(size_t i, std::string* error, cv::Mat* depth_m)>;

// `progress` (optional) is told the images done. Fails with the image and reason.
Status RunPlaceRecognition(size_t count, const ImageSource& images,
                           const PlaceRunSettings& settings,
                           const std::function<void(size_t)>& progress, PlaceRunResult* result);

}  // namespace icgm::tools
