// Constant-time box sums on an integral image (Viola-Jones 2001), the building block of the
// SURF box filters and Haar wavelets (Bay et al. 2008, sec. 2). The integral image is the
// (rows + 1) x (cols + 1) CV_32S output of cv::integral on an 8-bit image.
#pragma once

#include <algorithm>

#include <opencv2/core.hpp>

namespace icgm {

// Sum of the pixels in columns [x0, x1) and rows [y0, y1); the caller keeps the rectangle
// inside the image (0 <= x0 <= x1 <= cols, 0 <= y0 <= y1 <= rows).
inline int BoxSum(const cv::Mat& integral, int x0, int y0, int x1, int y1) {
  const int* top = integral.ptr<int>(y0);
  const int* bottom = integral.ptr<int>(y1);
  return bottom[x1] - bottom[x0] - top[x1] + top[x0];
}

// BoxSum with the rectangle clipped to the image (pixels outside count as zero).
inline int ClippedBoxSum(const cv::Mat& integral, int x0, int y0, int x1, int y1) {
  const int cols = integral.cols - 1;
  const int rows = integral.rows - 1;
  x0 = std::clamp(x0, 0, cols);
  x1 = std::clamp(x1, 0, cols);
  y0 = std::clamp(y0, 0, rows);
  y1 = std::clamp(y1, 0, rows);
  if (x1 <= x0 || y1 <= y0) return 0;
  return BoxSum(integral, x0, y0, x1, y1);
}

// Haar wavelet responses of side 2 * half_px centred on pixel corner (x, y): right half minus
// left half (x) and lower half minus upper half (y), clipped at the image border.
inline void HaarXY(const cv::Mat& integral, int x, int y, int half_px, float* dx, float* dy) {
  const int x0 = x - half_px, x1 = x + half_px, y0 = y - half_px, y1 = y + half_px;
  if (x0 >= 0 && y0 >= 0 && x1 < integral.cols && y1 < integral.rows) {
    // Inside: six corners shared by the four half boxes.
    const int* top = integral.ptr<int>(y0);
    const int* centre = integral.ptr<int>(y);
    const int* bottom = integral.ptr<int>(y1);
    const int left = bottom[x] - bottom[x0] - top[x] + top[x0];
    const int right = bottom[x1] - bottom[x] - top[x1] + top[x];
    const int upper = centre[x1] - centre[x0] - top[x1] + top[x0];
    const int lower = bottom[x1] - bottom[x0] - centre[x1] + centre[x0];
    *dx = static_cast<float>(right - left);
    *dy = static_cast<float>(lower - upper);
    return;
  }
  *dx = static_cast<float>(ClippedBoxSum(integral, x, y0, x1, y1) -
                           ClippedBoxSum(integral, x0, y0, x, y1));
  *dy = static_cast<float>(ClippedBoxSum(integral, x0, y, x1, y1) -
                           ClippedBoxSum(integral, x0, y0, x1, y));
}

}  // namespace icgm
