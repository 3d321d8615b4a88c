#include "tools/place_recognition_run.h"

#include <cmath>
#include <ctime>
#include <map>
#include <memory>

#include "core/common/thread_cpu_time.h"
#include "core/features/feature_extractor.h"
#include "core/registration/depth_points.h"

namespace icgm::tools {
namespace {

// Camera-frame 3-D point per keypoint from the depth image; NaN where it has none.
std::vector<Eigen::Vector3d> LiftKeypoints(const FeatureSet& features, const cv::Mat& depth_m,
                                           const CameraIntrinsics& camera) {
  std::vector<cv::Point2f> pixels;
  pixels.reserve(features.size());
  for (const cv::KeyPoint& k : features.keypoints) pixels.push_back(k.pt);
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> valid;
  KeypointsToPoints(pixels, CorrectedDepth(depth_m, camera), camera, DepthPointOptions(), &points,
                    &valid);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!valid[i]) points[i].setConstant(std::nan(""));
  }
  return points;
}

}  // namespace

Status RunPlaceRecognition(size_t count, const ImageSource& images,
                           const PlaceRunSettings& settings,
                           const std::function<void(size_t)>& progress, PlaceRunResult* result) {
  *result = PlaceRunResult();
  std::unique_ptr<FeatureExtractor> extractor = FeatureExtractor::Create(settings.tracker.features);
  if (!extractor) {
    return Status::Error(std::string("unknown detector '") +
                         NameOf(settings.tracker.features.detector) + "'");
  }
  result->detector = extractor->name();
  DictionaryOptions dictionary = settings.dictionary;
  dictionary.descriptor_type =
      extractor->binary() ? DescriptorType::kBinary : DescriptorType::kFloat;
  PlaceRecognizer recognizer(settings.place, dictionary, settings.camera);
  recognizer.set_keep_scores(settings.keep_scores);
  std::optional<RobustFeatureTracker> tracker;
  if (settings.robust != "none") {
    TrackerOptions t = settings.tracker;
    const std::optional<TrackerMode> mode = ParseEnum<TrackerMode>(settings.robust);
    if (!mode) return Status::Error("unknown tracker mode '" + settings.robust + "'");
    t.mode = *mode;
    t.window_size = std::max(t.window_size, MinWindowSize(t.mode));
    tracker.emplace(t);
  }
  size_t features = 0, verified = 0;
  double query_ms = 0.0;
  // Depth images of the frames not yet processed (the double-directional tracker holds one).
  const bool want_depth = settings.place.geometry.enabled &&
                          (settings.place.geometry.rgbd || settings.place.depth_candidates > 0) &&
                          settings.camera;
  std::map<int, cv::Mat> depths;
  auto process = [&](int index, const FeatureSet& f, const std::vector<uint8_t>& robust) {
    PlaceDecision d;
    std::vector<Eigen::Vector3d> points;
    const auto depth = depths.find(index);
    if (depth != depths.end()) {
      points = LiftKeypoints(f, depth->second, *settings.camera);
      depths.erase(depth);
    }
    const double t0 = ThreadCpuMs();
    Status s = recognizer.Recognize(index, f, robust, &d, points.empty() ? nullptr : &points);
    query_ms += ThreadCpuMs() - t0;
    if (s.ok()) s = recognizer.Add();
    if (!s.ok()) return Status::Error("image " + std::to_string(index) + ": " + s.reason());
    features += f.size();
    for (uint8_t r : robust) verified += r;
    if (robust.empty()) verified += f.size();
    result->decisions.push_back(d);
    result->queries.push_back({index, d.match, d.score});
    return Status::Ok();
  };
  auto process_tracked = [&](const std::optional<TrackedFrame>& frame) {
    if (!frame) return Status::Ok();
    return process(static_cast<int>(frame->stamp.nanoseconds()), frame->features, frame->robust);
  };
  for (size_t i = 0; i < count; ++i) {
    std::string error;
    cv::Mat depth;
    const cv::Mat image = images(i, &error, want_depth ? &depth : nullptr);
    if (image.empty()) return Status::Error(error);
    if (!depth.empty()) depths[static_cast<int>(i)] = depth;
    Status s = Status::Ok();
    try {
      s = tracker ? process_tracked(
                        tracker->AddImage(Time::FromNanoseconds(static_cast<int64_t>(i)), image))
                  : process(static_cast<int>(i), extractor->Extract(image), {});
    } catch (const cv::Exception& e) {
      return Status::Error("image " + std::to_string(i) + ": " + e.what());
    }
    if (!s.ok()) return s;
    if (progress) progress(i + 1);
  }
  if (tracker) {
    const Status s = process_tracked(tracker->Flush());
    if (!s.ok()) return s;
  }
  result->words = recognizer.dictionary().num_words();
  result->verified_share = features ? static_cast<double>(verified) / features : 0.0;
  result->mean_query_ms = count ? query_ms / static_cast<double>(count) : 0.0;
  return Status::Ok();
}

}  // namespace icgm::tools
