#include "tools/place_recognition_run.h"

#include <ctime>
#include <memory>

#include "core/common/thread_cpu_time.h"
#include "core/features/feature_extractor.h"

namespace icgm::tools {
namespace {

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
  auto process = [&](int index, const FeatureSet& f, const std::vector<uint8_t>& robust) {
    PlaceDecision d;
    const double t0 = ThreadCpuMs();
    Status s = recognizer.Recognize(index, f, robust, &d);
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
    const cv::Mat image = images(i, &error);
    if (image.empty()) return Status::Error(error);
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
