#include "core/eval/trajectory_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "core/eval/plot_axes.h"

namespace icgm {

namespace {

// Colours (BGR), a muted palette that survives greyscale printing.
const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kText(50, 50, 50);
const cv::Scalar kSubtleText(120, 120, 120);
const cv::Scalar kGroundTruth(70, 70, 70);
const cv::Scalar kEstimate(180, 119, 31);    // blue
const cv::Scalar kError(40, 39, 214);        // red
const cv::Scalar kErrorFill(240, 220, 200);  // light blue
const cv::Scalar kStart(44, 160, 44);        // green
constexpr char kAxisNames[3] = {'x', 'y', 'z'};

std::string Format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

// Metres shown as cm below 1 m for readability.
std::string Length(double m) {
  return std::abs(m) < 1.0 ? Format("%.2f cm", 100.0 * m) : Format("%.3f m", m);
}

// Splits a trajectory into runs without time gaps, projected onto axes (a0, a1).
std::vector<std::vector<cv::Point2d>> Runs(const Trajectory& t, const SimilarityTransform* align,
                                           int a0, int a1, const PlotAxes& axes, double max_gap_s) {
  std::vector<std::vector<cv::Point2d>> runs(1);
  for (size_t i = 0; i < t.size(); ++i) {
    if (i > 0 && DurationSeconds(t[i].stamp, t[i - 1].stamp) > max_gap_s) runs.emplace_back();
    const Eigen::Vector3d p =
        align ? align->Apply(t[i].pose.translation()) : t[i].pose.translation();
    runs.back().push_back(axes.ToPixel(p(a0), p(a1)));
  }
  return runs;
}

void DrawTopView(cv::Mat* img, const cv::Rect& area, const Trajectory& gt, const Trajectory& est,
                 const TrajectoryEvaluation& ev, const TrajectoryPlotOptions& opt) {
  // Extent of everything drawn, per world axis.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  auto grow = [&](const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const auto& sp : gt) grow(sp.pose.translation());
  for (const auto& sp : est) grow(ev.alignment.Apply(sp.pose.translation()));
  const Eigen::Vector3d extent = hi - lo;
  // The two axes with most extent, kept in x, y, z order.
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int a, int b) { return extent(a) > extent(b); });
  const int a0 = std::min(order[0], order[1]);
  const int a1 = std::max(order[0], order[1]);

  // Equal metres per pixel on both axes, 6% padding, centred.
  const double span0 = std::max(extent(a0), 1e-3) * 1.12;
  const double span1 = std::max(extent(a1), 1e-3) * 1.12;
  const double m_per_px = std::max(span0 / area.width, span1 / area.height);
  const double c0 = 0.5 * (lo(a0) + hi(a0)), c1 = 0.5 * (lo(a1) + hi(a1));
  const double h0 = 0.5 * m_per_px * area.width, h1 = 0.5 * m_per_px * area.height;
  const PlotAxes axes(area, c0 - h0, c0 + h0, c1 - h1, c1 + h1);
  axes.DrawFrame(img, std::string(1, kAxisNames[a0]) + " [m]",
                 std::string(1, kAxisNames[a1]) + " [m]");

  // Error connectors, translucent so the paths stay readable.
  cv::Mat overlay = img->clone();
  const size_t stride = std::max<size_t>(1, ev.num_associated() / 300);
  for (size_t k = 0; k < ev.num_associated(); k += stride) {
    const Eigen::Vector3d g = ev.groundtruth[k].translation();
    const Eigen::Vector3d e = ev.aligned_estimate[k].translation();
    DrawPolyline(&overlay, {axes.ToPixel(g(a0), g(a1)), axes.ToPixel(e(a0), e(a1))}, kError, 1);
  }
  cv::addWeighted(overlay, 0.45, *img, 0.55, 0.0, *img);

  for (const auto& run : Runs(gt, nullptr, a0, a1, axes, opt.max_line_gap_s)) {
    DrawPolyline(img, run, kGroundTruth, 2);
  }
  const auto est_runs = Runs(est, &ev.alignment, a0, a1, axes, opt.max_line_gap_s);
  for (const auto& run : est_runs) DrawPolyline(img, run, kEstimate, 1);
  if (!est_runs.front().empty()) {
    cv::circle(*img, est_runs.front().front(), 6, kStart, -1, cv::LINE_AA);
    const cv::Point2d end = est_runs.back().back();
    cv::rectangle(*img, cv::Rect(int(end.x) - 5, int(end.y) - 5, 11, 11), kError, -1);
  }

  // Legend, top right inside the plot.
  const std::string est_label = ev.alignment.scale != 1.0 ? "estimate (Sim(3) aligned, s = " +
                                                                Format("%.3f)", ev.alignment.scale)
                                                          : std::string("estimate (SE(3) aligned)");
  const std::vector<std::string> labels = {"ground truth", est_label, "position error", "start",
                                           "end"};
  int text_w = 0;
  for (const auto& l : labels) text_w = std::max(text_w, TextSize(l, 0.45).width);
  const int row_h = 22;
  const cv::Rect box(area.br().x - text_w - 70, area.y + 10, text_w + 60,
                     row_h * static_cast<int>(labels.size()) + 12);
  cv::rectangle(*img, box, kWhite, -1);
  cv::rectangle(*img, box, cv::Scalar(200, 200, 200), 1);
  for (size_t i = 0; i < labels.size(); ++i) {
    const int y = box.y + 6 + row_h * static_cast<int>(i) + row_h / 2;
    const cv::Point2d a(box.x + 10, y), b(box.x + 40, y);
    if (i == 0) DrawPolyline(img, {a, b}, kGroundTruth, 2);
    if (i == 1) DrawPolyline(img, {a, b}, kEstimate, 2);
    if (i == 2) DrawPolyline(img, {a, b}, kError, 1);
    if (i == 3) cv::circle(*img, (a + b) * 0.5, 6, kStart, -1, cv::LINE_AA);
    if (i == 4) cv::rectangle(*img, cv::Rect(box.x + 20, y - 5, 11, 11), kError, -1);
    DrawText(img, labels[i], cv::Point(box.x + 50, y + 5), 0.45, kText);
  }
}

