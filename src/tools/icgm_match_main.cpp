// icgm_match: putative descriptor matches between two images filtered by ICGM (thesis
// Algorithm 1). Writes every putative match with its verdict as CSV, optionally draws the kept
// (green) and rejected (red) matches side by side and plots the kept count against 1/Thr
// (thesis Fig. 5.1).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/option_reader.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/icgm_matcher.h"
#include "tools/cli_args.h"
#include "tools/image_input.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_match A.png B.png --out matches.csv [--detector orb|sift|akaze|gftt_orb|surf]\n"
    "                  [--thr 0.08] [--auto-thr] [--seed N] [--seeds K] [--refine]\n"
    "                  [--config config/icgm.yaml] [--draw out.png] [--sweep sweep.png]";
constexpr icgm::tools::ToolInfo kTool{"icgm_match", kUsage};

int BadArguments(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

// Faded grey copy of the image so that coloured match lines stand out.
cv::Mat Faded(const cv::Mat& image) {
  cv::Mat gray, bgr;
  if (image.channels() == 1) {
    gray = image;
  } else {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  }
  gray.convertTo(gray, CV_8U, 0.45, 140.0);
  cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

void DrawMatches(const cv::Mat& a, const cv::Mat& b, const std::vector<Eigen::Vector2d>& pa,
                 const std::vector<Eigen::Vector2d>& pb, const icgm::IcgmResult& result,
                 const std::string& path) {
  const cv::Mat left = Faded(a);
  const cv::Mat right = Faded(b);
  const int header = 28;
  cv::Mat canvas(std::max(left.rows, right.rows) + header, left.cols + right.cols, CV_8UC3,
                 cv::Scalar(255, 255, 255));
  left.copyTo(canvas(cv::Rect(0, header, left.cols, left.rows)));
  right.copyTo(canvas(cv::Rect(left.cols, header, right.cols, right.rows)));
  const cv::Point2d offset_a(0, header);
  const cv::Point2d offset_b(left.cols, header);
  // Rejected first so that kept matches are drawn on top.
  for (const int pass : {0, 1}) {
    for (size_t k = 0; k < pa.size(); ++k) {
      if (result.kept[k] != pass) continue;
      const cv::Scalar color = pass ? cv::Scalar(0, 170, 0) : cv::Scalar(0, 0, 230);
      const cv::Point2d p(pa[k].x(), pa[k].y());
      const cv::Point2d q(pb[k].x(), pb[k].y());
      cv::line(canvas, p + offset_a, q + offset_b, color, 1, cv::LINE_AA);
      cv::circle(canvas, p + offset_a, 3, color, cv::FILLED, cv::LINE_AA);
      cv::circle(canvas, q + offset_b, 3, color, cv::FILLED, cv::LINE_AA);
    }
  }
  char text[160];
  std::snprintf(text, sizeof(text), "ICGM Thr=%.3f  kept %zu (green)  rejected %zu (red)",
                result.threshold_used, result.num_kept, pa.size() - result.num_kept);
  cv::putText(canvas, text, cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  if (!cv::imwrite(path, canvas)) throw std::runtime_error("cannot write '" + path + "'");
}

std::string Format(double v, const char* fmt) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), fmt, v);
  return buffer;
}

