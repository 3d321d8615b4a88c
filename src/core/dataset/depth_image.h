// Canonical depth in the core: cv::Mat CV_32FC1 in metres, NaN where there is no valid
// measurement.
#pragma once

#include <opencv2/core.hpp>

namespace icgm {

// Converts a raw depth image to canonical metric depth.
//   CV_16UC1: depth_m = value / depth_scale (0 = invalid); depth_scale must be > 0.
//   CV_32FC1: value is already metres (depth_scale ignored); NaN/inf/<= 0 = invalid.
// Pixels outside [min_m, max_m] become NaN. Any other type, an empty input, a non-positive
// depth_scale for uint16 input or min_m > max_m gives an empty Mat.
cv::Mat ToMetricDepth(const cv::Mat& raw, double depth_scale, double min_m = 0.0,
                      double max_m = 1e9);
// The same into *depth_m: its buffer is reused when it is already CV_32FC1 of raw's size (the
// caller's own buffer: nothing else may read it), else a new one is allocated. False (and
// *depth_m empty) where ToMetricDepth gives an empty Mat.
bool ToMetricDepth(const cv::Mat& raw, double depth_scale, cv::Mat* depth_m, double min_m = 0.0,
                   double max_m = 1e9);

// Number of finite (valid) pixels of a canonical depth image.
int CountValidDepth(const cv::Mat& depth_m);

}  // namespace icgm