void DrawAteOverTime(cv::Mat* img, const cv::Rect& area, const TrajectoryEvaluation& ev) {
  const double t0 = ev.stamps.front().seconds();
  const double duration = std::max(DurationSeconds(ev.stamps.back(), ev.stamps.front()), 1e-3);
  const double top = std::max(ev.ate.max, 1e-6) * 1.15;
  // Errors in cm when small, so tick labels stay short.
  const double unit = ev.ate.max < 1.0 ? 100.0 : 1.0;
  const PlotAxes axes(area, 0.0, duration, 0.0, top * unit);
  axes.DrawFrame(img, "time [s]", unit == 100.0 ? "ATE [cm]" : "ATE [m]");

  std::vector<cv::Point2d> curve;
  for (size_t k = 0; k < ev.num_associated(); ++k) {
    curve.push_back(axes.ToPixel(ev.stamps[k].seconds() - t0, ev.ate_m[k] * unit));
  }
  std::vector<cv::Point> fill;
  fill.emplace_back(cv::Point(int(curve.front().x), area.br().y));
  for (const auto& p : curve) fill.emplace_back(int(p.x), int(p.y));
  fill.emplace_back(cv::Point(int(curve.back().x), area.br().y));
  cv::fillPoly(*img, std::vector<std::vector<cv::Point>>{fill}, kErrorFill, cv::LINE_AA);
  DrawPolyline(img, curve, kEstimate, 1);

  // RMSE as a dashed line with its value.
  const double y = axes.ToPixel(0, ev.ate.rmse * unit).y;
  for (double x = area.x; x < area.br().x; x += 14) {
    DrawPolyline(img, {{x, y}, {std::min(x + 8.0, double(area.br().x)), y}}, kError, 1);
  }
  // Label on a white patch at the right end, so the curve cannot hide it.
  const std::string label = "RMSE " + Length(ev.ate.rmse);
  const cv::Size ls = TextSize(label, 0.45);
  const cv::Rect patch(area.br().x - ls.width - 14, int(y) - ls.height - 12, ls.width + 10,
                       ls.height + 8);
  if ((patch & area) == patch) {
    cv::rectangle(*img, patch, kWhite, -1);
    DrawText(img, label, cv::Point(patch.x + 5, patch.br().y - 4), 0.45, kError);
  }
}

}  // namespace

cv::Mat RenderTrajectoryPlot(const Trajectory& groundtruth, const Trajectory& estimate,
                             const TrajectoryEvaluation& evaluation,
                             const TrajectoryPlotOptions& options) {
  const int w = std::max(options.width_px, 500);
  const int left = 95, right = 30;
  const int header = 78;
  const int top_h = static_cast<int>(0.62 * w);
  const int gap = 80;
  const int bottom_h = static_cast<int>(0.2 * w);
  const int h = header + top_h + gap + bottom_h + 60;
  cv::Mat img(h, w, CV_8UC3, kWhite);
  if (groundtruth.empty() || estimate.empty() || evaluation.num_associated() == 0) {
    DrawText(&img, "nothing to plot: empty trajectory or evaluation", cv::Point(left, 60), 0.7,
             kText);
    return img;
  }
  Trajectory gt = groundtruth, est = estimate;
  SortByStamp(&gt);
  SortByStamp(&est);

  const TrajectoryEvaluation& ev = evaluation;
  DrawText(&img, options.title, cv::Point(left - 60, 34), 0.8, kText, 2);
  std::string summary = "ATE  RMSE " + Length(ev.ate.rmse) + "   mean " + Length(ev.ate.mean) +
                        "   median " + Length(ev.ate.median) + "   max " + Length(ev.ate.max);
  if (ev.rpe_translation_m_per_s.count > 0) {
    summary += "     RPE  " + Length(ev.rpe_translation_m_per_s.rmse) + "/s   " +
               Format("%.2f deg/s", ev.rpe_rotation_deg_per_s.rmse);
  }
  DrawText(&img, summary, cv::Point(left - 60, 62), 0.5, kText);
  const std::string count = Format("%.0f poses", double(ev.num_associated()));
  DrawText(&img, count, cv::Point(w - right - TextSize(count, 0.5).width, 34), 0.5, kSubtleText);

  DrawTopView(&img, cv::Rect(left, header, w - left - right, top_h), gt, est, ev, options);
  DrawAteOverTime(&img, cv::Rect(left, header + top_h + gap, w - left - right, bottom_h), ev);
  return img;
}

Status WriteTrajectoryPlot(const std::string& png_path, const Trajectory& groundtruth,
                           const Trajectory& estimate, const TrajectoryEvaluation& evaluation,
                           const TrajectoryPlotOptions& options) {
  return WritePlotPng(png_path, RenderTrajectoryPlot(groundtruth, estimate, evaluation, options));
}

}  // namespace icgm
