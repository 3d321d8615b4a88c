// Which features a front-end keyframe brings into the map (`map_features.source` of
// config/map.yaml), as one step after each front-end frame, shared by SlamSystem (offline and
// in-process pipelines) and the registration nodelet (the live pipeline's keyframes):
//  - kReferenceKeyframe: a new keyframe goes to the map at once with the ICGM flags of its
//    registration against the reference keyframe;
//  - kTracker (thesis 6.1.3.1): the robust feature tracker (double-directional ICGM, S = 3 in
//    the thesis profile) runs over every frame's features; its set C = A u B of a frame needs
//    the next frame, so a new keyframe is held back and released, with the tracker's flags,
//    after its next frame (or by Flush, with the backward half only, at the end of the frames
//    or at a mode switch; or by ReleaseHeld, the same flags, when the frames pause).
// Not thread-safe.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/common/time.h"
#include "core/odometry/frontend_types.h"
#include "core/slam/slam_options.h"

namespace icgm {

class RgbdFrontend;

// `map_features:` of a map.yaml with the tracker's options from an icgm.yaml, as LoadSlamOptions
// reads them (the whole map.yaml is checked). Throws LoadError.
MapFeatureOptions LoadMapFeatureOptions(const std::string& map_config_file,
                                        const std::string& icgm_config_file);

class MapFeatureTracking {
 public:
  explicit MapFeatureTracking(const MapFeatureOptions& options);
  ~MapFeatureTracking();
  MapFeatureTracking(const MapFeatureTracking&) = delete;
  MapFeatureTracking& operator=(const MapFeatureTracking&) = delete;

  // After the front end processed a frame (whatever its outcome): `new_keyframe` is the
  // keyframe the front end made during it (nullptr: none). Returns the keyframe that enters the
  // map now, with the features the option chooses, or nullopt. kTracker: the front end's last
  // frame is fed to the tracker once (a frame the front end dropped is not fed again).
  std::optional<FrontendKeyframe> AfterFrame(const RgbdFrontend& frontend,
                                             KeyframePtr new_keyframe);
  // The same with the frame's features given directly (`features` nullptr: no new frame).
  std::optional<FrontendKeyframe> AfterFrame(Time stamp, const FeatureSet* features,
                                             KeyframePtr new_keyframe);
  // End of the frames (or a break in them): the held keyframe, robust from the backward half
  // of the window; the tracker starts a new sequence. nullopt when none is held.
  std::optional<FrontendKeyframe> Flush();
  // A pause in the frames (no frame for a while, live): the held keyframe now, robust from the
  // backward half of the window as Flush gives it, but the tracker's sequence goes on, so the
  // frames after the pause are tracked as without it. nullopt when none is held.
  std::optional<FrontendKeyframe> ReleaseHeld();

  bool holds_keyframes() const { return tracker_ != nullptr; }  // source = tracker
  bool holding() const { return held_ != nullptr; }
  const KeyframePtr& held() const { return held_; }

 private:
  // The held keyframe, with `tracked`'s flags when they are its frame's.
  std::optional<FrontendKeyframe> Release(const std::optional<TrackedFrame>& tracked);

  std::unique_ptr<RobustFeatureTracker> tracker_;  // source = tracker
  std::optional<Time> tracked_stamp_;              // the last frame fed to tracker_
  KeyframePtr held_;                               // waiting for its next frame
};

}  // namespace icgm
