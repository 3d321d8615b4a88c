// icgm_benchmark: per-frame cost of the robust-feature front end on consecutive TUM RGB-D
// colour frames (detect+describe, match to the previous frame, ICGM), single-threaded, plus
// ICGM alone on 2,000 synthetic matches. With --thr-sweep it also reports, per Thr, how ICGM
// agrees with a RANSAC fundamental-matrix inlier set (a geometric reference on a static scene).
// With --features it compares ORB, SIFT and the project's SURF instead: matching precision
// against ground truth, matches, and detect+describe time (feature_precision_benchmark.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/common/option_reader.h"
#include "core/common/progress_bar.h"
#include "core/common/sample_summary.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/icgm_matcher.h"
#include "core/icgm/robust_feature_tracker.h"
#include "tools/cli_args.h"
#include "tools/feature_precision_benchmark.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_benchmark [--tum /work/shared/data/tum_fr1_xyz] [--detector orb] [--frames N]\n"
    "                      [--config config/icgm.yaml] [--binary-index bf|lsh] [--gap G]\n"
    "                      [--thr-sweep] [--ransac-px 2.0] [--tracker]\n"
    "       icgm_benchmark --features [--tum DIR] [--camera config/camera/tum_fr1.yaml]\n"
    "                      [--frames N] [--gap G] [--correct-px 3] [--config config/icgm.yaml]";
constexpr icgm::tools::ToolInfo kTool{"icgm_benchmark", kUsage};

using Clock = std::chrono::steady_clock;
double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

using Stats = icgm::SampleSummary;
using icgm::Summarize;

void PrintRow(const char* name, const std::vector<double>& v) {
  const Stats s = Summarize(v);
  std::printf("  %-22s mean %8.3f  median %8.3f  p95 %8.3f  max %8.3f ms\n", name, s.mean, s.median,
              s.p95, s.max);
}

// Colour image paths listed in <dir>/rgb.txt, in file order.
std::vector<std::string> ReadRgbList(const std::string& dir) {
  std::ifstream in(dir + "/rgb.txt");
  if (!in) throw icgm::LoadError("cannot open '" + dir + "/rgb.txt'");
  std::vector<std::string> paths;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string stamp, path;
    if (!(fields >> stamp >> path)) {
      throw icgm::LoadError(dir + "/rgb.txt:" + std::to_string(line_no) + ": malformed line");
    }
    paths.push_back(dir + "/" + path);
  }
  return paths;
}

std::vector<icgm::IcgmOptions> IcgmVariants(const icgm::IcgmOptions& base,
                                            std::vector<std::string>* names) {
  std::vector<icgm::IcgmOptions> v;
  icgm::IcgmOptions thesis = base;
  thesis.seed_pairs = 1;
  thesis.refine = false;
  thesis.auto_threshold = false;
  v.push_back(thesis);
  names->push_back("thesis (1 seed)");
  icgm::IcgmOptions configured = base;
  v.push_back(configured);
  names->push_back("configured (" + std::to_string(base.seed_pairs) + " seeds" +
                   (base.refine ? ", refine" : "") + (base.auto_threshold ? ", auto" : "") + ")");
  icgm::IcgmOptions refine = base;
  refine.refine = true;
  v.push_back(refine);
  names->push_back("seeds + refine");
  icgm::IcgmOptions automatic = base;
  automatic.auto_threshold = true;
  v.push_back(automatic);
  names->push_back("seeds + auto Thr");
  return v;
}

