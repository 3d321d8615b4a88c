// SURF's fast-Hessian detector (Bay, Tuytelaars, Van Gool, "SURF: Speeded Up Robust Features",
// ECCV 2006; Bay, Ess, Tuytelaars, Van Gool, CVIU 110(3) 2008, sec. 3): the determinant of the
// Hessian approximated with box filters on an integral image, det = Dxx Dyy - (0.9 Dxy)^2 with
// each response divided by the filter area, over a scale space of octaves and intervals whose
// filter side is L = 3 (2^(octave+1) (interval+1) + 1) pixels (9, 15, 21, 27; 15, 27, 39, 51;
// ...), sampled every 2^octave pixels. Maxima above the threshold in their 3x3x3 neighbourhood
// are interpolated in x, y and scale by fitting a 3-D quadratic (Brown and Lowe 2002).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace icgm {

struct FastHessianOptions {
  // Minimum determinant of the Hessian, for intensities in [0, 255] and responses divided by
  // the filter area (larger: fewer, stronger blobs).
  double hessian_threshold = 100.0;
  // Scale-space octaves (each doubles the filter-size step and the sampling step).
  int octaves = 4;
  // Filter sizes per octave; maxima are searched in the inner intervals - 2.
  int intervals = 4;
};

// A detected blob: position in pixels, filter side L in pixels (interpolated), Gaussian scale
// s = 1.2 L / 9, the interpolated determinant, the sign of the Laplacian (Dxx + Dyy: +1 dark
// blob on bright ground, -1 bright blob) and the octave it was found in.
struct HessianBlob {
  cv::Point2f position_px;
  float filter_size_px = 0.0f;
  float scale_px = 0.0f;
  float response = 0.0f;
  int laplacian_sign = 0;
  int octave = 0;
};

// Filter side of the box filters at (octave, interval), both counted from 0.
int FastHessianFilterSize(int octave, int interval);

// Storage of the response layers, kept between calls: on images of one size DetectFastHessian
// then allocates no layer again (a fresh 640x480 scale space is ~6 MB of new pages per frame,
// whose page faults cost more than the filtering in a long-running process).
struct FastHessianBuffers {
  std::vector<cv::Mat> layers;
};

// Blobs of an 8-bit gray image given its CV_32S integral image (cv::integral), strongest first.
// `buffers` (optional, not shared between threads) is reused for the response layers; the
// result does not depend on it.
std::vector<HessianBlob> DetectFastHessian(const cv::Mat& integral,
                                           const FastHessianOptions& options,
                                           FastHessianBuffers* buffers = nullptr);

}  // namespace icgm
