// icgm_place_recognition: appearance-only place recognition over an image sequence (thesis 4.2,
// ICGM-based online-incremental appearance-only SLAM). Each image's features, weighted by
// whether ICGM verified them against the neighbouring images (single- or double-directional,
// PIRF: Thr -> inf; none: plain features), query the incremental dictionary of the earlier
// images; the best hypotheses pass the minimum-words guard, the temporal-consistency check and
// geometric verification (core/place/place_recognizer.h, config/place_recognition.yaml), then
// the image is added. Writes one CSV row per image: query,match,score with match = -1 for a
// new place. Images come from a list (--images) or a rendered simulator run (--sim), every
// --every-th one. With ground truth (--gt-poses: TUM trajectory, a revisit is an earlier image
// within --revisit-m and --revisit-deg; --gt-matrix: pixel (i, j) > 0 means images i and j show
// the same place; --sim: the simulator's camera poses) it prints precision and recall of the
// reported loops, the recall at 100 % precision, and draws the precision-recall curve swept over
// the acceptance threshold (core/eval/precision_recall.h). --table prints one row per run:
// tracker modes (modes), ICGM thresholds (thr, thesis Fig. 5.1 style) or the recognizer's
// checks switched on and off (checks).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/common/option_reader.h"
#include "core/common/progress_bar.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/depth_image.h"
#include "core/dataset/trajectory.h"
#include "core/eval/place_truth.h"
#include "core/eval/precision_recall.h"
#include "core/eval/precision_recall_plot.h"
#include "core/map/map_options.h"
#include "core/place/place_options.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "tools/cli_args.h"
#include "tools/image_input.h"
#include "tools/place_recognition_run.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_place_recognition (--images LIST.txt | --sim SCENARIO.yaml [--no-pedestrians])\n"
    "                              [--every N] [--out matches.csv] [--profile default|thesis]\n"
    "                              [--config config/map.yaml] [--icgm-config config/icgm.yaml]\n"
    "                              [--place-config config/place_recognition.yaml]\n"
    "                              [--robust double|single|pirf|none] [--min-score S]\n"
    "                              [--exclude-recent N] [--unverified-weight W]\n"
    "                              [--share-weighting on|off]\n"
    "                              [--min-words N] [--consistent-queries K]\n"
    "                              [--candidates N]\n"
    "                              [--descriptor-fallback on|off] [--continuation on|off]\n"
    "                              [--geometry on|off|rgbd] [--depth-candidates N]\n"
    "                              [--rgbd-nearest on|off] [--rgbd-fallback on|off]\n"
    "                              [--camera CAMERA.yaml]\n"
    "                              [--gt-poses GT.txt [--revisit-m 0.5] [--revisit-deg 30]\n"
    "                               [--gt-max-gap 0.2]\n"
    "                               [--soft-m M --soft-deg D]\n"
    "                               | --gt-matrix TRUTH.png] [--pr-plot PR.png]\n"
    "                              [--table modes|thr|checks] [--diagnose QUERIES.txt]\n"
    "  --profile thesis: map.yaml, icgm.yaml and place_recognition.yaml from config/thesis (the\n"
    "    thesis's method: ICGM-verified features only, the best-scored image is the loop, no\n"
    "    guard, no geometric check); --config, --icgm-config and --place-config override them.\n"
    "  --sim: renders the scenario (every --every-th frame only); its camera poses are the\n"
    "    ground truth and its camera the one of the essential-matrix check.\n"
    "  --share-weighting: an image's unverified features weigh max(W, 1 - its verified share)\n"
    "    (on) or W (off); default from --place-config (weight_by_verified_share).\n"
    "  --every N: every N-th image (a sparse sequence: ICGM then links images N frames apart).\n"
    "  --gt-poses: TUM trajectory; images are matched to it by the time stamp in their file\n"
    "    name (TUM rgb/<stamp>.png), or in order when it has one pose per image; a pose is\n"
    "    interpolated across motion-capture gaps of up to --gt-max-gap seconds (an image in a\n"
    "    longer gap, or outside the trajectory, has none: its loops count neither way, and a\n"
    "    revisit whose loop goes to it is neither found nor missed: it leaves recall).\n"
    "  --soft-m, --soft-deg (with --gt-poses or --sim): a tolerance band, the \"soft\" ground\n"
    "    truth of VPR evaluations: a loop to an earlier image beyond the revisit bounds but\n"
    "    within M metres and D degrees is counted neither true nor false (both needed, each at\n"
    "    least its revisit bound).\n"
    "  --gt-matrix: pixel (i, j) > 0 when images i and j show the same place (not with --every).\n"
    "  --camera: camera YAML (config/camera/*.yaml): essential matrix instead of fundamental.\n"
    "  --images LIST: one image per line, optionally followed (space or tab) by its registered\n"
    "    depth image (16-bit, the --camera's depth_scale per metre, 0 = none).\n"
    "  --geometry rgbd (with --sim, its depth, or --images with depth and --camera): loops\n"
    "    verified by RANSAC + Horn on the 3-D points of the word correspondences\n"
    "    (geometric_verification.rgbd); --depth-candidates N: a query with depth also tries\n"
    "    its N best-scored images down to depth_min_score (place_recognition); --rgbd-nearest:\n"
    "    of the verified hypotheses the one with the smallest motion by the RGB-D fit is the\n"
    "    loop (--diagnose prints each fitted motion);\n"
    "    --rgbd-fallback: a failed RGB-D check is retried on descriptor matches with depth;\n"
    "    --rgbd-agreement N: a failed RGB-D check with N+ 3-D inliers passes when the epipolar\n"
    "    check of the pair passes (geometric_verification.rgbd_agreement_min_inliers);\n"
    "  --continuation-inliers N: a continuation hypothesis passes the epipolar check with N\n"
    "    inliers (temporal_consistency.continuation_min_inliers; 0: min_inliers).\n"
    "  Only images more than --exclude-recent apart count as revisits. The curve goes to\n"
    "  --pr-plot (default: --out with _pr.png in place of its extension).\n"
    "  --diagnose (needs ground truth; no --table): one line per query: its words, the\n"
    "    hypotheses tried (score, true / false / band, correspondences, inliers, verdict) and,\n"
    "    for a missed revisit, why: the best-scored true earlier image's rank and score, under\n"
    "    min_score, not among the candidates, or rejected by which check.\n"
    "  --table (needs ground truth; no CSV) runs the sequence once per row and prints precision,\n"
    "    recall and recall at 100% precision of: modes: double ICGM, single, PIRF (Thr -> inf),\n"
    "    each weighted and verified-only, and plain features; thr: double ICGM over Thr;\n"
    "    checks: the recognizer's checks (weighting, guard, temporal, geometric) on and off.";
