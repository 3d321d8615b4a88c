#include "core/slam/live_map.h"

#include <utility>

namespace icgm {

std::string LocalizationMapPathFor(const std::string& map_path) {
  if (map_path.empty()) return "";
  const size_t dot = map_path.rfind(".db");
  return (dot == std::string::npos ? map_path : map_path.substr(0, dot)) + "_localization.db";
}

LiveMap::LiveMap(const SlamOptions& options, LiveMapOptions live)
    : options_(options), live_(std::move(live)), pending_mode_(live_.mode) {
  if (live_.localization_map_path.empty()) {
    live_.localization_map_path = LocalizationMapPathFor(live_.map_path);
  }
  if (!live_.load_path.empty()) pending_load_ = live_.load_path;
}

LiveMap::~LiveMap() = default;

Status LiveMap::Start(const CameraIntrinsics& intrinsics, std::string* loaded) {
  if (system_) return Status::Ok();
  system_ = std::make_unique<SlamSystem>(options_, intrinsics);
  system_->SetSavePolicy(
      {live_.map_path, live_.localization_map_path, live_.autosave_every_keyframes});
  Status status = Status::Ok();
  if (pending_load_) {
    status = system_->Load(*pending_load_, false);
    if (status.ok() && loaded) {
      *loaded = std::to_string(system_->map().size()) + " keyframes from " + *pending_load_;
      if (!system_->load_note().empty()) *loaded += " (" + system_->load_note() + ")";
    }
    pending_load_.reset();
  }
  system_->SetMode(pending_mode_);
  return status;
}

bool LiveMap::LocalizingWithoutMap() const {
  return system_ && system_->mode() == MapMode::kLocalization && system_->map().empty();
}

LiveMapUpdate LiveMap::AddKeyframe(const FrontendKeyframe& keyframe) {
  LiveMapUpdate update;
  update.result = system_->AddKeyframe(keyframe);
  if (update.result.map_status.ok()) {
    update.autosave = system_->Autosave(update.result, &update.saved_to);
  }
  return update;
}

Status LiveMap::Save(const std::string& path, std::string* message) {
  if (!system_) return Status::Error("no map yet (no camera_info received)");
  return system_->SaveMap(path, system_->options().map_refinement.enabled, message);
}

Status LiveMap::Load(const std::string& path, bool merge, std::string* message) {
  if (!system_) {
    pending_load_ = path;
    *message = "will load when the first camera_info arrives";
    return Status::Ok();
  }
  const Status s = system_->Load(path, merge);
  if (s.ok()) *message = "map has " + std::to_string(system_->map().size()) + " keyframes";
  if (s.ok() && !system_->load_note().empty()) *message += " (" + system_->load_note() + ")";
  return s;
}

Status LiveMap::SetMode(const std::string& name, std::string* message) {
  MapMode mode;
  if (const Status s = ParseMapMode(name, &mode); !s.ok()) return s;
  pending_mode_ = mode;
  if (system_) system_->SetMode(mode);
  *message = "mode " + name;
  return Status::Ok();
}

Status LiveMap::SaveAtShutdown(std::string* written) {
  written->clear();
  if (!system_ || system_->map().empty()) return Status::Ok();
  const bool localizing = system_->mode() == MapMode::kLocalization;
  // Localization without kept keyframes changed nothing.
  if (localizing && system_->options().localization.keyframes == LocalizationKeyframes::kNone) {
    return Status::Ok();
  }
  const SavePolicy& policy = system_->save_policy();
  const std::string& path = localizing ? policy.localization_path : policy.map_path;
  if (path.empty()) return Status::Ok();
  std::string detail;
  const Status s = system_->SaveMap("", false, &detail);
  if (s.ok()) *written = path;
  return s;
}

}  // namespace icgm
