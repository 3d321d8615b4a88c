// icgm_place_recognition: appearance-only place recognition over an image sequence (thesis 4.2,
// ICGM-based online-incremental appearance-only SLAM). Each image's ICGM-robust features (ICGM
// against the neighbouring images of the list, single- or double-directional) query the
// incremental dictionary of the earlier images, then are added to it. Writes one CSV row per
// image: query,match,score with match = -1 for a new place.
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
    "                              [--exclude-recent N]";
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

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  try {
    const icgm::tools::CliArgs args(
        argc, argv,
        {"images", "out", "config", "icgm-config", "robust", "min-score", "exclude-recent"}, {});
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
    s.robust = args.Get("robust", icgm::TrackerModeName(s.tracker.mode));
    if (s.robust != "double" && s.robust != "single" && s.robust != "none") {
      return BadArguments("--robust must be double, single or none, not '" + s.robust + "'");
    }
    if (s.robust != "none") icgm::ParseTrackerMode(s.robust, &s.tracker.mode);
    s.dictionary = map_options.dictionary;
    s.min_score = args.GetDouble("min-score", map_options.loop_closure.min_score);
    s.exclude_recent =
        args.GetInt("exclude-recent", map_options.loop_closure.exclude_recent_keyframes);
    if (!(s.min_score >= 0.0 && s.min_score <= 1.0)) {
      return BadArguments("--min-score must be in [0, 1]");
    }
    if (s.exclude_recent < 0) return BadArguments("--exclude-recent must be >= 0");
  } catch (const icgm::LoadError& e) {
    return BadArguments(e.what());
  } catch (const std::invalid_argument& e) {
    return BadArguments(e.what());
  }

  std::vector<std::string> images;
  std::string error;
  if (!ReadImageList(s.list_path, &images, &error)) return Failure(error);
  std::unique_ptr<icgm::FeatureExtractor> extractor =
      icgm::FeatureExtractor::Create(s.tracker.features);
  if (!extractor) return Failure("unknown detector '" + s.tracker.features.detector + "'");
  s.dictionary.descriptor_type = extractor->binary() ? "binary" : "float";
  icgm::VisualDictionary dictionary(s.dictionary);
  std::optional<icgm::RobustFeatureTracker> tracker;
  if (s.robust != "none") tracker.emplace(s.tracker);

  std::ofstream out(s.out_path);
  if (!out) return Failure("cannot write '" + s.out_path + "'");
  out << "query,match,score\n";
  int new_places = 0;
  int revisits = 0;
  // Queries the dictionary with image `index`'s features, writes its row, then adds it.
  auto process = [&](int index, const icgm::FeatureSet& features) -> bool {
    std::vector<icgm::DictionaryMatch> matches;
    icgm::WordAssignment words;
    const icgm::Status q = dictionary.Quantize(features.descriptors, &words);
    if (!q.ok()) {
      error = "image " + std::to_string(index) + ": " + q.reason();
      return false;
    }
    int match = -1;
    double score = 0.0;
    for (const auto& m : dictionary.Score(words)) {
      if (m.score < s.min_score) break;
      if (index - m.keyframe_id <= s.exclude_recent) continue;
      match = m.keyframe_id;
      score = m.score;
      break;
    }
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
  return 0;
}