void SyntheticIcgmTiming(const icgm::IcgmOptions& base) {
  constexpr int kMatches = 2000;
  constexpr int kRepeats = 300;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ux(0, 640), uy(0, 480);
  std::normal_distribution<double> noise(0, 0.5);
  std::vector<Eigen::Vector2d> a, b;
  const double c = std::cos(0.03), s = std::sin(0.03);
  for (int k = 0; k < kMatches; ++k) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    a.push_back(p);
    if (k % 5 == 0) {  // 20 % outliers
      b.emplace_back(ux(rng), uy(rng));
    } else {
      const Eigen::Vector2d q = p - Eigen::Vector2d(320, 240);
      b.push_back(Eigen::Vector2d(c * q.x() - s * q.y(), s * q.x() + c * q.y()) +
                  Eigen::Vector2d(335 + noise(rng), 231 + noise(rng)));
    }
  }
  std::printf("\nICGM alone on %d synthetic matches (20%% outliers), %d runs each:\n", kMatches,
              kRepeats);
  std::vector<std::string> names;
  const auto variants = IcgmVariants(base, &names);
  for (size_t i = 0; i < variants.size(); ++i) {
    std::vector<double> times;
    size_t kept = 0;
    for (int r = 0; r < kRepeats; ++r) {
      icgm::IcgmOptions o = variants[i];
      o.rng_seed = r;
      const auto t0 = Clock::now();
      kept = icgm::RunIcgm(a, b, o).num_kept;
      times.push_back(Ms(Clock::now() - t0));
    }
    const Stats st = Summarize(times);
    std::printf("  %-34s mean %7.3f  median %7.3f  p95 %7.3f ms   kept %zu\n", names[i].c_str(),
                st.mean, st.median, st.p95, kept);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string tum_dir = "/work/shared/data/tum_fr1_xyz";
  int frames = 200;
  bool thr_sweep = false;
  bool tracker = false;
  int gap = 1;
  double ransac_px = 2.0;
  icgm::FeatureOptions feature_options;
  icgm::MatcherOptions matcher_options;
  icgm::IcgmOptions icgm_options;
  bool features_mode = false;
  icgm::tools::FeaturePrecisionSettings features_settings;
  try {
    const icgm::tools::CliArgs args(
        argc, argv,
        {"tum", "detector", "frames", "config", "binary-index", "gap", "ransac-px", "camera",
         "correct-px"},
        {"thr-sweep", "tracker", "features"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) throw std::invalid_argument("unexpected argument");
    tum_dir = args.Get("tum", tum_dir);
    frames = args.GetInt("frames", frames);
    if (frames < 2) throw std::invalid_argument("--frames must be >= 2");
    if (args.Has("config")) {
      const icgm::OptionReader root = icgm::OptionReader::FromFile(args.Get("config"));
      icgm::ReadOptions(root.Section("features"), &feature_options);
      icgm::ReadOptions(root.Section("matcher"), &matcher_options);
      icgm::ReadOptions(root.Section("icgm"), &icgm_options);
    }
    feature_options.detector = args.GetEnum("detector", feature_options.detector);
    matcher_options.binary_index = args.GetEnum("binary-index", matcher_options.binary_index);
    thr_sweep = args.Has("thr-sweep");
    tracker = args.Has("tracker");
    gap = args.GetInt("gap", gap);
    if (gap < 1 || gap >= frames) throw std::invalid_argument("--gap must be in [1, frames)");
    ransac_px = args.GetDouble("ransac-px", ransac_px);
    if (!(ransac_px > 0.0)) throw std::invalid_argument("--ransac-px must be > 0");
    features_mode = args.Has("features");
    if (!features_mode && (args.Has("camera") || args.Has("correct-px"))) {
      throw std::invalid_argument("--camera and --correct-px need --features");
    }
    if (features_mode && (args.Has("detector") || thr_sweep || tracker)) {
      throw std::invalid_argument("--features compares all detectors: no --detector, "
                                  "--thr-sweep or --tracker");
    }
    features_settings.tum_dir = tum_dir;
    features_settings.camera_yaml = args.Get("camera", "config/camera/tum_fr1.yaml");
    features_settings.frames = frames;
    features_settings.gap = gap;
    features_settings.correct_px = args.GetDouble("correct-px", 3.0);
    if (!(features_settings.correct_px > 0.0)) {
      throw std::invalid_argument("--correct-px must be > 0");
    }
    features_settings.features = feature_options;
    features_settings.matcher = matcher_options;
  } catch (const std::exception& e) {
    return icgm::tools::UsageError(kTool, e.what());
  }

  try {
    cv::setNumThreads(1);
    if (features_mode) {
      icgm::tools::RunFeaturePrecisionBenchmark(features_settings);
      return 0;
    }
    std::vector<std::string> paths = ReadRgbList(tum_dir);
    if (paths.size() < 2) throw icgm::LoadError("fewer than 2 images in " + tum_dir);
    paths.resize(std::min(paths.size(), static_cast<size_t>(frames)));
    std::vector<cv::Mat> images;
    icgm::ProgressBar load(paths.size(), "loading");
    for (const std::string& p : paths) {
      images.push_back(cv::imread(p, cv::IMREAD_COLOR));
      if (images.back().empty()) throw icgm::LoadError("cannot read '" + p + "'");
      load.Update(images.size());
    }
    load.Finish();

    auto extractor = icgm::FeatureExtractor::Create(feature_options);
    const icgm::DescriptorMatcher matcher(matcher_options);
    icgm::MatcherOptions other_options = matcher_options;
    other_options.binary_index = matcher_options.binary_index == icgm::BinaryIndex::kBruteForce
                                     ? icgm::BinaryIndex::kLsh
                                     : icgm::BinaryIndex::kBruteForce;
    const icgm::DescriptorMatcher other(other_options);

    std::vector<double> t_detect, t_match, t_other, t_icgm, t_total;
    double keypoints = 0, putative = 0, kept = 0;
    // Thr sweep against RANSAC fundamental-matrix inliers.
    // The last entry (0) stands for the automatic threshold.
    const std::vector<double> sweep = {0.02, 0.03, 0.04, 0.05, 0.06, 0.08, 0.10, 0.12, 0.15, 0.0};
    std::vector<double> sweep_recall(sweep.size(), 0), sweep_outlier(sweep.size(), 0);
    std::vector<double> sweep_thr(sweep.size(), 0);
    int sweep_pairs = 0;

    // Features of the last `gap` frames; frame i is matched to frame i - gap.
    std::vector<icgm::FeatureSet> history(gap);
    for (size_t i = 0; i < images.size(); ++i) {
      const icgm::FeatureSet& previous = history[i % gap];
      const auto t0 = Clock::now();
      icgm::FeatureSet current = extractor->Extract(images[i]);
      const auto t1 = Clock::now();
      t_detect.push_back(Ms(t1 - t0));
      keypoints += current.size();
      if (i >= static_cast<size_t>(gap)) {
        const auto m0 = Clock::now();
        const std::vector<cv::DMatch> matches = matcher.Match(current, previous);
        const auto m1 = Clock::now();
        std::vector<Eigen::Vector2d> a, b;
        icgm::MatchedPoints(current.keypoints, previous.keypoints, matches, &b, &a);
        const icgm::IcgmResult r = icgm::RunIcgm(a, b, icgm_options);
        const auto m2 = Clock::now();
        t_match.push_back(Ms(m1 - m0));
        t_icgm.push_back(Ms(m2 - m1));
        t_total.push_back(Ms(m2 - t0));
        putative += matches.size();
        kept += r.num_kept;
        if (current.binary) {
          const auto o0 = Clock::now();
          other.Match(current, previous);
          t_other.push_back(Ms(Clock::now() - o0));
        }
        if (thr_sweep && a.size() >= 15) {
          std::vector<cv::Point2f> pa, pb;
          for (size_t k = 0; k < a.size(); ++k) {
            pa.emplace_back(a[k].x(), a[k].y());
            pb.emplace_back(b[k].x(), b[k].y());
          }
          std::vector<uchar> inlier;
          cv::findFundamentalMat(pa, pb, cv::FM_RANSAC, ransac_px, 0.999, inlier);
          if (inlier.size() == a.size()) {
            ++sweep_pairs;
            const double n_in = std::count(inlier.begin(), inlier.end(), 1);
            for (size_t s = 0; s < sweep.size(); ++s) {
              icgm::IcgmOptions o = icgm_options;
              o.threshold = sweep[s] > 0 ? sweep[s] : o.threshold;
              o.auto_threshold = sweep[s] == 0;
              const icgm::IcgmResult rs = icgm::RunIcgm(a, b, o);
              sweep_thr[s] += rs.threshold_used;
              double kept_in = 0, kept_out = 0;
              for (size_t k = 0; k < a.size(); ++k) {
                if (!rs.kept[k]) continue;
                (inlier[k] ? kept_in : kept_out) += 1;
              }
              sweep_recall[s] += n_in > 0 ? kept_in / n_in : 0;
              sweep_outlier[s] += rs.num_kept ? kept_out / rs.num_kept : 0;
            }
          }
        }
      }
      history[i % gap] = std::move(current);
    }

    const size_t pairs = images.size() - gap;
    std::printf(
        "%s: %zu frames %dx%d, gap %d, detector %s, matcher %s, ICGM Thr %.3f%s, %d seed(s)\n",
        tum_dir.c_str(), images.size(), images[0].cols, images[0].rows, gap,
        extractor->name().c_str(),
        extractor->binary() ? icgm::NameOf(matcher_options.binary_index) : "flann-kdtree",
        icgm_options.threshold, icgm_options.auto_threshold ? " (auto)" : "",
        icgm_options.seed_pairs);
    std::printf("  keypoints/frame %.0f  putative/pair %.0f  kept/pair %.0f (%.1f%%)\n",
                keypoints / images.size(), putative / pairs, kept / pairs,
                putative > 0 ? 100.0 * kept / putative : 0.0);
    std::printf("per frame (single thread):\n");
    PrintRow("detect+describe", t_detect);
    PrintRow("match", t_match);
    PrintRow("icgm", t_icgm);
    PrintRow("total", t_total);
    if (!t_other.empty()) {
      const std::string label =
          "match (" + std::string(icgm::NameOf(other_options.binary_index)) + ")";
      PrintRow(label.c_str(), t_other);
    }
    if (thr_sweep && sweep_pairs > 0) {
      std::printf("\nThr sweep vs RANSAC fundamental-matrix inliers (%.1f px), %d pairs:\n",
                  ransac_px, sweep_pairs);
      std::printf("  %6s  %8s  %12s\n", "Thr", "recall", "kept outl.");
      for (size_t s = 0; s < sweep.size(); ++s) {
        std::printf("  %6.3f  %7.1f%%  %11.2f%%%s\n", sweep_thr[s] / sweep_pairs,
                    100 * sweep_recall[s] / sweep_pairs, 100 * sweep_outlier[s] / sweep_pairs,
                    sweep[s] == 0 ? "  (auto, mean Thr)" : "");
      }
    }
    if (tracker) {
      std::printf("\nRobust features per frame (RobustFeatureTracker, frames 1..n-2):\n");
      for (const icgm::TrackerMode mode :
           {icgm::TrackerMode::kPirf, icgm::TrackerMode::kSingle, icgm::TrackerMode::kDouble}) {
        for (const int window : {icgm::MinWindowSize(mode), icgm::MinWindowSize(mode) + 1}) {
          icgm::TrackerOptions options;
          options.mode = mode;
          options.window_size = window;
          options.features = feature_options;
          options.matcher = matcher_options;
          options.icgm = icgm_options;
          icgm::RobustFeatureTracker t(options);
          double robust = 0;
          int counted = 0;
          auto consume = [&](const std::optional<icgm::TrackedFrame>& f) {
            if (!f) return;
            const auto idx = static_cast<size_t>(f->stamp.nanoseconds());
            if (idx == 0 || idx + 1 >= images.size()) return;  // same frames for every mode
            robust += f->NumRobust();
            ++counted;
          };
          for (size_t i = 0; i < images.size(); ++i) {
            consume(t.AddImage(icgm::Time::FromNanoseconds(static_cast<int64_t>(i)), images[i]));
          }
          consume(t.Flush());
          std::printf("  %-6s S=%d  robust/frame %7.1f\n", icgm::NameOf(mode), window,
                      counted ? robust / counted : 0.0);
        }
      }
    }
    SyntheticIcgmTiming(icgm_options);
  } catch (const std::exception& e) {
    std::cerr << "icgm_benchmark: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
