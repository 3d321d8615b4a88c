// A 2-D data-to-pixel mapping for drawing figures with OpenCV: a pixel rectangle showing a
// data range, with "nice" ticks (1, 2, 5 x 10^k), grid, frame and axis labels. Data y grows
// upwards on screen.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/status.h"

namespace icgm {

// Tick spacing from {1, 2, 5} x 10^k closest (on a log scale) to range / target_ticks.
double NiceTickStep(double range, int target_ticks);
// Tick values that are multiples of `step` inside [lo, hi].
std::vector<double> TickValues(double lo, double hi, double step);
// Tick label with just enough decimals for `step` ("0.25", "1.5", "-2").
std::string FormatTick(double value, double step);

class PlotAxes {
 public:
  // Shows data [x_min, x_max] x [y_min, y_max] in `area_px`. Empty ranges are widened.
  PlotAxes(const cv::Rect& area_px, double x_min, double x_max, double y_min, double y_max);

  // Pixel position of a data point; may fall outside the area.
  cv::Point2d ToPixel(double x, double y) const;
  const cv::Rect& area() const { return area_; }

  // Grid lines, frame, tick labels and axis labels around the area.
  void DrawFrame(cv::Mat* canvas, const std::string& x_label, const std::string& y_label) const;

 private:
  cv::Rect area_;
  double x_min_, x_max_, y_min_, y_max_;
};

// Drawing helpers with sub-pixel, anti-aliased output.
void DrawPolyline(cv::Mat* canvas, const std::vector<cv::Point2d>& points, const cv::Scalar& color,
                  int thickness);
void DrawText(cv::Mat* canvas, const std::string& text, cv::Point origin, double scale,
              const cv::Scalar& color, int thickness = 1);
// Width and height of `text` as DrawText would draw it.
cv::Size TextSize(const std::string& text, double scale, int thickness = 1);

// Writes a rendered figure as PNG; an unwritable path is an error naming it.
Status WritePlotPng(const std::string& png_path, const cv::Mat& image);

}  // namespace icgm
