#include "core/eval/plot_axes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace icgm {

namespace {
constexpr int kShift = 4;  // cv drawing fixed-point bits: 1/16 px
constexpr double kShiftScale = 1 << kShift;
const cv::Scalar kGridColor(232, 232, 232);
const cv::Scalar kFrameColor(110, 110, 110);
const cv::Scalar kTextColor(60, 60, 60);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

cv::Point Fixed(const cv::Point2d& p) {
  return cv::Point(static_cast<int>(std::lround(p.x * kShiftScale)),
                   static_cast<int>(std::lround(p.y * kShiftScale)));
}
}  // namespace

double NiceTickStep(double range, int target_ticks) {
  if (!(range > 0.0) || !std::isfinite(range) || target_ticks < 1) return 1.0;
  const double raw = range / target_ticks;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  // The candidate closest to the raw step on a log scale.
  double best = decade;
  for (double m : {2.0, 5.0, 10.0}) {
    if (std::abs(std::log(m * decade / raw)) < std::abs(std::log(best / raw))) best = m * decade;
  }
  return best;
}

std::vector<double> TickValues(double lo, double hi, double step) {
  std::vector<double> out;
  if (!(step > 0.0) || !(hi >= lo)) return out;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1.0) {
    out.push_back(std::abs(k) < 0.5 ? 0.0 : k * step);
  }
  return out;
}

std::string FormatTick(double value, double step) {
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 6);
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, std::abs(value) < 0.5 * step ? 0.0 : value);
  return buf;
}

PlotAxes::PlotAxes(const cv::Rect& area_px, double x_min, double x_max, double y_min, double y_max)
    : area_(area_px), x_min_(x_min), x_max_(x_max), y_min_(y_min), y_max_(y_max) {
  if (!(x_max_ > x_min_)) {
    x_min_ -= 0.5;
    x_max_ = x_min_ + 1.0;
  }
  if (!(y_max_ > y_min_)) {
    y_min_ -= 0.5;
    y_max_ = y_min_ + 1.0;
  }
}

cv::Point2d PlotAxes::ToPixel(double x, double y) const {
  const double u = area_.x + (x - x_min_) / (x_max_ - x_min_) * area_.width;
  const double v = area_.y + area_.height - (y - y_min_) / (y_max_ - y_min_) * area_.height;
  return {u, v};
}

void PlotAxes::DrawFrame(cv::Mat* canvas, const std::string& x_label,
                         const std::string& y_label) const {
  const double tick_scale = 0.45;
  // Aim for ~80 px between ticks.
  const double x_step = NiceTickStep(x_max_ - x_min_, std::max(2, area_.width / 90));
  const double y_step = NiceTickStep(y_max_ - y_min_, std::max(2, area_.height / 60));
  for (double x : TickValues(x_min_, x_max_, x_step)) {
    const double u = ToPixel(x, 0).x;
    cv::line(*canvas, Fixed({u, double(area_.y)}), Fixed({u, double(area_.br().y)}), kGridColor, 1,
             cv::LINE_AA, kShift);
    const std::string label = FormatTick(x, x_step);
    const cv::Size s = TextSize(label, tick_scale);
    DrawText(canvas, label,
             cv::Point(static_cast<int>(u) - s.width / 2, area_.br().y + 8 + s.height), tick_scale,
             kTextColor);
  }
  for (double y : TickValues(y_min_, y_max_, y_step)) {
    const double v = ToPixel(0, y).y;
    cv::line(*canvas, Fixed({double(area_.x), v}), Fixed({double(area_.br().x), v}), kGridColor, 1,
             cv::LINE_AA, kShift);
    const std::string label = FormatTick(y, y_step);
    const cv::Size s = TextSize(label, tick_scale);
    DrawText(canvas, label, cv::Point(area_.x - 8 - s.width, static_cast<int>(v) + s.height / 2),
             tick_scale, kTextColor);
  }
  cv::rectangle(*canvas, area_, kFrameColor, 1);
  const double label_scale = 0.5;
  const cv::Size xs = TextSize(x_label, label_scale);
  DrawText(canvas, x_label,
           cv::Point(area_.x + (area_.width - xs.width) / 2, area_.br().y + 24 + 2 * xs.height),
           label_scale, kTextColor);
  // Vertical label: draw horizontally into a patch and rotate it.
  const cv::Size ys = TextSize(y_label, label_scale);
  cv::Mat patch(ys.height + 8, ys.width + 4, canvas->type(), cv::Scalar::all(255));
  DrawText(&patch, y_label, cv::Point(2, ys.height + 2), label_scale, kTextColor);
  cv::rotate(patch, patch, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int px = area_.x - 62 - patch.cols / 2;
  const int py = area_.y + (area_.height - patch.rows) / 2;
  const cv::Rect dst(px, py, patch.cols, patch.rows);
  if ((dst & cv::Rect(0, 0, canvas->cols, canvas->rows)) == dst) patch.copyTo((*canvas)(dst));
}

void DrawPolyline(cv::Mat* canvas, const std::vector<cv::Point2d>& points, const cv::Scalar& color,
                  int thickness) {
  if (points.size() < 2) return;
  std::vector<cv::Point> fixed;
  fixed.reserve(points.size());
  for (const auto& p : points) fixed.push_back(Fixed(p));
  cv::polylines(*canvas, fixed, false, color, thickness, cv::LINE_AA, kShift);
}

void DrawText(cv::Mat* canvas, const std::string& text, cv::Point origin, double scale,
              const cv::Scalar& color, int thickness) {
  cv::putText(*canvas, text, origin, kFont, scale, color, thickness, cv::LINE_AA);
}

cv::Size TextSize(const std::string& text, double scale, int thickness) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, thickness, &baseline);
}

Status WritePlotPng(const std::string& png_path, const cv::Mat& image) {
  bool ok = false;
  try {
    ok = cv::imwrite(png_path, image);
  } catch (const cv::Exception& e) {
    return Status::Error("cannot write plot '" + png_path + "': " + e.what());
  }
  if (!ok) return Status::Error("cannot write plot '" + png_path + "'");
  return Status::Ok();
}

}  // namespace icgm