constexpr icgm::tools::ToolInfo kTool{"icgm_place_recognition", kUsage};

int BadArguments(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

int Failure(const std::string& message) { return icgm::tools::Failure(kTool, message); }

// Image paths, one per line, each optionally followed by its registered depth image (16-bit,
// camera depth_scale per metre, 0 = none) after a space or tab; relative paths are taken
// relative to the list's directory. `depths` gets one entry per image ("" without depth).
bool ReadImageList(const std::string& list_path, std::vector<std::string>* paths,
                   std::vector<std::string>* depths, std::string* error) {
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
    auto resolve = [&](const std::string& name) {
      const std::filesystem::path p(name);
      return p.is_absolute() || std::filesystem::exists(p) ? p.string() : (base / p).string();
    };
    std::string depth;
    const size_t gap = line.find_first_of(" \t");
    if (gap != std::string::npos && !std::filesystem::exists(resolve(line))) {
      depth = line.substr(line.find_first_not_of(" \t", gap));
      line.resize(gap);
    }
    paths->push_back(resolve(line));
    depths->push_back(depth.empty() ? "" : resolve(depth));
  }
  if (paths->empty()) {
    *error = "image list '" + list_path + "' names no images";
    return false;
  }
  return true;
}

struct Settings {
  std::string list_path;
  std::string sim_path;
  bool pedestrians = true;
  int every = 1;
  std::string out_path;
  std::string table;
  std::string gt_poses_path;
  // Longest motion-capture gap a pose is interpolated across (s); an image in a longer gap
  // has no pose (its loops count neither way).
  double gt_max_gap_s = 0.2;
  std::string gt_matrix_path;
  std::string pr_plot_path;
  std::string diagnose_path;
  icgm::RevisitCriterion revisit;
  icgm::tools::PlaceRunSettings run;
};

