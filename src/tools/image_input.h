// Reading an image for feature detection in the tools: an unreadable file or an image too small
// to hold a feature is an error naming the file, never an exception out of OpenCV.
#pragma once

#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace icgm::tools {

// Smaller images cannot hold a feature: the detectors' borders and patches (ORB: 31 px) alone
// are larger, and some OpenCV detectors fail on them instead of returning nothing.
constexpr int kMinFeatureImageSidePx = 16;

// BGR image of `path`; empty with *error set when unreadable or smaller than
// kMinFeatureImageSidePx on a side.
inline cv::Mat ReadImageForFeatures(const std::string& path, std::string* error) {
  cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty()) {
    *error = "cannot read image '" + path + "'";
    return cv::Mat();
  }
  if (image.cols < kMinFeatureImageSidePx || image.rows < kMinFeatureImageSidePx) {
    *error = "image '" + path + "' is " + std::to_string(image.cols) + "x" +
             std::to_string(image.rows) + " pixels, too small for feature detection (at least " +
             std::to_string(kMinFeatureImageSidePx) + "x" +
             std::to_string(kMinFeatureImageSidePx) + ")";
    return cv::Mat();
  }
  return image;
}

}  // namespace icgm::tools
