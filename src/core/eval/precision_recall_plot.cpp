#include "core/eval/precision_recall_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/eval/plot_axes.h"

namespace icgm {

namespace {

const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kText(50, 50, 50);
const cv::Scalar kCurve(180, 119, 31);  // blue
const cv::Scalar kMark(40, 39, 214);    // red

std::string Percent(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f %%", 100.0 * v);
  return buf;
}

}  // namespace

cv::Mat RenderPrecisionRecallPlot(const PrecisionRecallCurve& curve, const std::string& title,
                                  int width_px) {
  const int w = std::max(width_px, 400);
  const int left = 90, right = 30, header = 80, bottom = 70;
  const int plot_h = static_cast<int>(0.7 * w);
  cv::Mat img(header + plot_h + bottom, w, CV_8UC3, kWhite);
  DrawText(&img, title, cv::Point(20, 32), 0.8, kText, 2);
  const std::string summary = std::to_string(curve.queries) + " queries, " +
                              std::to_string(curve.revisits) + " revisits;  recall at 100 % " +
                              "precision " + Percent(curve.recall_at_full_precision);
  DrawText(&img, summary, cv::Point(20, 62), 0.5, kText);
  const PlotAxes axes(cv::Rect(left, header, w - left - right, plot_h), 0.0, 1.0, 0.0, 1.02);
  axes.DrawFrame(&img, "recall", "precision");
  if (curve.points.empty()) {
    DrawText(&img, "no loop candidates", cv::Point(left + 20, header + 40), 0.6, kText);
    return img;
  }
  // From (0, 1) (nothing accepted) through each threshold.
  std::vector<cv::Point2d> line = {axes.ToPixel(0.0, 1.0)};
  for (const PrecisionRecallPoint& p : curve.points) {
    line.push_back(axes.ToPixel(p.recall, p.precision));
  }
  DrawPolyline(&img, line, kCurve, 2);
  if (curve.recall_at_full_precision > 0.0) {
    const cv::Point2d m = axes.ToPixel(curve.recall_at_full_precision, 1.0);
    cv::circle(img,
               cv::Point(static_cast<int>(std::lround(m.x)), static_cast<int>(std::lround(m.y))), 6,
               kMark, 2, cv::LINE_AA);
    char label[64];
    std::snprintf(label, sizeof(label), "threshold %.3g", curve.threshold_at_full_precision);
    DrawText(&img, label, cv::Point(static_cast<int>(m.x) + 10, static_cast<int>(m.y) + 40), 0.5,
             kMark);
  }
  return img;
}

Status WritePrecisionRecallPlot(const std::string& png_path, const PrecisionRecallCurve& curve,
                                const std::string& title, int width_px) {
  return WritePlotPng(png_path, RenderPrecisionRecallPlot(curve, title, width_px));
}

}  // namespace icgm
