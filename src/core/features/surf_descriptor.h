// SURF orientation and descriptor (Bay et al., CVIU 2008, sec. 4), computed on an integral image:
//  - orientation: Haar wavelet responses of side 4s at the points of a radius-6s disc sampled
//    every s, weighted by a Gaussian (sigma 2s); the sum of the responses inside a sliding
//    pi/3 window gives a vector, the longest one the orientation;
//  - descriptor: a 20s square aligned with the orientation, split into 4x4 subregions of 5x5
//    samples; Haar responses of side 2s, turned into the keypoint's frame and weighted by a
//    Gaussian (sigma 3.3s) centred on the keypoint, give per subregion (sum dx, sum |dx|,
//    sum dy, sum |dy|): 64 values normalised to unit length.
// s is the blob's Gaussian scale (1.2 L / 9 for filter side L). U-SURF skips the orientation.
#pragma once

#include <opencv2/core.hpp>

namespace icgm {

inline constexpr int kSurfDescriptorSize = 64;

// Dominant orientation in radians (image frame: x right, y down, angle from x towards y) at
// (x, y) and scale s; 0 when there is no gradient.
double SurfOrientation(const cv::Mat& integral, cv::Point2f position_px, double scale_px);

// Writes the 64 floats of the descriptor at (position, scale, orientation) into `out`.
void SurfDescribe(const cv::Mat& integral, cv::Point2f position_px, double scale_px,
                  double orientation_rad, float* out);

}  // namespace icgm