// Kept count against 1/Thr with axes, ticks and labels; the used Thr as a dashed line.
void PlotSweep(const std::vector<Eigen::Vector2d>& pa, const std::vector<Eigen::Vector2d>& pb,
               const icgm::IcgmOptions& options, double thr_used, const std::string& path) {
  constexpr double kInvMin = 2.0;
  constexpr double kInvMax = 50.0;
  constexpr int kSteps = 97;
  std::vector<cv::Point2d> curve;
  for (int s = 0; s < kSteps; ++s) {
    const double inv = kInvMin + (kInvMax - kInvMin) * s / (kSteps - 1);
    icgm::IcgmOptions o = options;
    o.auto_threshold = false;
    o.threshold = 1.0 / inv;
    curve.emplace_back(inv, static_cast<double>(icgm::RunIcgm(pa, pb, o).num_kept));
  }
  const int width = 800, height = 500, left = 80, right = 30, top = 50, bottom = 70;
  cv::Mat plot(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const double y_max = std::max<double>(10.0, std::ceil(pa.size() / 50.0) * 50.0);
  auto to_px = [&](double x, double y) {
    return cv::Point(
        static_cast<int>(
            std::lround(left + (x - kInvMin) / (kInvMax - kInvMin) * (width - left - right))),
        static_cast<int>(std::lround(height - bottom - y / y_max * (height - top - bottom))));
  };
  const cv::Scalar black(0, 0, 0), grid(225, 225, 225);
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  for (int t = 0; t <= 5; ++t) {
    const double y = y_max * t / 5.0;
    cv::line(plot, to_px(kInvMin, y), to_px(kInvMax, y), grid, 1);
    cv::line(plot, to_px(kInvMin, y), to_px(kInvMin, y) + cv::Point(-6, 0), black, 1);
    const std::string label = Format(y, "%.0f");
    cv::putText(plot, label, to_px(kInvMin, y) + cv::Point(-12 - 10 * (int)label.size(), 5), font,
                0.45, black, 1, cv::LINE_AA);
  }
  for (double x = 5.0; x <= kInvMax; x += 5.0) {
    cv::line(plot, to_px(x, 0), to_px(x, y_max), grid, 1);
    cv::line(plot, to_px(x, 0), to_px(x, 0) + cv::Point(0, 6), black, 1);
    cv::putText(plot, Format(x, "%.0f"), to_px(x, 0) + cv::Point(-9, 22), font, 0.45, black, 1,
                cv::LINE_AA);
  }
  cv::line(plot, to_px(kInvMin, 0), to_px(kInvMax, 0), black, 1);
  cv::line(plot, to_px(kInvMin, 0), to_px(kInvMin, y_max), black, 1);
  // Used threshold.
  const double inv_used = 1.0 / thr_used;
  if (inv_used >= kInvMin && inv_used <= kInvMax) {
    for (double y = 0; y < y_max; y += y_max / 40.0) {
      cv::line(plot, to_px(inv_used, y), to_px(inv_used, y + y_max / 80.0), cv::Scalar(0, 0, 220),
               1);
    }
    cv::putText(plot, "Thr=" + Format(thr_used, "%.3f"), to_px(inv_used, y_max) + cv::Point(6, 14),
                font, 0.45, cv::Scalar(0, 0, 220), 1, cv::LINE_AA);
  }
  std::vector<cv::Point> poly;
  for (const cv::Point2d& p : curve) poly.push_back(to_px(p.x, p.y));
  cv::polylines(plot, poly, false, cv::Scalar(200, 80, 0), 2, cv::LINE_AA);
  for (const cv::Point& p : poly) cv::circle(plot, p, 2, cv::Scalar(200, 80, 0), cv::FILLED);
  cv::putText(plot, "ICGM kept matches vs 1/Thr (" + std::to_string(pa.size()) + " putative)",
              cv::Point(left, 30), font, 0.6, black, 1, cv::LINE_AA);
  cv::putText(plot, "1/Thr", cv::Point((width + left) / 2 - 20, height - 20), font, 0.55, black, 1,
              cv::LINE_AA);
  cv::Mat ylabel(24, 160, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(ylabel, "kept matches", cv::Point(10, 17), font, 0.55, black, 1, cv::LINE_AA);
  cv::rotate(ylabel, ylabel, cv::ROTATE_90_COUNTERCLOCKWISE);
  ylabel.copyTo(plot(cv::Rect(6, (height - 160) / 2 - 10, ylabel.cols, ylabel.rows)));
  if (!cv::imwrite(path, plot)) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace

int main(int argc, char** argv) {
  icgm::FeatureOptions feature_options;
  icgm::MatcherOptions matcher_options;
  icgm::IcgmOptions icgm_options;
  std::string image_a_path, image_b_path, out_path, draw_path, sweep_path;
  try {
    const icgm::tools::CliArgs args(
        argc, argv, {"detector", "thr", "seed", "seeds", "out", "draw", "sweep", "config"},
        {"auto-thr", "refine"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (args.positional().size() != 2) {
      return BadArguments("expected two images, got " + std::to_string(args.positional().size()));
    }
    image_a_path = args.positional()[0];
    image_b_path = args.positional()[1];
    out_path = args.Require("out");
    draw_path = args.Get("draw");
    sweep_path = args.Get("sweep");
    if (args.Has("config")) {
      const icgm::OptionReader root = icgm::OptionReader::FromFile(args.Get("config"));
      icgm::ReadOptions(root.Section("features"), &feature_options);
      icgm::ReadOptions(root.Section("matcher"), &matcher_options);
      icgm::ReadOptions(root.Section("icgm"), &icgm_options);
    }
    feature_options.detector = args.GetEnum("detector", feature_options.detector);
    icgm_options.threshold = args.GetDouble("thr", icgm_options.threshold);
    if (!(icgm_options.threshold > 0.0 && icgm_options.threshold <= 1.0)) {
      return BadArguments("--thr must be in (0, 1]");
    }
    const int seed = args.GetInt("seed", static_cast<int>(icgm_options.rng_seed));
    if (seed < 0) return BadArguments("--seed must be >= 0");
    icgm_options.rng_seed = static_cast<uint64_t>(seed);
    icgm_options.seed_pairs = args.GetInt("seeds", icgm_options.seed_pairs);
    if (icgm_options.seed_pairs < 1) return BadArguments("--seeds must be >= 1");
    if (args.Has("auto-thr")) icgm_options.auto_threshold = true;
    if (args.Has("refine")) icgm_options.refine = true;
  } catch (const std::invalid_argument& e) {
    return BadArguments(e.what());
  } catch (const icgm::LoadError& e) {
    return BadArguments(e.what());
  }

  try {
    std::string image_error;
    const cv::Mat image_a = icgm::tools::ReadImageForFeatures(image_a_path, &image_error);
    if (image_a.empty()) return icgm::tools::Failure(kTool, image_error);
    const cv::Mat image_b = icgm::tools::ReadImageForFeatures(image_b_path, &image_error);
    if (image_b.empty()) return icgm::tools::Failure(kTool, image_error);
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::duration d) {
      return std::chrono::duration<double, std::milli>(d).count();
    };
    auto extractor = icgm::FeatureExtractor::Create(feature_options);
    const auto t0 = Clock::now();
    const icgm::FeatureSet fa = extractor->Extract(image_a);
    const icgm::FeatureSet fb = extractor->Extract(image_b);
    const auto t1 = Clock::now();
    const std::vector<cv::DMatch> matches = icgm::DescriptorMatcher(matcher_options).Match(fa, fb);
    const auto t2 = Clock::now();
    std::vector<Eigen::Vector2d> pa, pb;
    icgm::MatchedPoints(fa.keypoints, fb.keypoints, matches, &pa, &pb);
    const icgm::IcgmResult result = icgm::RunIcgm(pa, pb, icgm_options);
    const auto t3 = Clock::now();

    std::ofstream out(out_path);
    if (!out) {
      std::cerr << "icgm_match: cannot write '" << out_path << "'" << std::endl;
      return 1;
    }
    out << "xa,ya,xb,yb,kept\n";
    for (size_t k = 0; k < pa.size(); ++k) {
      out << pa[k].x() << ',' << pa[k].y() << ',' << pb[k].x() << ',' << pb[k].y() << ','
          << static_cast<int>(result.kept[k]) << '\n';
    }
    if (!out) {
      std::cerr << "icgm_match: write to '" << out_path << "' failed" << std::endl;
      return 1;
    }
    std::printf("detector %s: %zu / %zu keypoints\n", extractor->name().c_str(), fa.size(),
                fb.size());
    std::printf("putative %zu  kept %zu  rejected %zu  Thr %.4f%s\n", matches.size(),
                result.num_kept, matches.size() - result.num_kept, result.threshold_used,
                icgm_options.auto_threshold ? " (auto)" : "");
    if (!result.status.ok()) std::printf("note: %s\n", result.status.reason().c_str());
    std::printf("time: detect+describe %.2f ms  match %.2f ms  icgm %.3f ms\n", ms(t1 - t0),
                ms(t2 - t1), ms(t3 - t2));
    if (!draw_path.empty()) DrawMatches(image_a, image_b, pa, pb, result, draw_path);
    if (!sweep_path.empty()) PlotSweep(pa, pb, icgm_options, result.threshold_used, sweep_path);
  } catch (const std::exception& e) {
    std::cerr << "icgm_match: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
