// icgm_place_recognition: appearance-only place recognition over an image sequence (thesis 4.2,
// ICGM-based online-incremental appearance-only SLAM). Each image's ICGM-robust features (ICGM
// against the neighbouring images of the list, single- or double-directional) query the
// incremental dictionary of the earlier images, then are added to it. Writes one CSV row per
// image: query,match,score with match = -1 for a new place. With ground truth (--gt-poses: TUM
// trajectory, a revisit is an earlier image within --revisit-m and --revisit-deg; --gt-matrix:
// an image whose pixel (i, j) > 0 means images i and j show the same place) it prints precision
// and recall at --min-score and the recall at 100 % precision, and draws the precision-recall
// curve swept over the acceptance threshold (core/eval/precision_recall.h).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/common/option_reader.h"
#include "core/common/progress_bar.h"
#include "core/dataset/trajectory.h"
#include "core/eval/place_truth.h"
#include "core/eval/precision_recall.h"
#include "core/eval/precision_recall_plot.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/map/map_options.h"
#include "core/map/visual_dictionary.h"
#include "tools/cli_args.h"
#include "tools/image_input.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_place_recognition --images LIST.txt --out matches.csv\n"
    "                              [--config config/map.yaml] [--icgm-config config/icgm.yaml]\n"
    "                              [--robust double|single|none] [--min-score S]\n"
    "                              [--exclude-recent N]\n"
    "                              [--gt-poses GT.txt [--revisit-m 0.5] [--revisit-deg 30]\n"
    "                               | --gt-matrix TRUTH.png] [--pr-plot PR.png]\n"
    "  --gt-poses: TUM trajectory; images are matched to it by the time stamp in their file\n"
    "    name (TUM rgb/<stamp>.png), or in order when it has one pose per image.\n"
    "  --gt-matrix: pixel (i, j) > 0 when images i and j show the same place.\n"
    "  Only images more than --exclude-recent apart count as revisits. The curve goes to\n"
    "  --pr-plot (default: --out with _pr.png in place of its extension).";
constexpr icgm::tools::ToolInfo kTool{"icgm_place_recognition", kUsage};

int BadArguments(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

int Failure(const std::string& message) { return icgm::tools::Failure(kTool, message); }

// Image paths, one per line; relative paths are taken relative to the list's directory.
bool ReadImageList(const std::string& list_path, std::vector<std::string>* paths,
                   std::string* error) {
  std::ifstream in(list_path);
  if (!in) {
    *error = "cannot open image list '" + list_path + "'";
    return false;
  }
  const std::filesystem::path base = std::filesystem::path(list_path).parent_path();
  std::string line;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::filesystem::path p(line);
    paths->push_back(p.is_absolute() || std::filesystem::exists(p) ? p.string()
                                                                   : (base / p).string());
  }
  if (paths->empty()) {
    *error = "image list '" + list_path + "' names no images";
    return false;
  }
  return true;
}

struct Settings {
  std::string list_path;
  std::string out_path;
  std::string robust = "double";
  double min_score = 0.0;
  int exclude_recent = 0;
  std::string gt_poses_path;
  std::string gt_matrix_path;
  std::string pr_plot_path;
  icgm::RevisitCriterion revisit;
  icgm::DictionaryOptions dictionary;
  icgm::TrackerOptions tracker;
};

// Keeps the rows of `features` flagged robust.
icgm::FeatureSet RobustSubset(const icgm::TrackedFrame& frame) {
  icgm::FeatureSet out;
  out.binary = frame.features.binary;
  for (size_t i = 0; i < frame.features.keypoints.size(); ++i) {
    if (!frame.robust[i]) continue;
    out.keypoints.push_back(frame.features.keypoints[i]);
    out.descriptors.push_back(frame.features.descriptors.row(static_cast<int>(i)));
  }
  return out;
}

// Ground-truth pose of each image: by the time stamp in the file name when every name is one
// (TUM's rgb/<seconds>.png), else by order when the trajectory has one pose per image.
bool PosesForImages(const std::vector<std::string>& images, const icgm::Trajectory& gt,
                    std::vector<std::optional<icgm::Pose3>>* poses, std::string* error) {
  std::vector<double> stamps;
  for (const std::string& path : images) {
    const std::string stem = std::filesystem::path(path).stem().string();
    char* end = nullptr;
    const double t = std::strtod(stem.c_str(), &end);
    if (stem.empty() || end != stem.c_str() + stem.size()) break;
    stamps.push_back(t);
  }
  icgm::Trajectory sorted = gt;
  icgm::SortByStamp(&sorted);
  if (stamps.size() == images.size()) {
    for (const double t : stamps) {
      poses->push_back(icgm::PoseAt(sorted, icgm::Time::FromSeconds(t), 0.1));
    }
    return true;
  }
  if (gt.size() == images.size()) {
    for (const icgm::StampedPose& p : gt) poses->push_back(p.pose);
    return true;
  }
  *error = "cannot pair the " + std::to_string(images.size()) + " images with the " +
           std::to_string(gt.size()) +
           " ground-truth poses: file names are not time stamps and the counts differ";
  return false;
}

