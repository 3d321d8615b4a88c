#include "core/slam/slam_system.h"

#include <chrono>
#include <exception>
#include <filesystem>
#include <limits>
#include <optional>
#include <utility>

#include "core/map/map_store.h"
#include "core/slam/keyframe_conversion.h"

namespace icgm {

namespace {
using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool SameFile(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ea, eb;
  const auto ca = std::filesystem::weakly_canonical(a, ea);
  const auto cb = std::filesystem::weakly_canonical(b, eb);
  return (ea || eb) ? a == b : ca == cb;
}
}  // namespace

Status ParseMapMode(const std::string& name, MapMode* mode) {
  const std::optional<MapMode> parsed = ParseEnum<MapMode>(name);
  if (!parsed) return Status::Error("map mode '" + name + "' is neither mapping nor localization");
  *mode = *parsed;
  return Status::Ok();
}

const char* MapModeName(MapMode mode) { return NameOf(mode); }

// One processed frame: its odometry pose and the map keyframe it hangs from (-1: none yet,
// then map_camera is the pose at the time).
struct SlamSystem::FrameRecord {
  Time stamp;
  Pose3 odom_camera = Pose3::Identity();
  int keyframe_id = -1;
  Pose3 keyframe_camera = Pose3::Identity();  // T_keyframe_camera from odometry
  Pose3 map_camera = Pose3::Identity();
};

SlamSystem::SlamSystem(const SlamOptions& options, const CameraIntrinsics& intrinsics)
    : options_(options),
      intrinsics_(intrinsics),
      frontend_(std::make_unique<RgbdFrontend>(options.frontend, intrinsics)),
      builder_(std::make_unique<MapBuilder>(options.map)),
      registration_(
          std::make_unique<KeyframeRegistration>(options.keyframe_registration, intrinsics)),
      map_features_(std::make_unique<MapFeatureTracking>(options.map_features)),
      fix_filter_(options.localization.fix_filter) {
  CheckBackEndAvailable(options_);
  CheckFeaturesFitDictionary(options_);
  frontend_->SetKeyframeCallback([this](const KeyframePtr& kf) { pending_ = kf; });
}

SlamSystem::~SlamSystem() = default;

Status SlamSystem::AddWheelOdometry(Time stamp, const Pose3& odom_base) {
  return frontend_->AddWheelOdometry(stamp, odom_base);
}

void SlamSystem::SetMode(MapMode mode) {
  if (mode == builder_->mode()) return;
  Flush();
  const Pose3 map_from_odom = MapFromOdom();
  if (mode == MapMode::kLocalization) {
    // The pose is known when this system placed keyframes since the last Load.
    fix_.reset();
    fix_filter_ = OdometryFixFilter(options_.localization.fix_filter);
    if (last_keyframe_) fix_ = map_from_odom;
    path_since_fix_m_ = 0.0;
    last_localized_.reset();
    learned_keyframes_ = map().size();
  } else {
    session_from_odom_ = map_from_odom;  // mapping resumes where localization left the robot
  }
  last_keyframe_.reset();
  new_session_ = true;
  builder_->SetMode(mode);
}

Status SlamSystem::SetMode(const std::string& mode) {
  MapMode parsed;
  if (const Status s = ParseMapMode(mode, &parsed); !s.ok()) return s;
  SetMode(parsed);
  return Status::Ok();
}

MapMode SlamSystem::mode() const { return builder_->mode(); }

void SlamSystem::SetInitialPose(const Pose3& map_camera, const Pose3& odom_camera) {
  fix_ = map_camera * odom_camera.inverse();
  fix_filter_ = OdometryFixFilter(options_.localization.fix_filter);  // the next fix is taken
  path_since_fix_m_ = 0.0;
  last_localized_ = odom_camera;
  if (mode() == MapMode::kLocalization) {
    last_keyframe_.reset();  // a kept localization session restarts at the given pose
    new_session_ = true;
  }
}
void SlamSystem::StartLoop() {
  if (!new_session_) builder_->StartLoop();
}

void SlamSystem::StartSession() {
  Flush();
  session_from_odom_ = MapFromOdom();
  last_keyframe_.reset();
  new_session_ = true;
}
const HybridMap& SlamSystem::map() const { return builder_->map(); }

Pose3 SlamSystem::MapFromOdom() const {
  if (mode() == MapMode::kLocalization) return fix_ ? *fix_ : session_from_odom_;
  if (!last_keyframe_) return session_from_odom_;
  return map().keyframe(last_keyframe_->id).global_pose * last_keyframe_->odom_camera.inverse();
}

SlamFrameResult SlamSystem::ProcessFrame(Time stamp, const cv::Mat& bgr, const cv::Mat& depth_m,
                                         std::optional<Time> depth_stamp) {
  SlamFrameResult result;
  pending_.reset();
  try {
    result.frontend = frontend_->ProcessFrame(stamp, bgr, depth_m, depth_stamp);
  } catch (const std::exception& e) {
    // The front end does not throw on bad input; this guards a long-running node anyway.
    result.frontend = FrontendFrameResult();
    result.frontend.stamp = stamp;
    result.frontend.status = Status::Error(std::string("front end failed: ") + e.what());
    result.frontend.odom_camera = frontend_->odom_camera();
    pending_.reset();
  }
  const bool ignored = !frames_.empty() && result.frontend.stamp <= frames_.back().stamp;
  if (options_.build_map) {
    // The keyframe entering the map now (held back one frame with map_features.source tracker).
    if (const std::optional<FrontendKeyframe> keyframe =
            map_features_->AfterFrame(*frontend_, std::move(pending_))) {
      AddHeldToMap(*keyframe, &result);
    }
  }
  pending_.reset();
  FrameRecord record;
  record.stamp = result.frontend.stamp;
  record.odom_camera = result.frontend.odom_camera;
  if (last_keyframe_) {
    record.keyframe_id = last_keyframe_->id;
    record.keyframe_camera = Between(last_keyframe_->odom_camera, record.odom_camera);
  }
  record.map_camera = MapFromOdom() * record.odom_camera;
  result.map_camera = FramePose(record);
  if (!ignored) frames_.push_back(record);
  return result;
}

void SlamSystem::AddHeldToMap(const FrontendKeyframe& keyframe, SlamFrameResult* result) {
  result->keyframe = true;
  AddToMap(keyframe, result);
  // A keyframe held back one frame: its own frame hangs from it, as without the delay.
  if (map_features_->holds_keyframes() && result->keyframe_id >= 0 && !frames_.empty() &&
      frames_.back().stamp == keyframe.stamp) {
    frames_.back().keyframe_id = result->keyframe_id;
    frames_.back().keyframe_camera = Pose3::Identity();
  }
}

std::optional<SlamFrameResult> SlamSystem::Flush() {
  const std::optional<FrontendKeyframe> held = map_features_->Flush();
  if (!held) return std::nullopt;
  SlamFrameResult result;
  result.frontend.stamp = held->stamp;
  result.frontend.odom_camera = held->odom_camera;
  AddHeldToMap(*held, &result);
  result.map_camera = MapFromOdom() * held->odom_camera;
  return result;
}

SlamFrameResult SlamSystem::AddKeyframe(const FrontendKeyframe& keyframe) {
  SlamFrameResult result;
  result.keyframe = true;
  result.frontend.stamp = keyframe.stamp;
  result.frontend.odom_camera = keyframe.odom_camera;
  if (!frames_.empty() && keyframe.stamp <= frames_.back().stamp) {
    result.map_status =
        Status::Error("keyframe skipped: time went backwards (" + keyframe.stamp.ToString() +
                      " after " + frames_.back().stamp.ToString() + ")");
    return result;
  }
  AddToMap(keyframe, &result);
  FrameRecord record;
  record.stamp = keyframe.stamp;
  record.odom_camera = keyframe.odom_camera;
  if (last_keyframe_) {
    record.keyframe_id = last_keyframe_->id;
    record.keyframe_camera = Between(last_keyframe_->odom_camera, record.odom_camera);
  }
  record.map_camera = MapFromOdom() * record.odom_camera;
  result.map_camera = FramePose(record);
  frames_.push_back(record);
  return result;
}

void SlamSystem::AddToMap(const FrontendKeyframe& keyframe, SlamFrameResult* result) {
  if (!keyframe.odom_camera.matrix().allFinite()) {
    result->map_status = Status::Error("keyframe skipped: non-finite odometry pose");
    return;
  }
  if (mode() == MapMode::kLocalization) {
    Localize(keyframe, result);
    return;
  }
  double registration_ms = 0.0;
  int registrations = 0;
  const RegisterFn timed = TimedRegistration(&registration_ms, &registrations);
  const auto t0 = Clock::now();
  try {
    const bool opens_session = new_session_ || map().current_session() < 0;
    std::optional<Pose3> previous;
    if (!opens_session && last_keyframe_) previous = last_keyframe_->odom_camera;
    const bool consecutive =
        previous && last_frontend_keyframe_ && *last_frontend_keyframe_ + 1 == keyframe.id;
    Keyframe converted = ToMapKeyframe(keyframe, previous, session_from_odom_, options_.conversion);
    if (options_.map.map.store_depth_images) {
      converted.images = DownsampleKeyframeImages(keyframe.bgr, keyframe.depth_m, intrinsics_,
                                                  options_.map.map.depth_image_downsample);
    }
    if (opens_session) builder_->StartSession(options_.session_name);
    new_session_ = false;
    // The front end's registration covariance and the wheels' step span this map step only
    // when the previous map keyframe is the front end's previous keyframe.
    const Pose3* wheel_motion =
        consecutive && keyframe.wheel_camera_motion ? &*keyframe.wheel_camera_motion : nullptr;
    const Mat6 information = builder_->OdometryInformation(
        converted.relative_source,
        consecutive && keyframe.covariance ? &*keyframe.covariance : nullptr, wheel_motion);
    const Status added =
        builder_->AddKeyframe(std::move(converted), options_.loop_closure ? timed : RegisterFn(),
                              &result->update, &information, wheel_motion);
    if (!added.ok() && result->update.keyframe_id < 0) {
      result->map_status = added;
    } else {
      // A dictionary failure after insertion still leaves the keyframe in the map.
      if (!added.ok()) result->map_status = added;
      result->keyframe_id = result->update.keyframe_id;
      last_keyframe_ = MapKeyframeRef{result->keyframe_id, keyframe.odom_camera};
      last_frontend_keyframe_ = keyframe.id;
      keyframe_ids_.push_back(result->keyframe_id);
    }
  } catch (const std::exception& e) {
    result->map_status = Status::Error(std::string("keyframe skipped: ") + e.what());
  }
  result->map_ms = MsSince(t0);
  result->loop_registration_ms = registration_ms;
  result->loop_registrations = registrations;
  if (result->update.loop_closed) RecordLoopClosure(keyframe, *result, result->update.pose);
}

void SlamSystem::Localize(const FrontendKeyframe& keyframe, SlamFrameResult* result) {
  double registration_ms = 0.0;
  int registrations = 0;
  const RegisterFn timed = TimedRegistration(&registration_ms, &registrations);
  const auto t0 = Clock::now();
  try {
    if (last_localized_) {
      path_since_fix_m_ += TranslationNorm(Between(*last_localized_, keyframe.odom_camera));
    }
    last_localized_ = keyframe.odom_camera;
    // Without a previous keyframe, R_n is the predicted pose in the map.
    Keyframe query = ToMapKeyframe(keyframe, std::nullopt, MapFromOdom(), options_.conversion);
    query.global_pose = query.relative_pose;
    query.session_id = -1;
    result->update.pose_before_correction = query.global_pose;
    bool tracked = false;  // located at the nearest keyframes (not the dictionary)
    if (options_.loop_closure) {
      std::string nearest_failed;
      if (fix_ && options_.localization.nearest.count > 0) {
        result->update.loop = LocateAtNearestKeyframes(
            query, map(), learned_keyframes_, timed, options_.localization.nearest,
            options_.map.loop_closure, options_.localization.fix_gate, path_since_fix_m_);
        tracked = result->update.loop.status.ok();
        if (!tracked) nearest_failed = result->update.loop.status.reason() + "; ";
      }
      if (!tracked) {
        // Before the first fix the guard is open: global relocalization by place recognition.
        const double path_m = fix_ ? path_since_fix_m_ : std::numeric_limits<double>::infinity();
        result->update.loop = builder_->Relocalize(query, timed, path_m, learned_keyframes_);
        if (fix_ && result->update.loop.status.ok()) {
          const Status gated =
              CheckFixGate(query.global_pose, result->update.loop.loop_closure_pose,
                           path_since_fix_m_, options_.localization.fix_gate);
          if (!gated.ok()) result->update.loop.status = gated;
        }
        if (!result->update.loop.status.ok() && !nearest_failed.empty()) {
          result->update.loop.status =
              Status::Error(nearest_failed + result->update.loop.status.reason());
        }
      }
    } else {
      result->update.loop.status = Status::Error("no relocalization: loop closure is off");
    }
    if (result->update.loop.status.ok()) {
      Pose3 located = result->update.loop.loop_closure_pose;
      if (options_.localization.fix_filter.enabled) {
        Mat6 information = Mat6::Zero();
        for (const auto& e : result->update.loop.evidence) {
          if (e.rejected.empty()) information += e.registration.information;
        }
        // Uninitialized (first fix, initial pose, global relocalization): taken as measured.
        if (!fix_) fix_filter_ = OdometryFixFilter(options_.localization.fix_filter);
        located = fix_filter_.Update(query.global_pose, located, information, path_since_fix_m_);
      }
      result->update.loop.loop_closure_pose = located;
      fix_ = located * keyframe.odom_camera.inverse();
      path_since_fix_m_ = 0.0;
      ++relocalizations_;
      result->update.loop_closed = true;
    }
    result->update.pose = MapFromOdom() * keyframe.odom_camera;
    if (options_.localization.keyframes == LocalizationKeyframes::kSession) {
      // Kept apart from the learned map, at the localized poses, without loop links.
      const bool opens_session = new_session_ || !last_keyframe_;
      Keyframe kept = ToMapKeyframe(keyframe, std::nullopt, MapFromOdom(), options_.conversion);
      if (!opens_session) {
        kept.relative_pose =
            Between(map().keyframe(last_keyframe_->id).global_pose, result->update.pose);
      }
      if (opens_session) builder_->StartSession(options_.session_name + "_localization");
      new_session_ = false;
      const Mat6 information = builder_->OdometryInformation(kept.relative_source);
      KeyframeUpdate kept_update;
      const Status added =
          builder_->AddKeyframe(std::move(kept), RegisterFn(), &kept_update, &information);
      if (!added.ok()) result->map_status = added;
      if (kept_update.keyframe_id >= 0) {
        result->keyframe_id = kept_update.keyframe_id;
        result->update.keyframe_id = kept_update.keyframe_id;
        last_keyframe_ = MapKeyframeRef{kept_update.keyframe_id, keyframe.odom_camera};
        keyframe_ids_.push_back(kept_update.keyframe_id);
      }
    }
  } catch (const std::exception& e) {
    result->map_status = Status::Error(std::string("localization failed: ") + e.what());
  }
  result->map_ms = MsSince(t0);
  result->loop_registration_ms = registration_ms;
  result->loop_registrations = registrations;
  if (result->update.loop_closed) {
    RecordLoopClosure(keyframe, *result, result->update.loop.loop_closure_pose);
  }
}

RegisterFn SlamSystem::TimedRegistration(double* ms, int* count) const {
  return [this, ms, count](const Keyframe& query, const Keyframe& candidate) {
    const auto t0 = Clock::now();
    RegistrationOutcome out = register_override_ ? register_override_(query, candidate)
                                                 : registration_->Register(query, candidate);
    *ms += MsSince(t0);
    ++*count;
    return out;
  };
}

void SlamSystem::RecordLoopClosure(const FrontendKeyframe& keyframe,
                                   const SlamFrameResult& result, const Pose3& pose_after) {
  LoopClosureEvent event;
  event.frame_index = keyframe.frame_index;
  event.stamp = keyframe.stamp;
  event.keyframe_id = result.keyframe_id;
  for (const auto& e : result.update.loop.evidence) {
    if (e.rejected.empty()) event.candidate_ids.push_back(e.candidate_id);
  }
  event.registrations = result.update.loop.registrations;
  event.delta_pose_diff = result.update.loop.delta_pose_diff;
  event.pose_before = result.update.pose_before_correction;
  event.pose_after = pose_after;
  loop_closures_.push_back(event);
}

Pose3 SlamSystem::FramePose(const FrameRecord& record) const {
  if (record.keyframe_id < 0 || record.keyframe_id >= map().size()) return record.map_camera;
  return map().keyframe(record.keyframe_id).global_pose * record.keyframe_camera;
}

Trajectory SlamSystem::MapTrajectory() const {
  Trajectory out;
  out.reserve(frames_.size());
  for (const FrameRecord& r : frames_) out.push_back({r.stamp, Orthonormalized(FramePose(r))});
  return out;
}

Trajectory SlamSystem::OdomTrajectory() const {
  Trajectory out;
  out.reserve(frames_.size());
  for (const FrameRecord& r : frames_) out.push_back({r.stamp, r.odom_camera});
  return out;
}

Trajectory SlamSystem::KeyframeTrajectory() const {
  Trajectory out;
  for (int id : keyframe_ids_) {
    const Keyframe& kf = map().keyframe(id);
    out.push_back({kf.stamp, kf.global_pose});
  }
  return out;
}

Status SlamSystem::RefineMap(MapRefinementSummary* summary) {
  std::vector<Pose3> poses;
  try {
    const Status st = RefineMapPoses(map(), *registration_, intrinsics_, options_.map_refinement,
                                     &poses, summary);
    if (!st.ok()) return st;
  } catch (const std::exception& e) {
    return Status::Error(std::string("map refinement failed: ") + e.what());
  }
  return builder_->SetGlobalPoses(poses);
}

Status SlamSystem::Save(const std::string& path) const { return icgm::SaveMap(map(), path); }

Status SlamSystem::SaveMap(const std::string& requested, bool refine, std::string* detail) {
  const bool localizing = mode() == MapMode::kLocalization;
  const std::string path = !requested.empty() ? requested
                           : localizing       ? save_policy_.localization_path
                                              : save_policy_.map_path;
  if (path.empty()) {
    return Status::Error(localizing ? "no path given (localization saves only to its own file)"
                                    : "no path given");
  }
  if (localizing && (SameFile(path, loaded_path_) || SameFile(path, save_policy_.map_path))) {
    return Status::Error("localization never writes the learned map ('" + path +
                         "'); save to another file");
  }
  Status s = Save(path);
  if (!s.ok()) return s;
  std::string what = "saved " + std::to_string(map().size()) + " keyframes to " + path;
  if (refine && localizing) {
    what += " (not refined: in localization the learned map is the reference)";
  } else if (refine && map().size() > 1) {
    MapRefinementSummary summary;
    const Status r = RefineMap(&summary);
    if (r.ok()) {
      s = Save(path);
      if (!s.ok()) return s;
      what += " (bundle-adjusted: " + std::to_string(summary.bundle_adjustment.points) +
              " points)";
    } else {
      what += " (not refined: " + r.reason() + ")";
    }
  }
  keyframes_since_save_ = 0;
  if (detail) *detail = what;
  return Status::Ok();
}

Status SlamSystem::Autosave(const SlamFrameResult& result, std::string* written) {
  written->clear();
  if (result.keyframe_id >= 0) ++keyframes_since_save_;
  const int every = save_policy_.autosave_every_keyframes;
  const bool due = result.keyframe_id >= 0 &&
                   (result.update.loop_closed || (every > 0 && keyframes_since_save_ >= every));
  const bool localizing = mode() == MapMode::kLocalization;
  const std::string& path = localizing ? save_policy_.localization_path : save_policy_.map_path;
  if (!due || path.empty() || map().empty()) return Status::Ok();
  const Status s = SaveMap(path, false);
  if (s.ok()) *written = path;
  return s;
}

Status SlamSystem::Load(const std::string& path, bool merge) {
  HybridMap loaded;
  std::string note;
  try {
    loaded = LoadMap(path, &note);
  } catch (const LoadError& e) {
    return Status::Error(e.what());
  } catch (const std::exception& e) {
    return Status::Error(path + ": " + e.what());
  }
  Flush();  // a held keyframe belongs to the map being replaced or merged into
  const Pose3 map_from_odom = MapFromOdom();
  if (merge) {
    HybridMap combined = map();
    combined.Merge(loaded);
    const Status reset = builder_->Reset(std::move(combined));
    if (!reset.ok()) return Status::Error(path + ": " + reset.reason());
    // Our ids are unchanged by Merge, so the frame records stay valid.
    session_from_odom_ = map_from_odom;
  } else {
    const Status reset = builder_->Reset(std::move(loaded));
    if (!reset.ok()) return Status::Error(path + ": " + reset.reason());
    frames_.clear();
    keyframe_ids_.clear();
    loop_closures_.clear();
    session_from_odom_ = Pose3::Identity();
    // Where the odometry lies in the loaded map is unknown until a fix.
    fix_.reset();
    fix_filter_ = OdometryFixFilter(options_.localization.fix_filter);
    last_localized_.reset();
  }
  last_keyframe_.reset();
  new_session_ = true;
  loaded_path_ = path;
  load_note_ = note;
  learned_keyframes_ = map().size();
  keyframes_since_save_ = 0;
  return Status::Ok();
}

}  // namespace icgm
