// The map of a running robot (the map-building nodelet's core): a SlamSystem that is created
// when the camera is known (the first keyframe), with a map to load and a mode that may be
// asked for before that, and the save policy of SavePolicy:
//  - mapping: saved to map_path on every loop closure, every autosave_every_keyframes keyframes
//    and at shutdown;
//  - localization: the learned map is never written; autosave and the shutdown save go to
//    localization_map_path (by default map_path with "_localization" before ".db"), and only
//    when localization keeps keyframes (localization.keyframes = session).
// Requests (save, load, mode) answer with a Status and a message for the caller.
// Not thread-safe: call from one thread.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/odometry/frontend_types.h"
#include "core/slam/slam_system.h"

namespace icgm {

struct LiveMapOptions {
  std::string map_path;               // mapping saves here ("" : never)
  std::string localization_map_path;  // "" : derived from map_path (LocalizationMapPathFor)
  std::string load_path;              // a map to load when the system starts ("" : none)
  MapMode mode = MapMode::kMapping;
  int autosave_every_keyframes = 20;  // and on every loop closure; 0: only on loop closures
};

// map_path with "_localization" before its ".db" (appended when there is none); "" for "".
std::string LocalizationMapPathFor(const std::string& map_path);

// What one keyframe did to the map, for the log.
struct LiveMapUpdate {
  SlamFrameResult result;
  Status autosave = Status::Ok();  // an autosave that failed
  std::string saved_to;            // the file written by autosave ("" : none)
};

class LiveMap {
 public:
  LiveMap(const SlamOptions& options, LiveMapOptions live);
  ~LiveMap();

  // Creates the system for `intrinsics` (once; later calls do nothing), loads the pending map
  // and sets the mode. *loaded: what was loaded; a failed load is the returned error (the
  // system is started anyway, with an empty map). Throws LoadError as SlamSystem does.
  Status Start(const CameraIntrinsics& intrinsics, std::string* loaded);
  bool started() const { return system_ != nullptr; }
  // Localization without a map: there is nothing to localize against.
  bool LocalizingWithoutMap() const;

  // A keyframe with its odometry pose (keyframe.odom_camera) into the map, then autosave.
  LiveMapUpdate AddKeyframe(const FrontendKeyframe& keyframe);

  // Save request: `path` ("" : the mode's file); in mapping mode with map_refinement.enabled,
  // refined and saved again (SlamSystem::SaveMap). *message: what was done.
  Status Save(const std::string& path, std::string* message);
  // Load request; before Start the load is deferred to it.
  Status Load(const std::string& path, bool merge, std::string* message);
  // Mode request by name (ParseMapMode); before Start it applies at Start.
  Status SetMode(const std::string& name, std::string* message);
  // The shutdown save of the policy (nothing when there is nothing to write). *written: path.
  Status SaveAtShutdown(std::string* written);

  SlamSystem* system() { return system_.get(); }
  const SlamSystem* system() const { return system_.get(); }

 private:
  SlamOptions options_;
  LiveMapOptions live_;
  std::optional<std::string> pending_load_;
  MapMode pending_mode_;
  std::unique_ptr<SlamSystem> system_;
};

}  // namespace icgm