std::string DefaultPlotPath(const std::string& out_path) {
  std::filesystem::path p(out_path);
  p.replace_extension();
  return p.string() + "_pr.png";
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  try {
    const icgm::tools::CliArgs args(
        argc, argv,
        {"images", "out", "config", "icgm-config", "robust", "min-score", "exclude-recent",
         "gt-poses", "gt-matrix", "revisit-m", "revisit-deg", "pr-plot"},
        {});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return BadArguments("unexpected argument '" + args.positional().front() + "'");
    }
    s.list_path = args.Require("images");
    s.out_path = args.Require("out");
    icgm::MapBuilderOptions map_options;
    if (args.Has("config")) {
      icgm::ReadOptions(icgm::OptionReader::FromFile(args.Get("config")), &map_options);
    }
    if (args.Has("icgm-config")) {
      icgm::ReadOptions(icgm::OptionReader::FromFile(args.Get("icgm-config")), &s.tracker);
    }
    s.robust = args.Get("robust", icgm::NameOf(s.tracker.mode));
    if (s.robust != "double" && s.robust != "single" && s.robust != "none") {
      return BadArguments("--robust must be double, single or none, not '" + s.robust + "'");
    }
    if (s.robust != "none") s.tracker.mode = *icgm::ParseEnum<icgm::TrackerMode>(s.robust);
    s.dictionary = map_options.dictionary;
    s.min_score = args.GetDouble("min-score", map_options.loop_closure.min_score);
    s.exclude_recent =
        args.GetInt("exclude-recent", map_options.loop_closure.exclude_recent_keyframes);
    if (!(s.min_score >= 0.0 && s.min_score <= 1.0)) {
      return BadArguments("--min-score must be in [0, 1]");
    }
    if (s.exclude_recent < 0) return BadArguments("--exclude-recent must be >= 0");
    s.gt_poses_path = args.Get("gt-poses", "");
    s.gt_matrix_path = args.Get("gt-matrix", "");
    if (!s.gt_poses_path.empty() && !s.gt_matrix_path.empty()) {
      return BadArguments("give --gt-poses or --gt-matrix, not both");
    }
    const bool truth = !s.gt_poses_path.empty() || !s.gt_matrix_path.empty();
    for (const char* key : {"revisit-m", "revisit-deg"}) {
      if (args.Has(key) && s.gt_poses_path.empty()) {
        return BadArguments(std::string("--") + key + " needs --gt-poses");
      }
    }
    if (args.Has("pr-plot") && !truth) return BadArguments("--pr-plot needs ground truth");
    s.revisit.max_distance_m = args.GetDouble("revisit-m", s.revisit.max_distance_m);
    s.revisit.max_angle_deg = args.GetDouble("revisit-deg", s.revisit.max_angle_deg);
    if (!(s.revisit.max_distance_m > 0.0)) return BadArguments("--revisit-m must be > 0");
    if (!(s.revisit.max_angle_deg > 0.0 && s.revisit.max_angle_deg <= 180.0)) {
      return BadArguments("--revisit-deg must be in (0, 180]");
    }
    s.revisit.min_frame_gap = s.exclude_recent + 1;
    if (truth) s.pr_plot_path = args.Get("pr-plot", DefaultPlotPath(s.out_path));
  } catch (const icgm::LoadError& e) {
    return BadArguments(e.what());
  } catch (const std::invalid_argument& e) {
    return BadArguments(e.what());
  }

  std::vector<std::string> images;
  std::string error;
  if (!ReadImageList(s.list_path, &images, &error)) return Failure(error);
  // Ground truth is read before the images are processed, so that a bad file fails early.
  std::optional<icgm::PlaceTruth> truth;
  try {
    if (!s.gt_poses_path.empty()) {
      std::vector<std::optional<icgm::Pose3>> poses;
      if (!PosesForImages(images, icgm::ReadTumTrajectory(s.gt_poses_path), &poses, &error)) {
        return Failure(error);
      }
      truth = icgm::RevisitsFromPoses(poses, s.revisit);
    }
  } catch (const icgm::LoadError& e) {
    return Failure(e.what());
  }
  if (!s.gt_matrix_path.empty()) {
    const cv::Mat matrix = cv::imread(s.gt_matrix_path, cv::IMREAD_UNCHANGED);
    if (matrix.empty()) {
      return Failure("cannot read ground-truth matrix '" + s.gt_matrix_path + "'");
    }
    truth.emplace();
    const icgm::Status st = icgm::PlaceTruthFromMatrix(
        matrix, static_cast<int>(images.size()), s.revisit.min_frame_gap, &*truth);
    if (!st.ok()) return Failure(s.gt_matrix_path + ": " + st.reason());
  }
  std::unique_ptr<icgm::FeatureExtractor> extractor =
      icgm::FeatureExtractor::Create(s.tracker.features);
  s.dictionary.descriptor_type =
      extractor->binary() ? icgm::DescriptorType::kBinary : icgm::DescriptorType::kFloat;
  icgm::VisualDictionary dictionary(s.dictionary);
  std::optional<icgm::RobustFeatureTracker> tracker;
  if (s.robust != "none") tracker.emplace(s.tracker);

  std::ofstream out(s.out_path);
  if (!out) return Failure("cannot write '" + s.out_path + "'");
  out << "query,match,score\n";
  int new_places = 0;
  int revisits = 0;
  std::vector<icgm::PlaceQuery> queries;  // best candidate of each image, whatever its score
  // Queries the dictionary with image `index`'s features, writes its row, then adds it.
  auto process = [&](int index, const icgm::FeatureSet& features) -> bool {
    std::vector<icgm::DictionaryMatch> matches;
    icgm::WordAssignment words;
    const icgm::Status q = dictionary.Quantize(features.descriptors, &words);
    if (!q.ok()) {
      error = "image " + std::to_string(index) + ": " + q.reason();
      return false;
    }
    icgm::PlaceQuery best{index, -1, 0.0};
    for (const auto& m : dictionary.Score(words)) {  // best score first
      if (index - m.keyframe_id <= s.exclude_recent) continue;
      best.candidate = m.keyframe_id;
      best.score = m.score;
      break;
    }
    queries.push_back(best);
    const bool accepted = best.candidate >= 0 && best.score >= s.min_score;
    const int match = accepted ? best.candidate : -1;
    const double score = accepted ? best.score : 0.0;
    (match < 0 ? new_places : revisits) += 1;
    out << index << ',' << match << ',' << score << '\n';
    if (features.descriptors.rows == 0) return true;
    const icgm::Status a = dictionary.Add(index, features.descriptors, nullptr, &words);
    if (!a.ok()) error = "image " + std::to_string(index) + ": " + a.reason();
    return a.ok();
  };
  auto process_tracked = [&](const std::optional<icgm::TrackedFrame>& frame) {
    if (!frame) return true;
    return process(static_cast<int>(frame->stamp.nanoseconds()), RobustSubset(*frame));
  };

  icgm::ProgressBar bar(images.size(), "images");
  for (size_t i = 0; i < images.size(); ++i) {
    const cv::Mat image = icgm::tools::ReadImageForFeatures(images[i], &error);
    if (image.empty()) return Failure(error);
    const icgm::Time stamp = icgm::Time::FromNanoseconds(static_cast<int64_t>(i));
    bool ok = false;
    try {
      ok = tracker ? process_tracked(tracker->AddImage(stamp, image))
                   : process(static_cast<int>(i), extractor->Extract(image));
    } catch (const cv::Exception& e) {
      return Failure("image '" + images[i] + "': " + e.what());
    }
    if (!ok) return Failure(error);
    bar.Update(i + 1);
  }
  if (tracker && !process_tracked(tracker->Flush())) return Failure(error);
  bar.Finish();
  out.flush();
  if (!out) return Failure("write error on '" + s.out_path + "'");
  std::fprintf(stderr, "%zu images: %d new places, %d recognized; %d words -> %s\n", images.size(),
               new_places, revisits, dictionary.num_words(), s.out_path.c_str());
  if (!truth) return 0;
  const icgm::PrecisionRecallPoint at = icgm::EvaluateAtThreshold(queries, *truth, s.min_score);
  const icgm::PrecisionRecallCurve curve = icgm::SweepPrecisionRecall(queries, *truth);
  char criterion[96];
  std::snprintf(criterion, sizeof(criterion), "within %.2f m and %.0f deg, %d+ images apart",
                s.revisit.max_distance_m, s.revisit.max_angle_deg, s.revisit.min_frame_gap);
  std::printf("ground truth: %d of %zu images revisit an earlier place (%s)\n", curve.revisits,
              images.size(),
              s.gt_poses_path.empty() ? ("matrix " + s.gt_matrix_path).c_str() : criterion);
  std::printf("at min score %.3f: precision %.1f%% (%d true, %d false loops), recall %.1f%%\n",
              s.min_score, 100.0 * at.precision, at.true_positives, at.false_positives,
              100.0 * at.recall);
  if (curve.recall_at_full_precision > 0.0) {
    std::printf("recall at 100%% precision: %.1f%% (threshold %.4f)\n",
                100.0 * curve.recall_at_full_precision, curve.threshold_at_full_precision);
  } else if (curve.points.empty()) {
    std::printf("recall at 100%% precision: 0%% (no loop candidates)\n");
  } else {
    std::printf("recall at 100%% precision: 0%% (the best-scored loop is false)\n");
  }
  const icgm::Status plot = icgm::WritePrecisionRecallPlot(
      s.pr_plot_path, curve, "place recognition (" + extractor->name() + ", " + s.robust + ")");
  if (!plot.ok()) return Failure(plot.reason());
  std::printf("precision-recall curve -> %s\n", s.pr_plot_path.c_str());
  return 0;
}
