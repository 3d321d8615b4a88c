#include "tools/feature_precision_benchmark.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <optional>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/common/progress_bar.h"
#include "core/common/sample_summary.h"
#include "core/common/thread_cpu_time.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/match_reprojection.h"

namespace icgm::tools {

namespace {

double WallMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

struct Variant {
  std::string label;
  FeatureOptions options;
};

}  // namespace

void RunFeaturePrecisionBenchmark(const FeaturePrecisionSettings& s) {
  const CameraIntrinsics intrinsics = LoadCameraIntrinsics(s.camera_yaml);
  const TumDataset dataset = TumDataset::Open(s.tum_dir, intrinsics);
  if (!dataset.has_groundtruth()) {
    throw std::runtime_error(s.tum_dir + " has no groundtruth.txt");
  }
  Trajectory gt = dataset.groundtruth();
  SortByStamp(&gt);
  const size_t n = std::min(dataset.size(), static_cast<size_t>(s.frames));
  std::vector<cv::Mat> gray(n), depth(n);
  std::vector<std::optional<Pose3>> pose(n);
  ProgressBar load(n, "loading");
  for (size_t i = 0; i < n; ++i) {
    cv::cvtColor(dataset.LoadBgr(i), gray[i], cv::COLOR_BGR2GRAY);
    depth[i] = dataset.LoadDepthM(i) * intrinsics.depth_correction;
    pose[i] = PoseAt(gt, dataset.frame(i).stamp, 0.05);
    load.Update(i + 1);
  }
  load.Finish();

  std::vector<Variant> variants;
  for (const Detector detector : {Detector::kOrb, Detector::kSift, Detector::kSurf}) {
    Variant v{NameOf(detector), s.features};
    v.options.detector = detector;
    variants.push_back(v);
  }
  Variant upright{"surf (upright)", s.features};
  upright.options.detector = Detector::kSurf;
  upright.options.surf_upright = true;
  variants.push_back(upright);

  std::printf(
      "%s: %zu frames %dx%d, pairs (i, i+%d), ratio %.2f, correct within %.1f px, "
      "max %d features\n",
      s.tum_dir.c_str(), n, gray[0].cols, gray[0].rows, s.gap, s.matcher.ratio, s.correct_px,
      s.features.max_features);
  std::printf("  %-15s %9s %9s %9s %9s %10s %11s %11s\n", "detector", "kp/frame", "match/pr",
              "w.depth", "correct", "precision", "cpu ms med", "wall ms med");
  const DescriptorMatcher matcher(s.matcher);
  for (const Variant& v : variants) {
    auto extractor = FeatureExtractor::Create(v.options);
    std::vector<FeatureSet> sets(n);
    std::vector<double> cpu_ms, wall_ms;
    double keypoints = 0;
    for (size_t i = 0; i < n; ++i) {
      const double c0 = ThreadCpuMs(), w0 = WallMs();
      sets[i] = extractor->Extract(gray[i]);
      cpu_ms.push_back(ThreadCpuMs() - c0);
      wall_ms.push_back(WallMs() - w0);
      keypoints += sets[i].size();
    }
    double matches = 0, with_depth = 0, correct = 0;
    int pairs = 0;
    for (size_t i = 0; i + s.gap < n; ++i) {
      const size_t j = i + s.gap;
      if (!pose[i] || !pose[j]) continue;
      ++pairs;
      const std::vector<cv::DMatch> m = matcher.Match(sets[i], sets[j]);
      const Pose3 j_from_i = pose[j]->inverse() * *pose[i];
      const std::vector<double> err = MatchReprojectionErrorsPx(
          sets[i].keypoints, sets[j].keypoints, m, depth[i], intrinsics, j_from_i);
      matches += m.size();
      for (const double e : err) {
        if (std::isnan(e)) continue;
        ++with_depth;
        correct += e <= s.correct_px;
      }
    }
    const double p = std::max(pairs, 1);
    std::printf("  %-15s %9.0f %9.0f %9.0f %9.0f %9.1f%% %11.2f %11.2f\n", v.label.c_str(),
                keypoints / n, matches / p, with_depth / p, correct / p,
                with_depth > 0 ? 100.0 * correct / with_depth : 0.0, Summarize(cpu_ms).median,
                Summarize(wall_ms).median);
  }
  std::printf(
      "  (match/pr: ratio-test matches per pair; w.depth: those with depth in frame i; "
      "precision = correct / w.depth;\n   times: detect+describe of one gray frame, "
      "thread CPU time and wall time, one thread)\n");
}

}  // namespace icgm::tools