// Ground-truth pose of each image: by the time stamp in the file name when every name is one
// (TUM's rgb/<seconds>.png), else by order when the trajectory has one pose per image.
bool PosesForImages(const std::vector<std::string>& images, const icgm::Trajectory& gt,
                    double max_gap_s, std::vector<std::optional<icgm::Pose3>>* poses,
                    std::string* error) {
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
      poses->push_back(icgm::PoseAt(sorted, icgm::Time::FromSeconds(t), max_gap_s));
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

// One table row: a label and the run settings.
struct Row {
  std::string label;
  icgm::tools::PlaceRunSettings run;
};

std::vector<Row> TableRows(const std::string& table, const icgm::tools::PlaceRunSettings& base) {
  std::vector<Row> rows;
  auto add = [&](const std::string& label, auto change) {
    Row r{label, base};
    change(&r.run);
    rows.push_back(r);
  };
  const double w = base.place.unverified_weight;
  char weighted[64];
  std::snprintf(weighted, sizeof(weighted), "weighted (unverified %.2f)", w);
  if (table == "modes") {
    for (const char* mode : {"double", "single", "pirf"}) {
      const std::string name = std::string(mode == std::string("pirf") ? "PIRF (Thr->inf)" : mode);
      add(name + ", " + weighted, [&](auto* r) { r->robust = mode; });
      add(name + ", verified only", [&](auto* r) {
        r->robust = mode;
        r->place.unverified_weight = 0.0;
        r->place.weight_by_verified_share = false;
      });
    }
    add("plain features", [&](auto* r) { r->robust = "none"; });
  } else if (table == "thr") {
    for (const double thr : {0.02, 0.04, 0.06, 0.08, 0.12, 0.16, 0.24, 1.0}) {
      char label[64];
      std::snprintf(label, sizeof(label), "Thr %.2f%s", thr, thr >= 1.0 ? " (inf)" : "");
      add(std::string(label) + ", " + weighted, [&](auto* r) {
        r->robust = "double";
        r->tracker.icgm.threshold = thr;
        r->tracker.icgm.auto_threshold = false;
      });
      add(std::string(label) + ", verified only", [&](auto* r) {
        r->robust = "double";
        r->tracker.icgm.threshold = thr;
        r->tracker.icgm.auto_threshold = false;
        r->place.unverified_weight = 0.0;
        r->place.weight_by_verified_share = false;
      });
    }
    add("plain features", [&](auto* r) { r->robust = "none"; });
  } else {  // checks
    add("as configured", [](auto*) {});
    add("verified only (weight 0)", [](auto* r) {
      r->place.unverified_weight = 0.0;
      r->place.weight_by_verified_share = false;
    });
    add("fixed unverified weight (not by verified share)",
        [](auto* r) { r->place.weight_by_verified_share = false; });
    add("all alike (weight 1)", [](auto* r) { r->place.unverified_weight = 1.0; });
    add("no minimum-words guard", [](auto* r) { r->place.min_query_words = 0; });
    add("temporal consistency 1 query", [](auto* r) { r->place.temporal.consistent_queries = 1; });
    add("temporal consistency 2 queries",
        [](auto* r) { r->place.temporal.consistent_queries = 2; });
    add("no geometric verification", [](auto* r) { r->place.geometry.enabled = false; });
    add("no checks, verified only (dictionary alone)", [](auto* r) {
      r->place.unverified_weight = 0.0;
      r->place.weight_by_verified_share = false;
      r->place.min_query_words = 0;
      r->place.temporal.consistent_queries = 0;
      r->place.geometry.enabled = false;
    });
    add("plain features, all checks", [](auto* r) { r->robust = "none"; });
    add("plain features, no checks", [](auto* r) {
      r->robust = "none";
      r->place.min_query_words = 0;
      r->place.temporal.consistent_queries = 0;
      r->place.geometry.enabled = false;
    });
  }
  return rows;
}

// Precision and recall of every reported loop (result.queries holds the accepted loops only;
// a continuation loop may score under min_score), recall at 100 % precision.
void PrintEvaluation(const icgm::tools::PlaceRunResult& result, const icgm::PlaceTruth& truth) {
  const icgm::PrecisionRecallPoint at = icgm::EvaluateAtThreshold(result.queries, truth, 0.0);
  const icgm::PrecisionRecallCurve curve = icgm::SweepPrecisionRecall(result.queries, truth);
  std::printf("reported loops: precision %.1f%% (%d true, %d false loops), recall %.1f%%\n",
              100.0 * at.precision, at.true_positives, at.false_positives, 100.0 * at.recall);
  if (at.undetermined > 0) {
    std::printf(
        "%d revisits with a loop to an image without a ground-truth pose: neither found nor "
        "missed (left out of recall)\n",
        at.undetermined);
  }
  if (curve.recall_at_full_precision > 0.0) {
    std::printf("recall at 100%% precision: %.1f%% (threshold %.4f)\n",
                100.0 * curve.recall_at_full_precision, curve.threshold_at_full_precision);
  } else if (curve.points.empty()) {
    std::printf("recall at 100%% precision: 0%% (no loop candidates)\n");
  } else {
    std::printf("recall at 100%% precision: 0%% (the best-scored loop is false)\n");
  }
}

// Per query: the hypotheses tried with their truth, and for a missed revisit why it was
// missed (see --diagnose). Returns the number of missed revisits by cause on stdout.
bool WriteDiagnosis(const std::string& path, const icgm::tools::PlaceRunResult& result,
                    const icgm::PlaceTruth& truth, const icgm::PlaceRecognitionOptions& place) {
  std::ofstream out(path);
  if (!out) return false;
  auto label = [&](int q, int c) -> const char* {
    if (!truth.Judged(q, c)) return truth.Ambiguous(q, c) ? "band" : "unknown";
    return truth.SamePlace(q, c) ? "true" : "false";
  };
  std::map<std::string, int> causes;
  char line[256];
  for (const icgm::PlaceDecision& d : result.decisions) {
    const bool revisit = truth.IsRevisit(d.query);
    std::snprintf(line, sizeof(line), "query %d: %s, %d words, match %d", d.query,
                  revisit ? "revisit" : "new place", d.words, d.match);
    out << line;
    if (d.match >= 0) out << " (" << label(d.query, d.match) << ")";
    out << '\n';
    if (!d.scores.empty()) {
      // The previous image's score (the query's self-similarity) and the five best-scored
      // images the query may match, with their truth.
      double previous = 0.0;
      for (const icgm::DictionaryMatch& m : d.scores) {
        if (m.keyframe_id == d.query - 1) previous = m.score;
      }
      std::snprintf(line, sizeof(line), "  previous image score %.4f; best:", previous);
      out << line;
      int shown = 0;
      for (const icgm::DictionaryMatch& m : d.scores) {
        if (d.query - m.keyframe_id <= place.exclude_recent_images) continue;
        std::snprintf(line, sizeof(line), " %d %.4f %s", m.keyframe_id, m.score,
                      label(d.query, m.keyframe_id));
        out << line;
        if (++shown == 5) break;
      }
      out << '\n';
    }
    for (const icgm::PlaceHypothesis& h : d.checked) {
      std::snprintf(line, sizeof(line),
                    "  hypothesis %d score %.4f %s, %d correspondences, %d inliers", h.candidate,
                    h.score, label(d.query, h.candidate), h.correspondences, h.inliers);
      out << line;
      if (std::isfinite(h.translation_m)) {
        std::snprintf(line, sizeof(line), ", motion %.3f m %.1f deg", h.translation_m,
                      h.rotation_deg);
        out << line;
      }
      out << ": " << (h.verdict.empty() ? "accepted" : h.verdict) << '\n';
    }
    if (!revisit || (d.match >= 0 && truth.SamePlace(d.query, d.match))) continue;
    if (d.match >= 0 && !truth.Known(d.match)) {
      out << "  UNDETERMINED: a loop to an image without a pose (neither found nor missed)\n";
      continue;
    }
    // The best-scored true earlier image among those the query may match.
    int rank = 0, true_rank = -1;
    double true_score = 0.0;
    int true_image = -1;
    for (const icgm::DictionaryMatch& m : d.scores) {
      if (d.query - m.keyframe_id <= place.exclude_recent_images) continue;
      ++rank;
      if (truth.SamePlace(d.query, m.keyframe_id)) {
        true_rank = rank;
        true_score = m.score;
        true_image = m.keyframe_id;
        break;
      }
    }
    std::string cause;
    if (true_rank < 0) {
      cause = "no true image shares a word";
    } else if (true_score < place.min_score) {
      cause = "true image under min_score";
    } else if (true_rank > place.candidates) {
      cause = "true image not among the candidates";
    } else {
      cause = "true candidate rejected: ";
      for (const icgm::PlaceHypothesis& h : d.checked) {
        if (h.candidate != true_image) continue;
        std::string v = h.verdict;
        if (v.find("inliers <") != std::string::npos) v = "too few inliers";
        if (v.find("matches <") != std::string::npos) v = "too few correspondences";
        if (v.find("words:") != std::string::npos) v = "minimum-words guard";
        cause += v;
      }
    }
    if (d.match >= 0) {
      cause += std::string(" (a loop to ") +
               (truth.Ambiguous(d.query, d.match) ? "a band image" : "a false image") +
               " was taken)";
    }
    ++causes[cause];
    std::snprintf(line, sizeof(line), "  MISSED: %s; best true image %d rank %d score %.4f\n",
                  cause.c_str(), true_image, true_rank, true_score);
    out << line;
  }
  for (const auto& [cause, n] : causes) std::printf("missed revisits: %d %s\n", n, cause.c_str());
  return static_cast<bool>(out);
}

std::string DefaultPlotPath(const std::string& out_path) {
  std::filesystem::path p(out_path);
  p.replace_extension();
  return p.string() + "_pr.png";
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  bool args_rgbd = false;  // --geometry rgbd given
  try {
    const icgm::tools::CliArgs args(argc, argv,
                                    {"images",
                                     "sim",
                                     "every",
                                     "out",
                                     "config",
                                     "icgm-config",
                                     "place-config",
                                     "robust",
                                     "min-score",
                                     "exclude-recent",
                                     "unverified-weight",
                                     "share-weighting",
                                     "min-words",
                                     "consistent-queries",
                                     "geometry",
                                     "camera",
                                     "gt-poses",
                                     "gt-max-gap",
                                     "gt-matrix",
                                     "revisit-m",
                                     "revisit-deg",
                                     "soft-m",
                                     "soft-deg",
                                     "pr-plot",
                                     "table",
                                     "profile",
                                     "diagnose",
                                     "candidates",
                                     "descriptor-fallback",
                                     "continuation",
                                     "depth-candidates",
                                     "rgbd-nearest",
                                     "rgbd-fallback",
                                     "continuation-inliers",
                                     "rgbd-agreement"},
                                    {"no-pedestrians"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return BadArguments("unexpected argument '" + args.positional().front() + "'");
    }
    s.list_path = args.Get("images", "");
    s.sim_path = args.Get("sim", "");
    if (s.list_path.empty() == s.sim_path.empty()) {
      return BadArguments("give --images or --sim (one of them)");
    }
    s.pedestrians = !args.Has("no-pedestrians");
    if (args.Has("no-pedestrians") && s.sim_path.empty()) {
      return BadArguments("--no-pedestrians needs --sim");
    }
    s.every = args.GetInt("every", 1);
    if (s.every < 1) return BadArguments("--every must be >= 1");
    s.table = args.Get("table", "");
    if (!s.table.empty() && s.table != "modes" && s.table != "thr" && s.table != "checks") {
      return BadArguments("--table must be modes, thr or checks, not '" + s.table + "'");
    }
    s.out_path = s.table.empty() ? args.Require("out") : args.Get("out", "");
    if (!s.table.empty() && args.Has("out")) return BadArguments("--table writes no --out");
    icgm::tools::PlaceRunSettings& run = s.run;
    // Without a profile the code's defaults (equal to config/*.yaml) serve.
    const std::string profile = args.Get("profile", "default");
    if (profile != "default" && profile != "thesis") {
      return BadArguments("--profile must be default or thesis, not '" + profile + "'");
    }
    const std::string thesis_dir =
        profile == "thesis" ? std::string(ICGM_CONFIG_DIR) + "/thesis/" : "";
    const auto config_file = [&](const char* flag, const char* name) {
      return args.Get(flag, thesis_dir.empty() ? "" : thesis_dir + name);
    };
    icgm::MapBuilderOptions map_options;
    if (const std::string path = config_file("config", "map.yaml"); !path.empty()) {
      icgm::ReadOptions(icgm::OptionReader::FromFile(path), &map_options);
    }
    run.dictionary = map_options.dictionary;
    if (const std::string path = config_file("icgm-config", "icgm.yaml"); !path.empty()) {
      icgm::ReadOptions(icgm::OptionReader::FromFile(path), &run.tracker);
    }
    if (const std::string path = config_file("place-config", "place_recognition.yaml");
        !path.empty()) {
      icgm::ReadPlaceRecognitionFile(icgm::OptionReader::FromFile(path), &run.place);
    }
    run.robust = args.Get("robust", icgm::NameOf(run.tracker.mode));
    if (run.robust != "double" && run.robust != "single" && run.robust != "pirf" &&
        run.robust != "none") {
      return BadArguments("--robust must be double, single, pirf or none, not '" + run.robust +
                          "'");
    }
    icgm::PlaceRecognitionOptions& place = run.place;
    place.min_score = args.GetDouble("min-score", place.min_score);
    place.exclude_recent_images = args.GetInt("exclude-recent", place.exclude_recent_images);
    place.unverified_weight = args.GetDouble("unverified-weight", place.unverified_weight);
    if (args.Has("share-weighting")) {
      const std::string v = args.Get("share-weighting");
      if (v != "on" && v != "off") return BadArguments("--share-weighting must be on or off");
      place.weight_by_verified_share = v == "on";
    }
    place.min_query_words = args.GetInt("min-words", place.min_query_words);
    if (args.Has("descriptor-fallback")) {
      const std::string v = args.Get("descriptor-fallback");
      if (v != "on" && v != "off") return BadArguments("--descriptor-fallback must be on or off");
      place.geometry.descriptor_fallback = v == "on";
    }
    if (args.Has("rgbd-fallback")) {
      const std::string v = args.Get("rgbd-fallback");
      if (v != "on" && v != "off") return BadArguments("--rgbd-fallback must be on or off");
      place.geometry.rgbd_descriptor_fallback = v == "on";
    }
    if (args.Has("rgbd-nearest")) {
      const std::string v = args.Get("rgbd-nearest");
      if (v != "on" && v != "off") return BadArguments("--rgbd-nearest must be on or off");
      place.geometry.rgbd_nearest = v == "on";
    }
    place.depth_candidates = args.GetInt("depth-candidates", place.depth_candidates);
    if (place.depth_candidates < 0) return BadArguments("--depth-candidates must be >= 0");
    if (args.Has("continuation")) {
      const std::string v = args.Get("continuation");
      if (v != "on" && v != "off") return BadArguments("--continuation must be on or off");
      place.temporal.continuation = v == "on";
    }
    place.temporal.continuation_min_inliers =
        args.GetInt("continuation-inliers", place.temporal.continuation_min_inliers);
    if (place.temporal.continuation_min_inliers != 0 &&
        place.temporal.continuation_min_inliers < 8) {
      return BadArguments("--continuation-inliers must be 0 (off) or >= 8");
    }
    place.geometry.rgbd_agreement_min_inliers =
        args.GetInt("rgbd-agreement", place.geometry.rgbd_agreement_min_inliers);
    if (place.geometry.rgbd_agreement_min_inliers != 0 &&
        place.geometry.rgbd_agreement_min_inliers < 3) {
      return BadArguments("--rgbd-agreement must be 0 (off) or >= 3");
    }
    place.candidates = args.GetInt("candidates", place.candidates);
    if (place.candidates < 1) return BadArguments("--candidates must be >= 1");
    place.temporal.consistent_queries =
        args.GetInt("consistent-queries", place.temporal.consistent_queries);
    std::string configured = "on";
    if (!place.geometry.enabled) configured = "off";
    if (place.geometry.enabled && place.geometry.rgbd) configured = "rgbd";
    const std::string geometry = args.Get("geometry", configured);
    if (geometry != "on" && geometry != "off" && geometry != "rgbd") {
      return BadArguments("--geometry must be on, off or rgbd");
    }
    place.geometry.enabled = geometry != "off";
    place.geometry.rgbd = geometry == "rgbd";
    args_rgbd = args.Has("geometry") && geometry == "rgbd";
    if (args_rgbd && s.sim_path.empty() && !args.Has("camera")) {
      return BadArguments(
          "--geometry rgbd needs depth: --sim, or --images with a depth column "
          "and --camera");
    }
    if (place.geometry.rgbd && place.geometry.matching != icgm::PlaceMatching::kWords) {
      return BadArguments("--geometry rgbd needs geometric_verification.matching: words");
    }
    if (!(place.min_score >= 0.0 && place.min_score <= 1.0)) {
      return BadArguments("--min-score must be in [0, 1]");
    }
    if (place.exclude_recent_images < 0) return BadArguments("--exclude-recent must be >= 0");
    if (!(place.unverified_weight >= 0.0 && place.unverified_weight <= 1.0)) {
      return BadArguments("--unverified-weight must be in [0, 1]");
    }
    if (place.min_query_words < 0) return BadArguments("--min-words must be >= 0");
    if (place.temporal.consistent_queries < 0) {
      return BadArguments("--consistent-queries must be >= 0");
    }
    if (args.Has("camera")) {
      if (!s.sim_path.empty()) return BadArguments("--camera: --sim has its own camera");
      run.camera = icgm::LoadCameraIntrinsics(args.Get("camera"));
    }
    s.gt_poses_path = args.Get("gt-poses", "");
    s.gt_matrix_path = args.Get("gt-matrix", "");
    if (!s.gt_poses_path.empty() && !s.gt_matrix_path.empty()) {
      return BadArguments("give --gt-poses or --gt-matrix, not both");
    }
    if (!s.sim_path.empty() && (!s.gt_poses_path.empty() || !s.gt_matrix_path.empty())) {
      return BadArguments("--sim is its own ground truth: no --gt-poses or --gt-matrix");
    }
    if (!s.gt_matrix_path.empty() && s.every > 1) {
      return BadArguments("--gt-matrix indexes the whole list: not with --every");
    }
    const bool truth = !s.gt_poses_path.empty() || !s.gt_matrix_path.empty() || !s.sim_path.empty();
    if (args.Has("gt-max-gap") && s.gt_poses_path.empty()) {
      return BadArguments("--gt-max-gap needs --gt-poses");
    }
    s.gt_max_gap_s = args.GetDouble("gt-max-gap", s.gt_max_gap_s);
    if (!(s.gt_max_gap_s > 0.0)) return BadArguments("--gt-max-gap must be > 0");
    for (const char* key : {"revisit-m", "revisit-deg", "soft-m", "soft-deg"}) {
      if (args.Has(key) && s.gt_poses_path.empty() && s.sim_path.empty()) {
        return BadArguments(std::string("--") + key + " needs --gt-poses or --sim");
      }
    }
    if (args.Has("pr-plot") && (!truth || !s.table.empty())) {
      return BadArguments("--pr-plot needs ground truth and no --table");
    }
    if (!s.table.empty() && !truth) return BadArguments("--table needs ground truth");
    s.revisit.max_distance_m = args.GetDouble("revisit-m", s.revisit.max_distance_m);
    s.revisit.max_angle_deg = args.GetDouble("revisit-deg", s.revisit.max_angle_deg);
    if (!(s.revisit.max_distance_m > 0.0)) return BadArguments("--revisit-m must be > 0");
    if (!(s.revisit.max_angle_deg > 0.0 && s.revisit.max_angle_deg <= 180.0)) {
      return BadArguments("--revisit-deg must be in (0, 180]");
    }
    if (args.Has("soft-m") != args.Has("soft-deg")) {
      return BadArguments("--soft-m and --soft-deg go together");
    }
    if (args.Has("soft-m")) {
      s.revisit.soft_max_distance_m = args.GetDouble("soft-m", 0.0);
      s.revisit.soft_max_angle_deg = args.GetDouble("soft-deg", 0.0);
      if (!(s.revisit.soft_max_distance_m >= s.revisit.max_distance_m)) {
        return BadArguments("--soft-m must be >= --revisit-m");
      }
      if (!(s.revisit.soft_max_angle_deg >= s.revisit.max_angle_deg &&
            s.revisit.soft_max_angle_deg <= 180.0)) {
        return BadArguments("--soft-deg must be in [--revisit-deg, 180]");
      }
    }
    s.diagnose_path = args.Get("diagnose", "");
    if (!s.diagnose_path.empty() && (!truth || !s.table.empty())) {
      return BadArguments("--diagnose needs ground truth and no --table");
    }
    run.keep_scores = !s.diagnose_path.empty();
    s.revisit.min_frame_gap = place.exclude_recent_images + 1;
    if (truth && s.table.empty()) s.pr_plot_path = args.Get("pr-plot", DefaultPlotPath(s.out_path));
  } catch (const icgm::LoadError& e) {
    return BadArguments(e.what());
  } catch (const std::invalid_argument& e) {
    return BadArguments(e.what());
  }

  // The sequence: image paths or simulator frame numbers, every s.every-th.
  std::vector<std::string> images;
  std::vector<std::string> depth_images;  // per image, "" without depth
  std::vector<size_t> sim_frames;
  std::optional<icgm::sim::Simulator> sim;
  std::string error;
  std::optional<icgm::PlaceTruth> truth;
  try {
    if (!s.list_path.empty()) {
      std::vector<std::string> all, all_depths;
      if (!ReadImageList(s.list_path, &all, &all_depths, &error)) return Failure(error);
      for (size_t i = 0; i < all.size(); i += static_cast<size_t>(s.every)) {
        images.push_back(all[i]);
        depth_images.push_back(all_depths[i]);
      }
      const bool any_depth = std::any_of(depth_images.begin(), depth_images.end(),
                                         [](const std::string& d) { return !d.empty(); });
      if (s.run.place.geometry.rgbd && args_rgbd && !any_depth) {
        return BadArguments("--geometry rgbd: the image list has no depth column");
      }
    } else {
      sim.emplace(icgm::sim::LoadSimOptions(s.sim_path));
      for (size_t i = 0; i < sim->size(); i += static_cast<size_t>(s.every)) {
        sim_frames.push_back(i);
      }
      s.run.camera = sim->intrinsics();
      std::vector<std::optional<icgm::Pose3>> poses;
      for (size_t i : sim_frames) poses.push_back(sim->T_world_camera(i));
      truth = icgm::RevisitsFromPoses(poses, s.revisit);
    }
    // Ground truth is read before the images are processed, so that a bad file fails early.
    if (!s.gt_poses_path.empty()) {
      std::vector<std::optional<icgm::Pose3>> poses;
      if (!PosesForImages(images, icgm::ReadTumTrajectory(s.gt_poses_path), s.gt_max_gap_s, &poses,
                          &error)) {
        return Failure(error);
      }
      truth = icgm::RevisitsFromPoses(poses, s.revisit);
    }
  } catch (const icgm::LoadError& e) {
    return Failure(e.what());
  }
  const size_t count = sim ? sim_frames.size() : images.size();
  if (!s.gt_matrix_path.empty()) {
    const cv::Mat matrix = cv::imread(s.gt_matrix_path, cv::IMREAD_UNCHANGED);
    if (matrix.empty()) {
      return Failure("cannot read ground-truth matrix '" + s.gt_matrix_path + "'");
    }
    truth.emplace();
    const icgm::Status st = icgm::PlaceTruthFromMatrix(matrix, static_cast<int>(count),
                                                       s.revisit.min_frame_gap, &*truth);
    if (!st.ok()) return Failure(s.gt_matrix_path + ": " + st.reason());
  }
  // Tables run the sequence many times: images are read or rendered once and kept.
  std::vector<cv::Mat> cache(s.table.empty() ? 0 : count);
  std::vector<cv::Mat> depth_cache(s.table.empty() ? 0 : count);
  const icgm::sim::RenderFlags flags{s.pedestrians, true};
  const icgm::tools::ImageSource source = [&](size_t i, std::string* err,
                                              cv::Mat* depth_m) -> cv::Mat {
    if (!cache.empty() && !cache[i].empty()) {
      if (depth_m) *depth_m = depth_cache[i];
      return cache[i];
    }
    cv::Mat image, depth;
    if (sim) {
      icgm::sim::SimFrame frame = sim->Render(sim_frames[i], flags);
      image = frame.bgr;
      depth = frame.depth_m;
    } else {
      image = icgm::tools::ReadImageForFeatures(images[i], err);
      if (!image.empty() && depth_m && s.run.camera && !depth_images[i].empty()) {
        const cv::Mat raw = cv::imread(depth_images[i], cv::IMREAD_UNCHANGED);
        depth = icgm::ToMetricDepth(raw, s.run.camera->depth_scale);
        if (depth.empty()) {
          *err = "cannot read depth image '" + depth_images[i] + "' (16-bit or float)";
          return cv::Mat();
        }
      }
    }
    if (!cache.empty()) {
      cache[i] = image;
      depth_cache[i] = depth;
    }
    if (depth_m) *depth_m = depth;
    return image;
  };

  if (!s.table.empty()) {
    const std::vector<Row> rows = TableRows(s.table, s.run);
    std::printf("%zu images (every %d), %d revisit an earlier place\n", count, s.every,
                truth->NumRevisits());
    std::printf(
        "| run | loops | precision | recall | recall at 100%% precision | verified "
        "share | query ms (CPU) |\n|---|---|---|---|---|---|---|\n");
    for (size_t r = 0; r < rows.size(); ++r) {
      icgm::ProgressBar bar(count,
                            "run " + std::to_string(r + 1) + "/" + std::to_string(rows.size()));
      icgm::tools::PlaceRunResult result;
      const icgm::Status st = icgm::tools::RunPlaceRecognition(
          count, source, rows[r].run, [&](size_t done) { bar.Update(done); }, &result);
      bar.Finish();
      if (!st.ok()) return Failure(st.reason());
      const auto at = icgm::EvaluateAtThreshold(result.queries, *truth, 0.0);  // every loop
      const auto curve = icgm::SweepPrecisionRecall(result.queries, *truth);
      std::printf("| %s | %d | %.1f%% | %.1f%% | %.1f%% | %.0f%% | %.2f |\n", rows[r].label.c_str(),
                  at.true_positives + at.false_positives, 100.0 * at.precision, 100.0 * at.recall,
                  100.0 * curve.recall_at_full_precision, 100.0 * result.verified_share,
                  result.mean_query_ms);
      std::fflush(stdout);
    }
    return 0;
  }

  std::ofstream out(s.out_path);
  if (!out) return Failure("cannot write '" + s.out_path + "'");
  icgm::ProgressBar bar(count, "images");
  icgm::tools::PlaceRunResult result;
  const icgm::Status st = icgm::tools::RunPlaceRecognition(
      count, source, s.run, [&](size_t done) { bar.Update(done); }, &result);
  bar.Finish();
  if (!st.ok()) return Failure(st.reason());
  out << "query,match,score\n";
  int revisits = 0;
  for (const icgm::PlaceDecision& d : result.decisions) {
    out << d.query << ',' << d.match << ',' << d.score << '\n';
    if (d.match >= 0) ++revisits;
  }
  out.flush();
  if (!out) return Failure("write error on '" + s.out_path + "'");
  std::fprintf(stderr, "%zu images: %zu new places, %d recognized; %d words -> %s\n", count,
               count - static_cast<size_t>(revisits), revisits, result.words, s.out_path.c_str());
  if (!truth) return 0;
  char criterion[96];
  std::snprintf(criterion, sizeof(criterion), "within %.2f m and %.0f deg, %d+ images apart",
                s.revisit.max_distance_m, s.revisit.max_angle_deg, s.revisit.min_frame_gap);
  std::printf("ground truth: %d of %zu images revisit an earlier place (%s)\n",
              truth->NumRevisits(), count,
              s.gt_matrix_path.empty() ? criterion : ("matrix " + s.gt_matrix_path).c_str());
  if (truth->NumUnknown() > 0) {
    std::printf(
        "%d images without a ground-truth pose: their loops count neither way (a revisit whose "
        "loop goes to one is neither found nor missed)\n",
        truth->NumUnknown());
  }
  if (s.revisit.soft_max_distance_m > 0.0) {
    int band_loops = 0;
    for (const icgm::PlaceQuery& q : result.queries) {
      band_loops += q.candidate >= 0 && truth->Ambiguous(q.query, q.candidate);
    }
    std::printf(
        "tolerance band: within %.2f m and %.0f deg, %d image pairs; %d reported loops "
        "in it count neither way\n",
        s.revisit.soft_max_distance_m, s.revisit.soft_max_angle_deg, truth->NumAmbiguousPairs(),
        band_loops);
  }
  PrintEvaluation(result, *truth);
  std::printf("ICGM-verified share of the features %.0f%%, place query %.2f ms CPU per image\n",
              100.0 * result.verified_share, result.mean_query_ms);
  if (!s.diagnose_path.empty()) {
    if (!WriteDiagnosis(s.diagnose_path, result, *truth, s.run.place)) {
      return Failure("cannot write '" + s.diagnose_path + "'");
    }
    std::printf("per-query diagnosis -> %s\n", s.diagnose_path.c_str());
  }
  const icgm::PrecisionRecallCurve curve = icgm::SweepPrecisionRecall(result.queries, *truth);
  const icgm::Status plot = icgm::WritePrecisionRecallPlot(
      s.pr_plot_path, curve, "place recognition (" + result.detector + ", " + s.run.robust + ")");
  if (!plot.ok()) return Failure(plot.reason());
  std::printf("precision-recall curve -> %s\n", s.pr_plot_path.c_str());
  return 0;
}
