#include "core/mono/mono_odometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>
#include <utility>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/hal/hal.hpp>

#include "core/common/thread_cpu_time.h"
#include "core/icgm/icgm_matcher.h"
#include "core/mono/pnp_pose.h"
#include "core/mono/rotation_only.h"
#include "core/mono/triangulation.h"
#include "core/mono/two_view.h"
#include "core/odometry/odometry_fusion.h"
#include "core/optimization/bundle_adjustment.h"

namespace icgm {

namespace {

// The pose after p1 at the motion from p0 to p1 repeated `f` times (constant velocity).
Pose3 CarryOn(const Pose3& p0, const Pose3& p1, double f) {
  return p1 * ExpSE3(f * LogSE3(Between(p0, p1)));
}

// Stage times are the thread's CPU time, which other processes on a loaded machine do not
// inflate as they do the wall clock.
struct Clock {
  static double now() { return ThreadCpuMs(); }
};
double MsSince(double t0) { return ThreadCpuMs() - t0; }

// The ICGM group of matches pa[k] <-> pb[k] grown (Algorithm 1, Thr `threshold`) from seed
// pairs spread over `anchors` (matches known to be static; deterministic): the group holding
// most anchors wins. Empty when no seed pair of anchors is consistent.
std::vector<uint8_t> AnchoredIcgmGroup(const std::vector<Eigen::Vector2d>& pa,
                                       const std::vector<Eigen::Vector2d>& pb,
                                       const std::vector<int>& anchors, int seed_pairs,
                                       double threshold) {
  const int n = static_cast<int>(anchors.size());
  const int seeds = std::max(1, seed_pairs);
  IcgmResult best;
  size_t best_anchors = 0;
  for (int s = 0; s < seeds; ++s) {
    const int i = (s * n) / (2 * seeds);
    const int j = n - 1 - i;
    if (i >= j) break;
    IcgmResult r = RunIcgmFromSeed(pa, pb, anchors[i], anchors[j], threshold);
    if (!r.status.ok()) continue;
    size_t kept = 0;
    for (const int a : anchors) kept += r.kept[a];
    if (kept > best_anchors) {
      best_anchors = kept;
      best = std::move(r);
    }
  }
  return best_anchors > 0 ? best.kept : std::vector<uint8_t>();
}

// The essential matrix's RANSAC and the triangulation's bounds from the VO options.
TwoViewOptions TwoViewOptionsFrom(const MonoVoOptions& o) {
  TwoViewOptions tv;
  tv.ransac_threshold_px = o.essential_threshold_px;
  tv.ransac_confidence = o.essential_confidence;
  tv.ransac_order_seed = static_cast<uint64_t>(o.ransac_order_seed);
  tv.triangulation.max_reprojection_px = o.max_reprojection_px;
  tv.triangulation.min_angle_deg = o.min_triangulation_deg;
  tv.triangulation.max_depth_baselines = o.max_depth_baselines;
  return tv;
}
}  // namespace

const char* MonoStateName(MonoState state) {
  switch (state) {
    case MonoState::kInitializing:
      return "initializing";
    case MonoState::kTracking:
      return "tracking";
    case MonoState::kLost:
      return "lost";
  }
  return "?";
}

// One image's features; `px` are the keypoints on the ideal pinhole image.
struct MonoOdometry::Frame {
  size_t index = 0;
  Time stamp;
  FeatureSet features;
  std::vector<Eigen::Vector2d> px;
};

struct MonoOdometry::Keyframe {
  Frame frame;
  Pose3 world_camera = Pose3::Identity();
  std::vector<int> point_ids;  // per keypoint: map point id, -1 none
};

struct MonoOdometry::MapPoint {
  Eigen::Vector3d world = Eigen::Vector3d::Zero();
  cv::Mat descriptor;      // of the keypoint that created it (one row)
  int outlier_frames = 0;  // tracked frames in a row it was matched but off the pose
  // Keyframes that saw it in place (pnp_verified_min_keyframes), the first and the last.
  int keyframes = 0;
  Time first_seen, last_seen;
};

// Matches a -> b (queryIdx in a, trainIdx in b) and which of them ICGM kept.
struct MonoOdometry::Matches {
  std::vector<cv::DMatch> all;
  std::vector<uint8_t> kept;
  size_t num_kept = 0;
};

MonoOdometry::MonoOdometry(const MonoOptions& options, const CameraIntrinsics& intrinsics)
    : options_(options),
      intrinsics_(intrinsics),
      extractor_(FeatureExtractor::Create(options.features)),
      matcher_(options.matcher),
      wheel_(options.wheel_odometry),
      undistort_(intrinsics.HasDistortion()) {}

MonoOdometry::~MonoOdometry() = default;

Status MonoOdometry::AddWheelOdometry(Time stamp, const Pose3& odom_base) {
  return wheel_.Add(stamp, odom_base);
}

MonoOdometry::Frame MonoOdometry::MakeFrame(Time stamp, const cv::Mat& image,
                                            MonoStageTimes* times) const {
  Frame f;
  f.index = frame_count_;
  f.stamp = stamp;
  const auto t0 = Clock::now();
  f.features = extractor_->Extract(image);
  std::vector<cv::Point2f> raw;
  raw.reserve(f.features.size());
  for (const cv::KeyPoint& k : f.features.keypoints) raw.push_back(k.pt);
  if (undistort_ && !raw.empty()) {
    const CameraIntrinsics& c = intrinsics_;
    const cv::Matx33d k(c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1);
    const cv::Vec<double, 5> d(c.distortion_k1, c.distortion_k2, c.distortion_p1, c.distortion_p2,
                               c.distortion_k3);
    std::vector<cv::Point2f> ideal;
    cv::undistortPoints(raw, ideal, k, d, cv::noArray(), k);
    raw = ideal;
    for (size_t i = 0; i < raw.size(); ++i) f.features.keypoints[i].pt = raw[i];
  }
  f.px.reserve(raw.size());
  for (const cv::Point2f& p : raw) f.px.emplace_back(p.x, p.y);
  times->features_ms += MsSince(t0);
  return f;
}

MonoOdometry::Matches MonoOdometry::MatchFrames(const Frame& a, const Frame& b,
                                                MonoStageTimes* times, bool robust,
                                                const Keyframe* keyframe,
                                                const std::optional<Pose3>& predicted,
                                                const std::vector<cv::DMatch>* given) const {
  Matches m;
  auto t0 = Clock::now();
  m.all = given ? *given : matcher_.Match(a.features, b.features);
  times->matching_ms += MsSince(t0);
  t0 = Clock::now();
  m.kept.assign(m.all.size(), 1);
  if (robust && options_.vo.use_icgm && m.all.size() >= 2) {
    std::vector<Eigen::Vector2d> pa, pb;
    pa.reserve(m.all.size());
    pb.reserve(m.all.size());
    for (const cv::DMatch& d : m.all) {
      pa.push_back(a.px[d.queryIdx]);
      pb.push_back(b.px[d.trainIdx]);
    }
    // Motion prior: where the keyframe's map points reproject with the predicted pose if they
    // are static. ICGM on those matches with the prediction (a walker filling the view cannot
    // win by size); the matches without a map point (candidates for new points) keep the plain
    // rules.
    std::vector<Eigen::Vector2d> expected;
    size_t with_prior = 0;
    if (options_.icgm.motion_prior && keyframe && predicted) {
      const Pose3 camera_world = predicted->inverse();
      expected.assign(m.all.size(), Eigen::Vector2d::Constant(std::nan("")));
      for (size_t k = 0; k < m.all.size(); ++k) {
        const int id = keyframe->point_ids[m.all[k].queryIdx];
        if (id < 0) continue;
        const Eigen::Vector3d c = camera_world * points_.at(id).world;
        if (c.z() <= 1e-6) continue;
        expected[k] = intrinsics_.Project(c);
        ++with_prior;
      }
    }
    if (with_prior >= 2) {
      m.kept = RunIcgm(pa, pb, PriorOptions(), &expected).kept;
      std::vector<Eigen::Vector2d> qa, qb;
      std::vector<size_t> rest;
      for (size_t k = 0; k < m.all.size(); ++k) {
        if (expected[k].allFinite()) continue;
        qa.push_back(pa[k]);
        qb.push_back(pb[k]);
        rest.push_back(k);
      }
      IcgmOptions plain = options_.icgm;
      plain.motion_prior = false;
      const std::vector<uint8_t> rest_kept = RunIcgm(qa, qb, plain).kept;
      for (size_t i = 0; i < rest.size(); ++i) m.kept[rest[i]] = rest_kept[i];
    } else {
      IcgmOptions plain = options_.icgm;
      plain.motion_prior = false;
      m.kept = RunIcgm(pa, pb, plain).kept;
    }
  }
  m.num_kept = static_cast<size_t>(std::count(m.kept.begin(), m.kept.end(), 1));
  times->icgm_ms += MsSince(t0);
  return m;
}

std::optional<double> MonoOdometry::WheelDistance(Time from, Time to) const {
  if (!base_to_camera_ || wheel_.empty()) return std::nullopt;
  Pose3 base_motion;
  if (!wheel_.RelativeMotion(from, to, &base_motion).ok()) return std::nullopt;
  return CameraMotionFromBase(base_motion, *base_to_camera_).translation().norm();
}

std::optional<Pose3> MonoOdometry::PredictPose(Time stamp, bool* from_wheels) const {
  if (from_wheels) *from_wheels = false;
  if (recent_.empty()) return last_pose_;
  // With the wheels' metric scale the map is in metres: the last pose moved by the wheels'
  // motion since it (a turning robot breaks the constant-velocity assumption, the wheels do
  // not).
  if (options_.vo.wheel_prediction && scale_known_ && base_to_camera_ && !wheel_.empty()) {
    Pose3 base_motion;
    if (wheel_.RelativeMotion(recent_.back().first, stamp, &base_motion).ok()) {
      if (from_wheels) *from_wheels = true;
      return recent_.back().second * CameraMotionFromBase(base_motion, *base_to_camera_);
    }
  }
  if (recent_.size() < 2) return recent_.back().second;
  const auto& [t0, p0] = recent_[recent_.size() - 2];
  const auto& [t1, p1] = recent_.back();
  const double dt_last = DurationSeconds(t1, t0);
  if (!(dt_last > 1e-6)) return p1;
  return CarryOn(p0, p1, std::min(3.0, DurationSeconds(stamp, t1) / dt_last));
}

IcgmOptions MonoOdometry::PriorOptions() const {
  const MonoVoOptions& o = options_.vo;
  IcgmOptions prior = options_.icgm;
  // A wheel prediction is close to the truth: a tighter Thr separates walkers better.
  if (prediction_from_wheels_) {
    prior.motion_prior_threshold = o.wheel_prior_threshold;
  } else if (o.prior_from_prediction_error && prediction_error_px_) {
    // Static points move away from their constant-velocity prediction by about the last
    // frames' prediction error; Thr and tolerance follow it.
    prior.motion_prior_threshold = std::clamp(o.prior_threshold_per_px * *prediction_error_px_,
                                              o.prior_threshold_min, o.prior_threshold_max);
    prior.motion_prior_tolerance_px =
        std::max(prior.motion_prior_tolerance_px, o.prior_tolerance_errors * *prediction_error_px_);
  }
  return prior;
}

std::optional<double> MonoOdometry::PredictionError(const Pose3& predicted,
                                                    const std::vector<Eigen::Vector3d>& points,
                                                    const std::vector<Eigen::Vector2d>& pixels,
                                                    const std::vector<uint8_t>& use) const {
  const Pose3 camera_world = predicted.inverse();
  std::vector<double> errors;
  for (size_t i = 0; i < points.size() && i < use.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::Vector3d c = camera_world * points[i];
    if (c.z() <= 1e-6) continue;
    errors.push_back((intrinsics_.Project(c) - pixels[i]).norm());
  }
  if (errors.size() < 10) return std::nullopt;
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}

void MonoOdometry::RememberPose(Time stamp, const Pose3& world_camera) {
  recent_.emplace_back(stamp, world_camera);
  while (recent_.size() > 2) recent_.pop_front();
  last_pose_ = world_camera;
}

MonoFrameResult MonoOdometry::ProcessFrame(Time stamp, const cv::Mat& image) {
  const auto t0 = Clock::now();
  MonoFrameResult result;
  result.frame_index = frame_count_;
  result.stamp = stamp;
  if (image.empty() || image.depth() != CV_8U ||
      (image.channels() != 1 && image.channels() != 3 && image.channels() != 4)) {
    result.status = Status::Error("image empty or not 8-bit grey/BGR/BGRA");
  }
  Frame frame = result.status.ok() ? MakeFrame(stamp, image, &result.times) : Frame();
  frame.index = frame_count_;
  frame.stamp = stamp;
  result.num_features = frame.features.size();
  if (result.status.ok() && static_cast<int>(frame.features.size()) < options_.vo.min_features) {
    result.status = Status::Error(std::to_string(frame.features.size()) + " features < " +
                                  std::to_string(options_.vo.min_features));
  }
  if (state_ == MonoState::kInitializing && result.status.ok() && kept_map_ && !window_.empty()) {
    // relocalize_while_initializing: the map lost at the reset first; tracking resumes in it
    // when the frame relocalizes there.
    Correspondences c;
    Matches to_last;
    MonoFrameResult probe;
    const bool found = Relocalize(frame, PredictPose(stamp), &c, &to_last, &probe).status.ok();
    result.times.matching_ms += probe.times.matching_ms;
    result.times.geometry_ms += probe.times.geometry_ms;
    if (found) {
      kept_map_ = false;
      reference_.reset();
      lost_frames_ = 0;
      frames_since_keyframe_ = 0;
      state_ = MonoState::kTracking;
      result.relocalized = true;
    }
  }
  if (state_ == MonoState::kInitializing) {
    if (result.status.ok()) TryInitialize(std::move(frame), &result);
  } else {
    if (result.status.ok()) {
      Track(std::move(frame), &result);
    } else if (++lost_frames_ >= static_cast<size_t>(options_.vo.lost_frames_before_reset)) {
      Reset(&result);
    } else {
      state_ = MonoState::kLost;
    }
  }
  ++frame_count_;
  result.state = state_;
  result.scale_known = scale_known_;
  result.map_points = points_.size();
  result.times.total_ms = MsSince(t0);
  return result;
}

void MonoOdometry::TryInitialize(Frame frame, MonoFrameResult* result) {
  const MonoVoOptions& o = options_.vo;
  const auto take_as_reference = [&](Frame&& f) {
    reference_ = std::make_unique<Frame>(std::move(f));
    reference_pose_ = ReferencePose(reference_->stamp);
    frames_since_reference_ = 0;
  };
  if (!reference_) {
    take_as_reference(std::move(frame));
    result->status = Status::Error("initialization: reference frame taken");
    return;
  }
  ++frames_since_reference_;
  const bool robust =
      o.initialization_matches == MonoInitMatches::kIcgm ||
      (o.initialization_matches == MonoInitMatches::kAllAfterReset && num_resets_ == 0);
  const Matches m = MatchFrames(*reference_, frame, &result->times, robust);
  result->num_matches = m.all.size();
  result->num_icgm_kept = m.num_kept;
  if (static_cast<int>(m.num_kept) < o.init_min_matches) {
    result->status = Status::Error("initialization: " + std::to_string(m.num_kept) + " matches < " +
                                   std::to_string(o.init_min_matches) + ", new reference");
    take_as_reference(std::move(frame));
    return;
  }
  const auto tg = Clock::now();
  std::vector<Eigen::Vector2d> pa, pb;
  std::vector<size_t> index;  // into m.all
  for (size_t k = 0; k < m.all.size(); ++k) {
    if (!m.kept[k]) continue;
    pa.push_back(reference_->px[m.all[k].queryIdx]);
    pb.push_back(frame.px[m.all[k].trainIdx]);
    index.push_back(k);
  }
  TwoViewOptions tv_options = TwoViewOptionsFrom(o);
  tv_options.refine_max_solver_time_s = options_.bundle_adjustment.max_solver_time_s;
  result->robust_pixels = pb;
  const TwoViewResult tv = RecoverTwoViewMotion(pa, pb, intrinsics_, tv_options);
  result->times.geometry_ms += MsSince(tg);
  result->num_inliers = tv.num_inliers;
  for (size_t k = 0; k < tv.inliers.size(); ++k) {
    if (tv.inliers[k]) result->robust_inliers.push_back(static_cast<int>(k));
  }
  result->inlier_ratio = pa.empty() ? 0.0 : static_cast<double>(tv.num_inliers) / pa.size();
  const bool enough = tv.status.ok() &&
                      static_cast<int>(tv.num_triangulated) >= o.init_min_points &&
                      tv.median_parallax_deg >= o.init_min_parallax_deg;
  if (!enough) {
    result->status =
        Status::Error("initialization: " +
                      (tv.status.ok() ? std::to_string(tv.num_triangulated) + " points, parallax " +
                                            std::to_string(tv.median_parallax_deg) + " deg"
                                      : tv.status.reason()));
    if (frames_since_reference_ >= static_cast<size_t>(o.init_max_frames)) {
      take_as_reference(std::move(frame));
    }
    return;
  }
  const auto tm = Clock::now();
  // Scale of the unit baseline: the wheels' distance, else the speed carried over a reset.
  double scale = 1.0;
  bool known = false;
  const double dt = DurationSeconds(frame.stamp, reference_->stamp);
  if (const auto d = WheelDistance(reference_->stamp, frame.stamp);
      d && *d >= o.wheel_min_baseline_m) {
    scale = *d;
    known = true;
  } else if (carried_speed_ && *carried_speed_ * dt > 1e-9) {
    scale = *carried_speed_ * dt;
    known = scale_known_;
  }
  scale_known_ = known;
  Pose3 a_b = tv.a_b;
  a_b.translation() *= scale;
  // The map kept for relocalization (relocalize_while_initializing) gives way to the new one.
  if (kept_map_) points_.clear();
  kept_map_ = false;
  auto kf0 = std::make_shared<Keyframe>();
  auto kf1 = std::make_shared<Keyframe>();
  kf0->world_camera = reference_pose_;
  kf1->world_camera = reference_pose_ * a_b;
  kf0->point_ids.assign(reference_->features.size(), -1);
  kf1->point_ids.assign(frame.features.size(), -1);
  for (size_t j = 0; j < index.size(); ++j) {
    if (!tv.triangulated[j]) continue;
    const cv::DMatch& d = m.all[index[j]];
    const int id = next_point_id_++;
    points_[id].world = reference_pose_ * (scale * tv.points_a[j]);
    points_[id].descriptor = reference_->features.descriptors.row(d.queryIdx);
    points_[id].keyframes = 2;
    points_[id].first_seen = reference_->stamp;
    points_[id].last_seen = frame.stamp;
    kf0->point_ids[d.queryIdx] = id;
    kf1->point_ids[d.trainIdx] = id;
  }
  kf0->frame = std::move(*reference_);
  kf1->frame = std::move(frame);
  reference_.reset();
  window_ = {kf0, kf1};
  num_keyframes_ += 2;
  AdjustWindow();
  map_depth_ = MedianTrackedDepth(kf1->frame, kf1->world_camera, kf1->point_ids);
  state_ = MonoState::kTracking;
  lost_frames_ = 0;
  frames_since_keyframe_ = 0;
  recent_.clear();
  prediction_error_px_.reset();
  previous_frame_.reset();
  moving_pixels_.clear();
  previous_moving_pixels_.clear();
  RememberPose(kf0->frame.stamp, kf0->world_camera);
  RememberPose(kf1->frame.stamp, kf1->world_camera);
  result->times.mapping_ms += MsSince(tm);
  result->status = Status::Ok();
  result->has_pose = true;
  result->world_camera = kf1->world_camera;
  result->initialized = true;
  result->new_keyframe = true;
  result->reference_stamp = kf0->frame.stamp;
  result->reference_world_camera = kf0->world_camera;
}

void MonoOdometry::Collect(const Frame& frame, int refs, bool robust,
                           const std::optional<Pose3>& predicted, Correspondences* c,
                           Matches* to_last, MonoFrameResult* result,
                           std::vector<std::vector<cv::DMatch>>* ratio_matches) const {
  c->keypoint_used.assign(frame.features.size(), 0);
  refs = std::min<int>(refs, static_cast<int>(window_.size()));
  for (int r = 0; r < refs; ++r) {
    const Keyframe& kf = *window_[window_.size() - 1 - r];
    const bool given = ratio_matches && static_cast<size_t>(r) < ratio_matches->size();
    Matches m = MatchFrames(kf.frame, frame, &result->times, robust, &kf, predicted,
                            given ? &(*ratio_matches)[r] : nullptr);
    if (ratio_matches && !given) ratio_matches->push_back(m.all);
    result->num_matches += m.all.size();
    for (size_t k = 0; k < m.all.size(); ++k) {
      if (!m.kept[k]) {
        const int id = kf.point_ids[m.all[k].queryIdx];
        if (robust && options_.vo.use_icgm && id >= 0) {
          c->icgm_rejected.emplace(id, m.all[k].trainIdx);
        }
        continue;
      }
      const int id = kf.point_ids[m.all[k].queryIdx];
      const int kp = m.all[k].trainIdx;
      if (id < 0 || c->keypoint_used[kp] || c->point_used.count(id)) continue;
      c->keypoint_used[kp] = 1;
      c->point_used.insert(id);
      c->points.push_back(points_.at(id).world);
      c->pixels.push_back(frame.px[kp]);
      c->point_of.push_back(id);
      c->keypoint_of.push_back(kp);
    }
    if (r == 0) *to_last = std::move(m);
  }
  for (const int id : c->point_used) c->icgm_rejected.erase(id);
  c->num_collected = c->points.size();
}

void MonoOdometry::Track(Frame frame, MonoFrameResult* result) {
  const MonoVoOptions& o = options_.vo;
  const std::optional<Pose3> predicted = PredictPose(frame.stamp, &prediction_from_wheels_);
  if (predicted && o.use_icgm && options_.icgm.motion_prior) {
    result->prior_threshold = PriorOptions().motion_prior_threshold;
  }
  PnpOptions pnp;
  pnp.reprojection_px = o.pnp_reprojection_px;
  pnp.iterations = o.pnp_iterations;
  pnp.min_inliers = o.pnp_min_inliers;
  pnp.ransac_order_seed = static_cast<uint64_t>(o.ransac_order_seed);
  // prior_from_pnp: the motion prior's prediction from a PnP pose on all ratio-test matches
  // (the constant-velocity prediction of a hand-held camera misses by the hand's jitter).
  std::optional<Pose3> prior_pose = predicted;
  std::vector<std::vector<cv::DMatch>> ratio_matches;
  if (o.prior_from_pnp && o.use_icgm && options_.icgm.motion_prior && !prediction_from_wheels_) {
    Correspondences first;
    Matches first_to_last;
    const size_t num_matches = result->num_matches;
    Collect(frame, o.track_reference_keyframes, false, predicted, &first, &first_to_last, result,
            &ratio_matches);
    result->num_matches = num_matches;
    const auto tp = Clock::now();
    const PnpResult first_pose =
        EstimatePnpPose(first.points, first.pixels, intrinsics_, pnp, predicted);
    result->times.geometry_ms += MsSince(tp);
    if (first_pose.status.ok()) prior_pose = first_pose.world_camera;
  }
  // 2D-3D correspondences from the newest keyframes, each current keypoint and map point once.
  Correspondences c;
  Matches to_last;
  Collect(frame, o.track_reference_keyframes, true, prior_pose, &c, &to_last, result,
          &ratio_matches);
  // track_icgm_baseline_frames: keypoints that moved against the room over the longer baseline.
  const std::vector<uint8_t> moving = MovingOverLongBaseline(frame, predicted, c, result);
  if (!moving.empty()) DropMovingCorrespondences(moving, &c, result);
  if (o.track_icgm_baseline_frames > 0) {
    baseline_frames_.emplace_back(std::make_unique<Frame>(frame), std::nullopt);
    while (baseline_frames_.size() > static_cast<size_t>(o.track_icgm_baseline_frames)) {
      baseline_frames_.pop_front();
    }
  }
  result->num_icgm_kept = c.points.size();
  result->robust_pixels = c.pixels;
  result->icgm_rejected_points = c.icgm_rejected.size();
  for (const auto& [id, kp] : c.icgm_rejected) {
    result->icgm_rejected_pixels.push_back(frame.px[kp]);
  }
  auto tg = Clock::now();
  PnpResult pose = TrackingPnp(c, pnp, predicted, result);
  result->times.geometry_ms += MsSince(tg);
  for (size_t k = 0; k < pose.inliers.size(); ++k) {
    if (pose.inliers[k]) result->robust_inliers.push_back(static_cast<int>(k));
  }
  // A relocalization that placed the frame replaces the tracking's matches and pose.
  const auto adopt = [&](Correspondences* found, Matches* found_to_last, PnpResult* again) {
    if (!again->status.ok()) return false;
    c = std::move(*found);
    to_last = std::move(*found_to_last);
    pose = std::move(*again);
    result->num_icgm_kept = c.points.size();
    result->relocalized = true;
    return true;
  };
  if (!pose.status.ok() && o.relocalize) {
    Correspondences all;
    Matches all_to_last;
    PnpResult again = Relocalize(frame, predicted, &all, &all_to_last, result, &ratio_matches);
    adopt(&all, &all_to_last, &again);
  }
  if (!pose.status.ok() && o.relocalize_good_keyframe_points > 0 && good_keyframe_) {
    Correspondences good;
    Matches good_to_last;
    PnpResult again = RelocalizeOnGoodKeyframe(frame, &good, &good_to_last, result);
    if (adopt(&good, &good_to_last, &again)) result->relocalized_on_good_keyframe = true;
  }
  {
    const Keyframe& newest = *window_.back();
    for (size_t k = 0; k < to_last.all.size() && k < to_last.kept.size(); ++k) {
      const bool point = newest.point_ids[to_last.all[k].queryIdx] >= 0;
      auto& px = point ? result->to_last_point_pixels : result->to_last_candidate_pixels;
      auto& kept = point ? result->to_last_point_kept : result->to_last_candidate_kept;
      if (to_last.kept[k]) kept.push_back(static_cast<int>(px.size()));
      px.push_back(frame.px[to_last.all[k].trainIdx]);
    }
  }
  std::vector<Eigen::Vector3d>& points = c.points;
  std::vector<Eigen::Vector2d>& pixels = c.pixels;
  std::vector<int>& point_of = c.point_of;
  std::vector<int>& keypoint_of = c.keypoint_of;
  result->num_inliers = pose.num_inliers;
  result->inlier_ratio =
      points.empty() ? 0.0 : static_cast<double>(pose.num_inliers) / points.size();
  // rotation_only_when_lost: a frame no PnP places, whose matches to the newest keyframe a
  // rotation explains at low parallax, is posed by it at the keyframe's position and the map
  // is kept (a walker hiding the map points seldom hides every match).
  Pose3 turned = Pose3::Identity();
  if (!pose.status.ok() && o.rotation_only_when_lost &&
      LowParallaxRotation(frame, *window_.back(), to_last, &turned, result)) {
    lost_frames_ = 0;
    state_ = MonoState::kTracking;
    ++frames_since_keyframe_;
    RememberPose(frame.stamp, turned);
    result->rotation_only = true;
    result->has_pose = true;
    result->world_camera = turned;
    return;
  }
  if (!pose.status.ok()) {
    result->status = pose.status;
    if (++lost_frames_ >= static_cast<size_t>(o.lost_frames_before_reset)) {
      Reset(result);
      // The frame that could not be tracked starts the new initialization.
      reference_ = std::make_unique<Frame>(std::move(frame));
      reference_pose_ = ReferencePose(reference_->stamp);
      frames_since_reference_ = 0;
    } else {
      state_ = MonoState::kLost;
    }
    return;
  }
  lost_frames_ = 0;
  state_ = MonoState::kTracking;
  ++frames_since_keyframe_;
  PnpResult final_pose = pose;
  if (o.projection_radius_px > 0.0 && frame.features.binary) {
    // More of the local map: its other points projected with the pose, matched by descriptor
    // near their projection; the pose is then refined on all correspondences.
    const auto tp = Clock::now();
    // Keypoints moving over the long baseline stay out of the projection search too.
    std::vector<uint8_t> taken =
        moving.empty() ? std::vector<uint8_t>(frame.features.size(), 0) : moving;
    for (size_t i = 0; i < point_of.size(); ++i) {
      if (pose.inliers[i]) taken[keypoint_of[i]] = 1;
    }
    std::vector<Eigen::Vector3d> more_points;
    std::vector<Eigen::Vector2d> more_pixels;
    std::vector<int> more_point_of, more_keypoint_of;
    for (size_t i = 0; i < point_of.size(); ++i) {
      if (!pose.inliers[i]) continue;
      more_points.push_back(points[i]);
      more_pixels.push_back(pixels[i]);
      more_point_of.push_back(point_of[i]);
      more_keypoint_of.push_back(keypoint_of[i]);
    }
    // Skipped: the points matched from the keyframes (inliers or not) and those the pose
    // keeps. After a relocalization the latter include points its projection search found
    // (not the former): each map point is matched at most once per frame.
    std::unordered_set<int> used(point_of.begin(), point_of.begin() + c.num_collected);
    if (c.num_collected < point_of.size()) {
      result->duplicate_points_skipped =
          CountDuplicates(frame, pose.world_camera, used, taken, more_point_of);
      used.insert(more_point_of.begin(), more_point_of.end());
    }
    // projection_skips_icgm_rejected (not after a relocalization, which uses every match).
    if (o.projection_skips_icgm_rejected && !result->relocalized) {
      for (const auto& rejected : c.icgm_rejected) used.insert(rejected.first);
    }
    const size_t found =
        SearchByProjection(frame, pose.world_camera, o.projection_radius_px, &used, &taken,
                           &more_points, &more_pixels, &more_point_of, &more_keypoint_of);
    if (found > 0) {
      PnpOptions refine = pnp;
      refine.ransac = false;
      PnpResult refined =
          EstimatePnpPose(more_points, more_pixels, intrinsics_, refine, pose.world_camera);
      if (refined.status.ok() && refined.num_inliers >= pose.num_inliers) {
        final_pose = std::move(refined);
        points = std::move(more_points);
        pixels = std::move(more_pixels);
        point_of = std::move(more_point_of);
        keypoint_of = std::move(more_keypoint_of);
      }
    }
    result->times.geometry_ms += MsSince(tp);
  }
  result->num_inliers = final_pose.num_inliers;
  if (predicted && !prediction_from_wheels_) {
    prediction_error_px_ = PredictionError(*predicted, points, pixels, final_pose.inliers);
  }
  const bool checks = MovingPointChecksApply();
  if (checks && o.cull_outlier_frames > 0) {
    CullMovingPoints(point_of, pixels, final_pose.inliers, result);
  }
  if (checks && o.dynamic_mask_radius_px > 0.0) {
    previous_moving_pixels_ = std::move(moving_pixels_);
    moving_pixels_.clear();
    for (size_t i = 0; i < pixels.size() && i < final_pose.inliers.size(); ++i) {
      if (!final_pose.inliers[i]) moving_pixels_.push_back(pixels[i]);
    }
    const Keyframe& newest = *window_.back();
    for (size_t k = 0; k < to_last.all.size() && k < to_last.kept.size(); ++k) {
      if (!to_last.kept[k] && newest.point_ids[to_last.all[k].queryIdx] >= 0) {
        moving_pixels_.push_back(frame.px[to_last.all[k].trainIdx]);
      }
    }
  }
  result->pose_point_ids = point_of;
  std::vector<int> tracked(frame.features.size(), -1);
  for (size_t i = 0; i < point_of.size(); ++i) {
    if (!final_pose.inliers[i]) continue;
    tracked[keypoint_of[i]] = point_of[i];
    result->tracked_pixels.push_back(pixels[i]);
    result->tracked_depths.push_back((final_pose.world_camera.inverse() * points[i]).z());
    if (!result->relocalized && c.icgm_rejected.count(point_of[i])) {
      result->icgm_rejected_readmitted_pixels.push_back(pixels[i]);
    }
  }
  const Keyframe& last = *window_.back();
  const size_t last_points = static_cast<size_t>(
      std::count_if(last.point_ids.begin(), last.point_ids.end(), [](int id) { return id >= 0; }));
  Pose3 world_camera = final_pose.world_camera;
  // A frame with far fewer features than the newest keyframe (a blurred view) tracks, but the
  // frames after it would track badly against it: it does not become a keyframe.
  const bool sharp = static_cast<double>(frame.features.size()) >=
                     o.keyframe_min_feature_ratio * last.frame.features.size();
  const bool weak = final_pose.num_inliers < o.keyframe_tracked_ratio * last_points ||
                    static_cast<int>(final_pose.num_inliers) < o.keyframe_min_tracked;
  // keyframe_min_baseline_depth_ratio: a frame tracking fewer than keyframe_min_tracked points
  // waits for parallax to the newest keyframe, unless tracking is about to fail (without wheels
  // unless moving_point_checks_with_wheels).
  bool parallax = true;
  if (o.keyframe_min_baseline_depth_ratio > 0.0 && MovingPointChecksApply() &&
      static_cast<int>(final_pose.num_inliers) < o.keyframe_min_tracked &&
      static_cast<int>(final_pose.num_inliers) >= o.keyframe_force_tracked) {
    if (const auto depth = MedianTrackedDepth(frame, world_camera, tracked)) {
      const double baseline = (last.world_camera.translation() - world_camera.translation()).norm();
      parallax = baseline >= o.keyframe_min_baseline_depth_ratio * *depth;
    }
  }
  // rotation_only_parallax_deg: a low-parallax view keeps the newest keyframe's position and
  // makes no keyframe, unless tracking is about to fail.
  const bool rotation_only =
      LowParallaxRotation(frame, last, to_last, &world_camera, result) &&
      static_cast<int>(final_pose.num_inliers) >= o.keyframe_force_tracked;
  // rotation_only_keeps_pnp_pose: the low-parallax view only holds the keyframe back.
  if (!rotation_only || o.rotation_only_keeps_pnp_pose) world_camera = final_pose.world_camera;
  result->rotation_only = rotation_only;
  const bool need_keyframe =
      !rotation_only && sharp &&
      ((weak && parallax) ||
       frames_since_keyframe_ >= static_cast<size_t>(o.keyframe_max_interval));
  if (need_keyframe) {
    const auto tm = Clock::now();
    AddKeyframe(frame, world_camera, tracked, to_last, result);
    world_camera = window_.back()->world_camera;
    result->new_keyframe = true;
    result->times.mapping_ms += MsSince(tm);
  }
  RememberPose(frame.stamp, world_camera);
  if (checks && o.new_point_confirm_px > 0.0) {
    previous_frame_ = std::make_unique<Frame>(std::move(frame));
    previous_world_camera_ = world_camera;
  }
  result->has_pose = true;
  result->world_camera = world_camera;
  if (!baseline_frames_.empty() && baseline_frames_.back().first->index == result->frame_index) {
    baseline_frames_.back().second = world_camera;
  }
}

bool MonoOdometry::LowParallaxRotation(const Frame& frame, const Keyframe& last,
                                       const Matches& to_last, Pose3* world_camera,
                                       MonoFrameResult* result) const {
  const MonoVoOptions& o = options_.vo;
  if (o.rotation_only_parallax_deg <= 0.0 || (base_to_camera_ && !wheel_.empty())) return false;
  const auto tg = Clock::now();
  std::vector<Eigen::Vector2d> pa, pb;
  for (size_t k = 0; k < to_last.all.size() && k < to_last.kept.size(); ++k) {
    if (!to_last.kept[k]) continue;
    pa.push_back(last.frame.px[to_last.all[k].queryIdx]);
    pb.push_back(frame.px[to_last.all[k].trainIdx]);
  }
  RotationOnlyOptions ro;
  ro.inlier_px = o.pnp_reprojection_px;
  ro.min_inliers = o.pnp_min_inliers;
  const RotationOnlyResult r = EstimateRotationOnly(pa, pb, intrinsics_, ro);
  // Over every match given (the median stands while the rotation's inliers are the majority).
  result->parallax_deg = MedianParallaxDeg(r.b_R_a, pa, pb, intrinsics_);
  result->times.geometry_ms += MsSince(tg);
  if (!r.status.ok() || result->parallax_deg >= o.rotation_only_parallax_deg) return false;
  // T_world_frame: the keyframe's position, its orientation turned by R_keyframe_frame.
  world_camera->linear() = last.world_camera.linear() * r.b_R_a.transpose();
  world_camera->translation() = last.world_camera.translation();
  return true;
}

bool MonoOdometry::Verified(int point_id) const {
  const MonoVoOptions& o = options_.vo;
  const auto it = points_.find(point_id);
  return it != points_.end() && it->second.keyframes >= o.pnp_verified_min_keyframes &&
         DurationSeconds(it->second.last_seen, it->second.first_seen) >= o.pnp_verified_min_span_s;
}

PnpResult MonoOdometry::TrackingPnp(const Correspondences& c, const PnpOptions& pnp,
                                    const std::optional<Pose3>& predicted,
                                    MonoFrameResult* result) const {
  const MonoVoOptions& o = options_.vo;
  PnpResult pose = EstimatePnpPose(c.points, c.pixels, intrinsics_, pnp, predicted);
  if (o.pnp_verified_min_keyframes <= 0 || !MovingPointChecksApply()) return pose;
  std::vector<uint8_t> verified(c.point_of.size(), 0);
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  for (size_t i = 0; i < c.point_of.size(); ++i) {
    if (!Verified(c.point_of[i])) continue;
    verified[i] = 1;
    result->robust_verified.push_back(static_cast<int>(i));
    points.push_back(c.points[i]);
    pixels.push_back(c.pixels[i]);
  }
  if (static_cast<int>(points.size()) < o.pnp_verified_min_points) return pose;
  const PnpResult persistent = EstimatePnpPose(points, pixels, intrinsics_, pnp, predicted);
  if (!persistent.status.ok()) return pose;
  // The persistent points' pose, refined on its inliers among all correspondences.
  PnpOptions refine = pnp;
  refine.ransac = false;
  PnpResult from_verified =
      EstimatePnpPose(c.points, c.pixels, intrinsics_, refine, persistent.world_camera);
  if (!from_verified.status.ok()) return pose;
  const auto verified_inliers = [&](const PnpResult& r) {
    size_t n = 0;
    for (size_t i = 0; i < verified.size() && i < r.inliers.size(); ++i) {
      n += verified[i] && r.inliers[i];
    }
    return n;
  };
  // The pose from all correspondences stands unless the persistent points fit the other better
  // (a walker near the camera pulled it).
  if (pose.status.ok() && verified_inliers(pose) >= verified_inliers(from_verified)) return pose;
  result->pnp_on_verified = true;
  return from_verified;
}

size_t MonoOdometry::CountDuplicates(const Frame& frame, const Pose3& world_camera,
                                     std::unordered_set<int> used, std::vector<uint8_t> taken,
                                     const std::vector<int>& matched) const {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<int> point_of, keypoint_of;
  SearchByProjection(frame, world_camera, options_.vo.projection_radius_px, &used, &taken, &points,
                     &pixels, &point_of, &keypoint_of);
  const std::unordered_set<int> already(matched.begin(), matched.end());
  return static_cast<size_t>(std::count_if(point_of.begin(), point_of.end(),
                                           [&](int id) { return already.count(id) > 0; }));
}

PnpResult MonoOdometry::Relocalize(const Frame& frame, const std::optional<Pose3>& predicted,
                                   Correspondences* c, Matches* to_last,
                                   MonoFrameResult* result,
                                   std::vector<std::vector<cv::DMatch>>* ratio_matches) const {
  // Before giving up on a frame: the newest relocalize_keyframes keyframes, every ratio-test
  // match (the PnP RANSAC is the only filter), more RANSAC iterations.
  const MonoVoOptions& o = options_.vo;
  Collect(frame, o.relocalize_keyframes, false, predicted, c, to_last, result, ratio_matches);
  const auto tg = Clock::now();
  // A blurred frame keeps few ratio-test matches: the local map's points projected with the
  // predicted pose are matched within relocalize_radius_px as well.
  if (predicted && o.relocalize_radius_px > 0.0 && frame.features.binary) {
    SearchByProjection(frame, *predicted, o.relocalize_radius_px, &c->point_used, &c->keypoint_used,
                       &c->points, &c->pixels, &c->point_of, &c->keypoint_of);
  }
  PnpOptions wide;
  wide.reprojection_px = o.pnp_reprojection_px;
  wide.iterations = std::max(o.pnp_iterations, o.relocalize_pnp_iterations);
  wide.min_inliers = o.pnp_min_inliers;
  wide.ransac_order_seed = static_cast<uint64_t>(o.ransac_order_seed);
  PnpResult pose = EstimatePnpPose(c->points, c->pixels, intrinsics_, wide, predicted);
  result->times.geometry_ms += MsSince(tg);
  return pose;
}

PnpResult MonoOdometry::RelocalizeOnGoodKeyframe(const Frame& frame, Correspondences* c,
                                                 Matches* to_last,
                                                 MonoFrameResult* result) const {
  const MonoVoOptions& o = options_.vo;
  const Keyframe& kf = *good_keyframe_;
  PnpResult failed;
  failed.status = Status::Error("last good keyframe: no motion");
  // ICGM's consistent set between the last good keyframe and this frame (every ratio-test
  // match without ICGM) gives the essential matrix and the motion's direction.
  const Matches m = MatchFrames(kf.frame, frame, &result->times, true);
  if (static_cast<int>(m.num_kept) < o.init_min_matches) return failed;
  const auto tg = Clock::now();
  std::vector<Eigen::Vector2d> pa, pb;
  std::vector<int> point;  // the keyframe's map point of each kept match (-1 none)
  for (size_t k = 0; k < m.all.size(); ++k) {
    if (!m.kept[k]) continue;
    pa.push_back(kf.frame.px[m.all[k].queryIdx]);
    pb.push_back(frame.px[m.all[k].trainIdx]);
    point.push_back(kf.point_ids[m.all[k].queryIdx]);
  }
  TwoViewOptions tv_options = TwoViewOptionsFrom(o);
  tv_options.refine = false;
  const TwoViewResult tv = RecoverTwoViewMotion(pa, pb, intrinsics_, tv_options);
  result->times.geometry_ms += MsSince(tg);
  if (!tv.status.ok()) return failed;
  // The translation's length from the keyframe's map points the two views triangulate: their
  // depth in the keyframe over the unit-baseline depth. Too few: the rotation alone.
  const Pose3 camera_world = kf.world_camera.inverse();
  std::vector<double> ratio;
  for (size_t j = 0; j < point.size(); ++j) {
    if (point[j] < 0 || !tv.triangulated[j]) continue;
    const auto now = points_.find(point[j]);
    const auto then = good_points_.find(point[j]);
    if (now == points_.end() && then == good_points_.end()) continue;
    const double z =
        (camera_world * (now != points_.end() ? now->second.world : then->second)).z();
    if (z > 0.0 && tv.points_a[j].z() > 1e-9) ratio.push_back(z / tv.points_a[j].z());
  }
  Pose3 a_b = tv.a_b;
  if (ratio.size() >= 5) {
    std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
    a_b.translation() *= ratio[ratio.size() / 2];
  } else {
    a_b.translation().setZero();
  }
  // The local map projected with that pose, PnP RANSAC on all it finds.
  return Relocalize(frame, kf.world_camera * a_b, c, to_last, result);
}

size_t MonoOdometry::SearchByProjection(const Frame& frame, const Pose3& world_camera,
                                        double radius_px, std::unordered_set<int>* used,
                                        std::vector<uint8_t>* taken,
                                        std::vector<Eigen::Vector3d>* points,
                                        std::vector<Eigen::Vector2d>* pixels,
                                        std::vector<int>* point_of,
                                        std::vector<int>* keypoint_of) const {
  const MonoVoOptions& o = options_.vo;
  const double cell = std::max(4.0, radius_px);
  const int cols = static_cast<int>(std::ceil(intrinsics_.width_px / cell)) + 1;
  const int rows = static_cast<int>(std::ceil(intrinsics_.height_px / cell)) + 1;
  std::vector<std::vector<int>> grid(static_cast<size_t>(cols * rows));
  const auto cell_of = [&](double u, double v, int* cx, int* cy) {
    *cx = static_cast<int>(std::floor(u / cell));
    *cy = static_cast<int>(std::floor(v / cell));
    return *cx >= 0 && *cy >= 0 && *cx < cols && *cy < rows;
  };
  for (size_t k = 0; k < frame.px.size(); ++k) {
    int cx, cy;
    if (!(*taken)[k] && cell_of(frame.px[k].x(), frame.px[k].y(), &cx, &cy)) {
      grid[cy * cols + cx].push_back(static_cast<int>(k));
    }
  }
  const Pose3 camera_world = world_camera.inverse();
  size_t found = 0;
  for (const auto& [id, point] : points_) {
    if (used->count(id) || point.descriptor.empty()) continue;
    const Eigen::Vector3d c = camera_world * point.world;
    if (c.z() <= 1e-6) continue;
    const Eigen::Vector2d uv = intrinsics_.Project(c);
    int cx, cy;
    if (!cell_of(uv.x(), uv.y(), &cx, &cy)) continue;
    int best = -1;
    double best_d = 1e9, second_d = 1e9;
    for (int y = cy - 1; y <= cy + 1; ++y) {
      for (int x = cx - 1; x <= cx + 1; ++x) {
        if (x < 0 || y < 0 || x >= cols || y >= rows) continue;
        for (const int k : grid[y * cols + x]) {
          if ((*taken)[k] || (frame.px[k] - uv).norm() > radius_px) continue;
          const double d = cv::hal::normHamming(point.descriptor.ptr<uchar>(),
                                                frame.features.descriptors.ptr<uchar>(k),
                                                frame.features.descriptors.cols);
          if (d < best_d) {
            second_d = best_d;
            best_d = d;
            best = k;
          } else if (d < second_d) {
            second_d = d;
          }
        }
      }
    }
    if (best < 0 || best_d > o.projection_max_hamming ||
        best_d > options_.matcher.ratio * second_d) {
      continue;
    }
    (*taken)[best] = 1;
    used->insert(id);
    points->push_back(point.world);
    pixels->push_back(frame.px[best]);
    point_of->push_back(id);
    keypoint_of->push_back(best);
    ++found;
  }
  return found;
}

void MonoOdometry::AddKeyframe(const Frame& frame, const Pose3& world_camera,
                               const std::vector<int>& tracked_point, const Matches& to_last,
                               MonoFrameResult* result) {
  const MonoVoOptions& o = options_.vo;
  auto kf = std::make_shared<Keyframe>();
  kf->frame = frame;
  kf->world_camera = world_camera;
  kf->point_ids = tracked_point;
  // The tracked points (inliers of this pose) are seen in place by one more keyframe.
  for (const int id : tracked_point) {
    const auto it = id >= 0 ? points_.find(id) : points_.end();
    if (it == points_.end()) continue;
    ++it->second.keyframes;
    it->second.last_seen = frame.stamp;
  }
  TriangulationCheck check;
  check.max_reprojection_px = o.max_reprojection_px;
  check.min_angle_deg = o.min_triangulation_deg;
  check.max_depth_baselines = o.max_depth_baselines;
  // new_point_expected_parallax: the angle is checked at the tracked points' depth instead.
  const std::optional<double> expected_depth =
      o.new_point_expected_parallax && (!base_to_camera_ || wheel_.empty())
          ? MedianTrackedDepth(frame, world_camera, tracked_point)
          : std::nullopt;
  if (expected_depth) {
    check.min_angle_deg = o.new_point_min_measured_deg;
    check.max_depth_baselines = 0.0;
  }
  // The keyframe the new points are triangulated with: the previous one, or an older one with
  // enough parallax (new_point_min_baseline_depth_ratio), matched for the purpose.
  // new_point_extra_keyframes: then with older local-map keyframes far enough away.
  std::vector<size_t> references = {NewPointReference(frame, world_camera, tracked_point)};
  for (const size_t i :
       ExtraNewPointReferences(frame, world_camera, tracked_point, references[0])) {
    references.push_back(i);
  }
  for (const size_t ref_index : references) {
    const bool extra = ref_index != references.front();
    Keyframe& last = *window_[ref_index];
    const bool older = ref_index + 1 != window_.size();
    Matches older_matches;
    if (older) {
      older_matches = MatchFrames(last.frame, frame, &result->times, true, &last, world_camera);
    }
    const Matches& pairs = older ? older_matches : to_last;
    // New points from the ICGM-kept matches to that keyframe that carry none yet.
    const std::vector<uint8_t> candidate =
        NewPointCandidates(last, frame, world_camera, tracked_point, pairs);
    // Candidates that the longer baseline shows moving (new_point_icgm_baseline_keyframes).
    const std::vector<uint8_t> moving =
        older || extra ? std::vector<uint8_t>()
                       : OutsideLongBaselineGroup(frame, tracked_point, to_last);
    // Earlier views that did not make the new points (new_point_confirm_px): the frame tracked
    // before this one, the keyframes between the reference and this frame (at most two, newest
    // first) and the keyframe before the reference.
    std::vector<std::pair<const Frame*, Pose3>> views;
    if (o.new_point_confirm_px > 0.0 && frame.features.binary && MovingPointChecksApply()) {
      if (previous_frame_ && previous_frame_->index != last.frame.index) {
        views.emplace_back(previous_frame_.get(), previous_world_camera_);
      }
      for (size_t i = window_.size() - 1, n = 0; older && i > ref_index && n < 2; --i, ++n) {
        const Keyframe& between = *window_[i];
        if (previous_frame_ && previous_frame_->index == between.frame.index) continue;
        views.emplace_back(&between.frame, between.world_camera);
      }
      if (ref_index >= 1) {
        const Keyframe& before = *window_[ref_index - 1];
        views.emplace_back(&before.frame, before.world_camera);
      }
    }
    const bool mask = o.dynamic_mask_radius_px > 0.0 && MovingPointChecksApply();
    for (size_t k = 0; k < pairs.all.size(); ++k) {
      if (!candidate[k]) continue;
      const int q = pairs.all[k].queryIdx, t = pairs.all[k].trainIdx;
      if (last.point_ids[q] >= 0 || kf->point_ids[t] >= 0) continue;
      if (expected_depth && ExpectedParallaxDeg(intrinsics_, last.world_camera, world_camera,
                                                frame.px[t], *expected_depth) <
                                o.min_triangulation_deg) {
        continue;
      }
      const TriangulatedPoint p = TriangulatePoint(intrinsics_, last.world_camera, last.frame.px[q],
                                                   world_camera, frame.px[t], check);
      if (!p.status.ok()) continue;
      if (((!moving.empty() && moving[k]) || (mask && InMovingRegion(frame.px[t]))) ||
          (!views.empty() &&
           !SeenInEarlierView(p.point_world, frame.features.descriptors.row(t), views))) {
        ++result->rejected_new_points;
        result->rejected_new_point_pixels.push_back(frame.px[t]);
        continue;
      }
      const int id = next_point_id_++;
      points_[id].world = p.point_world;
      points_[id].descriptor = last.frame.features.descriptors.row(q);
      points_[id].keyframes = 2;
      points_[id].first_seen = last.frame.stamp;
      points_[id].last_seen = frame.stamp;
      last.point_ids[q] = id;
      kf->point_ids[t] = id;
      result->new_point_pixels.push_back(frame.px[t]);
      if (extra) ++result->extra_new_points;
    }
  }
  window_.push_back(kf);
  if (o.relocalize_good_keyframe_points > 0 &&
      std::count_if(kf->point_ids.begin(), kf->point_ids.end(), [](int id) { return id >= 0; }) >=
          o.relocalize_good_keyframe_points) {
    good_keyframe_ = kf;
    good_points_.clear();
    for (const int id : kf->point_ids) {
      const auto it = id >= 0 ? points_.find(id) : points_.end();
      if (it != points_.end()) good_points_.emplace(id, it->second.world);
    }
  }
  ++num_keyframes_;
  frames_since_keyframe_ = 0;
  ApplyWheelScale();
  AdjustWindow();
  result->scene_depth_scale = HoldSceneDepth(tracked_point);
  DropOldKeyframes();
}

std::optional<double> MonoOdometry::MedianTrackedDepth(
    const Frame& frame, const Pose3& world_camera, const std::vector<int>& tracked_point) const {
  const Pose3 camera_world = world_camera.inverse();
  std::vector<double> depths;
  for (size_t kp = 0; kp < tracked_point.size() && kp < frame.px.size(); ++kp) {
    if (tracked_point[kp] < 0) continue;
    const auto it = points_.find(tracked_point[kp]);
    if (it == points_.end()) continue;
    const double z = (camera_world * it->second.world).z();
    if (z > 1e-9) depths.push_back(z);
  }
  if (depths.size() < 10) return std::nullopt;
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  return depths[depths.size() / 2];
}

std::vector<size_t> MonoOdometry::ExtraNewPointReferences(const Frame& frame,
                                                          const Pose3& world_camera,
                                                          const std::vector<int>& tracked_point,
                                                          size_t first) const {
  const MonoVoOptions& o = options_.vo;
  std::vector<size_t> extra;
  if (o.new_point_extra_keyframes <= 0 || window_.size() < 2) return extra;
  const std::optional<double> depth = MedianTrackedDepth(frame, world_camera, tracked_point);
  if (!depth) return extra;
  const double needed = o.new_point_extra_min_baseline_depth_ratio * *depth;
  // Newest first, among the keyframes older than the first reference, those far enough away.
  for (size_t i = std::min(first, window_.size() - 1); i-- > 0;) {
    if (static_cast<int>(extra.size()) >= o.new_point_extra_keyframes) break;
    const double baseline =
        (window_[i]->world_camera.translation() - world_camera.translation()).norm();
    if (baseline >= needed) extra.push_back(i);
  }
  return extra;
}

size_t MonoOdometry::NewPointReference(const Frame& frame, const Pose3& world_camera,
                                       const std::vector<int>& tracked_point) const {
  const size_t newest = window_.size() - 1;
  const double ratio = options_.vo.new_point_min_baseline_depth_ratio;
  if (ratio <= 0.0 || window_.size() < 2 || !MovingPointChecksApply()) return newest;
  const std::optional<double> depth = MedianTrackedDepth(frame, world_camera, tracked_point);
  if (!depth) return newest;
  const double needed = ratio * *depth;
  size_t farthest = newest;
  double farthest_m = -1.0;
  for (size_t i = newest + 1; i-- > 0;) {
    const double baseline =
        (window_[i]->world_camera.translation() - world_camera.translation()).norm();
    if (baseline >= needed) return i;
    if (baseline > farthest_m) {
      farthest_m = baseline;
      farthest = i;
    }
  }
  return farthest;
}

std::optional<std::vector<uint8_t>> MonoOdometry::PriorCandidates(const Keyframe& last,
                                                                  const Frame& frame,
                                                                  const Pose3& world_camera,
                                                                  const Matches& to_last) const {
  // The keyframe's map points: pixel and depth in it.
  const Pose3 last_camera_world = last.world_camera.inverse();
  std::vector<std::pair<Eigen::Vector2d, double>> known;
  for (size_t kp = 0; kp < last.point_ids.size(); ++kp) {
    const int id = last.point_ids[kp];
    if (id < 0) continue;
    const double z = (last_camera_world * points_.at(id).world).z();
    if (z > 1e-6) known.emplace_back(last.frame.px[kp], z);
  }
  if (known.size() < 3) return std::nullopt;
  const auto median = [](std::vector<double>* v) {
    std::nth_element(v->begin(), v->begin() + v->size() / 2, v->end());
    return (*v)[v->size() / 2];
  };
  std::vector<double> depths;
  for (const auto& k : known) depths.push_back(k.second);
  const double all_median = median(&depths);
  const double r2 = options_.vo.new_point_prior_radius_px * options_.vo.new_point_prior_radius_px;
  // Where each keyframe keypoint would be in this frame if static: its map point, or the
  // median depth of the map points near it (with a hand-held baseline a wrong depth moves the
  // prediction by little, a walker's own motion by much more).
  const Pose3 camera_world = world_camera.inverse();
  std::vector<Eigen::Vector2d> pa, pb;
  std::vector<Eigen::Vector2d> expected(to_last.all.size(),
                                        Eigen::Vector2d::Constant(std::nan("")));
  for (size_t k = 0; k < to_last.all.size(); ++k) {
    const int q = to_last.all[k].queryIdx;
    const Eigen::Vector2d& a = last.frame.px[q];
    pa.push_back(a);
    pb.push_back(frame.px[to_last.all[k].trainIdx]);
    Eigen::Vector3d world;
    if (const int id = last.point_ids[q]; id >= 0) {
      world = points_.at(id).world;
    } else {
      depths.clear();
      for (const auto& [px, z] : known) {
        if ((px - a).squaredNorm() <= r2) depths.push_back(z);
      }
      const double z = depths.size() >= 3 ? median(&depths) : all_median;
      world = last.world_camera * intrinsics_.BackProject(a.x(), a.y(), z);
    }
    const Eigen::Vector3d c = camera_world * world;
    if (c.z() > 1e-6) expected[k] = intrinsics_.Project(c);
  }
  const IcgmResult r = RunIcgm(pa, pb, PriorOptions(), &expected);
  if (!r.status.ok()) return std::nullopt;
  return r.kept;
}

std::vector<uint8_t> MonoOdometry::NewPointCandidates(const Keyframe& last, const Frame& frame,
                                                      const Pose3& world_camera,
                                                      const std::vector<int>& tracked_point,
                                                      const Matches& to_last) const {
  if (!options_.vo.use_icgm) return to_last.kept;
  if (options_.vo.new_points_from_prior && !options_.vo.new_points_from_map_group) {
    return PriorCandidates(last, frame, world_camera, to_last).value_or(to_last.kept);
  }
  if (!options_.vo.new_points_from_map_group) return to_last.kept;
  // Anchors: matches whose keyframe map point this frame tracked as a PnP inlier.
  std::vector<Eigen::Vector2d> pa, pb;
  std::vector<int> anchors;
  for (size_t k = 0; k < to_last.all.size(); ++k) {
    const int q = to_last.all[k].queryIdx, t = to_last.all[k].trainIdx;
    pa.push_back(last.frame.px[q]);
    pb.push_back(frame.px[t]);
    if (last.point_ids[q] >= 0 && tracked_point[t] == last.point_ids[q]) {
      anchors.push_back(static_cast<int>(k));
    }
  }
  if (anchors.size() < 2) return to_last.kept;
  std::vector<uint8_t> group =
      AnchoredIcgmGroup(pa, pb, anchors, options_.icgm.seed_pairs, options_.icgm.threshold);
  return group.empty() ? to_last.kept : group;
}

std::vector<uint8_t> MonoOdometry::OutsideLongBaselineGroup(const Frame& frame,
                                                            const std::vector<int>& tracked_point,
                                                            const Matches& to_last) const {
  const size_t back = static_cast<size_t>(options_.vo.new_point_icgm_baseline_keyframes);
  if (!options_.vo.use_icgm || back == 0 || window_.size() <= back || !MovingPointChecksApply()) {
    return {};
  }
  const Keyframe& old = *window_[window_.size() - 1 - back];
  const std::vector<cv::DMatch> matches = matcher_.Match(old.frame.features, frame.features);
  std::vector<Eigen::Vector2d> pa, pb;
  std::vector<int> anchors;
  for (size_t k = 0; k < matches.size(); ++k) {
    const int q = matches[k].queryIdx, t = matches[k].trainIdx;
    pa.push_back(old.frame.px[q]);
    pb.push_back(frame.px[t]);
    if (old.point_ids[q] >= 0 && tracked_point[t] == old.point_ids[q]) {
      anchors.push_back(static_cast<int>(k));
    }
  }
  if (anchors.size() < 2) return {};
  const std::vector<uint8_t> group =
      AnchoredIcgmGroup(pa, pb, anchors, options_.icgm.seed_pairs, options_.icgm.threshold);
  if (group.empty()) return {};
  // Keypoints of this frame the older keyframe matched outside the group; the others (not
  // matched from it: newly seen, or changed too much) stay candidates.
  std::vector<uint8_t> outside_at(frame.features.size(), 0);
  for (size_t k = 0; k < matches.size(); ++k) outside_at[matches[k].trainIdx] = !group[k];
  std::vector<uint8_t> outside(to_last.all.size(), 0);
  for (size_t k = 0; k < to_last.all.size(); ++k) outside[k] = outside_at[to_last.all[k].trainIdx];
  return outside;
}

std::vector<uint8_t> MonoOdometry::MovingOverLongBaseline(const Frame& frame,
                                                          const std::optional<Pose3>& predicted,
                                                          const Correspondences& c,
                                                          MonoFrameResult* result) const {
  const MonoVoOptions& o = options_.vo;
  const size_t back = static_cast<size_t>(o.track_icgm_baseline_frames);
  if (!o.use_icgm || back == 0 || baseline_frames_.empty() || !MovingPointChecksApply()) {
    return {};
  }
  // The oldest buffered frame, at most `back` and at least half as many frames before this one.
  const Frame* old = nullptr;
  std::optional<Pose3> old_pose;
  for (const auto& [f, pose] : baseline_frames_) {
    const size_t gap = frame.index - f->index;
    if (gap <= back && 2 * gap >= back) {
      old = f.get();
      old_pose = pose;
      break;
    }
  }
  if (!old) return {};
  const double max_ratio = o.track_icgm_baseline_max_translation_depth_ratio;
  if (max_ratio > 0.0 && old_pose && predicted) {
    std::vector<int> tracked(frame.features.size(), -1);
    for (size_t i = 0; i < c.point_of.size(); ++i) tracked[c.keypoint_of[i]] = c.point_of[i];
    const std::optional<double> depth = MedianTrackedDepth(frame, *predicted, tracked);
    const double moved = (old_pose->translation() - predicted->translation()).norm();
    if (depth && moved > max_ratio * *depth) {
      result->long_baseline_gated = true;
      return {};
    }
  }
  const auto t0 = Clock::now();
  const std::vector<cv::DMatch> matches = matcher_.Match(old->features, frame.features);
  result->times.matching_ms += MsSince(t0);
  const auto t1 = Clock::now();
  std::vector<Eigen::Vector2d> pa, pb;
  pa.reserve(matches.size());
  pb.reserve(matches.size());
  for (const cv::DMatch& d : matches) {
    pa.push_back(old->px[d.queryIdx]);
    pb.push_back(frame.px[d.trainIdx]);
  }
  // Rotation prior: where each older keypoint appears after the rotation alone (a point at
  // infinity).
  const bool prior = o.track_icgm_baseline_rotation_prior && old_pose && predicted;
  std::vector<Eigen::Vector2d> expected;
  if (prior) {
    const Eigen::Matrix3d turn = predicted->rotation().transpose() * old_pose->rotation();
    expected.resize(pa.size());
    for (size_t k = 0; k < pa.size(); ++k) {
      const Eigen::Vector3d ray((pa[k].x() - intrinsics_.cx_px) / intrinsics_.fx_px,
                                (pa[k].y() - intrinsics_.cy_px) / intrinsics_.fy_px, 1.0);
      const Eigen::Vector3d r = turn * ray;
      expected[k] = r.z() > 1e-6 ? intrinsics_.Project(r) : Eigen::Vector2d::Constant(std::nan(""));
    }
  }
  IcgmOptions icgm = prior ? PriorOptions() : options_.icgm;
  icgm.motion_prior = prior;
  const IcgmResult r = RunIcgm(pa, pb, icgm, prior ? &expected : nullptr);
  result->times.icgm_ms += MsSince(t1);
  if (!r.status.ok()) return {};
  const std::vector<uint8_t>& group = r.kept;
  std::vector<uint8_t> moving(frame.features.size(), 0);
  for (size_t k = 0; k < matches.size(); ++k) {
    if (group[k]) result->long_baseline_kept.push_back(static_cast<int>(k));
    moving[matches[k].trainIdx] = !group[k];
  }
  result->long_baseline_pixels = std::move(pb);
  return moving;
}

void MonoOdometry::DropMovingCorrespondences(const std::vector<uint8_t>& moving, Correspondences* c,
                                             MonoFrameResult* result) {
  size_t n = 0, collected = 0;
  for (size_t i = 0; i < c->points.size(); ++i) {
    const int kp = c->keypoint_of[i];
    if (moving[kp]) {
      result->long_baseline_dropped_pixels.push_back(c->pixels[i]);
      c->keypoint_used[kp] = 0;
      c->point_used.erase(c->point_of[i]);
      continue;
    }
    c->points[n] = c->points[i];
    c->pixels[n] = c->pixels[i];
    c->point_of[n] = c->point_of[i];
    c->keypoint_of[n] = kp;
    collected += i < c->num_collected;
    ++n;
  }
  c->points.resize(n);
  c->pixels.resize(n);
  c->point_of.resize(n);
  c->keypoint_of.resize(n);
  c->num_collected = collected;
}

bool MonoOdometry::MovingPointChecksApply() const {
  return options_.vo.moving_point_checks_with_wheels || !base_to_camera_ || wheel_.empty();
}

bool MonoOdometry::InMovingRegion(const Eigen::Vector2d& px) const {
  const double r2 = options_.vo.dynamic_mask_radius_px * options_.vo.dynamic_mask_radius_px;
  int votes = 0;
  for (const auto* list : {&moving_pixels_, &previous_moving_pixels_}) {
    for (const Eigen::Vector2d& m : *list) {
      if ((m - px).squaredNorm() <= r2 && ++votes >= options_.vo.dynamic_mask_min_votes) {
        return true;
      }
    }
  }
  return false;
}

bool MonoOdometry::SeenInEarlierView(
    const Eigen::Vector3d& world, const cv::Mat& descriptor,
    const std::vector<std::pair<const Frame*, Pose3>>& views) const {
  const double radius = options_.vo.new_point_confirm_px;
  const double contradiction = options_.vo.new_point_contradiction_px;
  // new_point_contradiction_px: search the wider radius for the most similar keypoint.
  const double search = std::max(radius, contradiction);
  bool in_view = false, contradicted = false;
  for (const auto& [view, world_camera] : views) {
    const Eigen::Vector3d c = world_camera.inverse() * world;
    if (c.z() <= 1e-6) continue;
    const Eigen::Vector2d uv = intrinsics_.Project(c);
    if (uv.x() < 0 || uv.y() < 0 || uv.x() >= intrinsics_.width_px ||
        uv.y() >= intrinsics_.height_px) {
      continue;
    }
    in_view = true;
    double best = std::numeric_limits<double>::infinity(), best_px = 0.0;
    for (size_t k = 0; k < view->px.size(); ++k) {
      const double d2 = (view->px[k] - uv).squaredNorm();
      if (d2 > search * search) continue;
      const double d =
          cv::hal::normHamming(descriptor.ptr<uchar>(), view->features.descriptors.ptr<uchar>(k),
                               view->features.descriptors.cols);
      if (d > options_.vo.projection_max_hamming) continue;
      if (contradiction <= 0.0 && d2 <= radius * radius) return true;
      if (d < best || (d == best && d2 < best_px * best_px)) {
        best = d;
        best_px = std::sqrt(d2);
      }
    }
    if (contradiction > 0.0 && std::isfinite(best)) {
      if (best_px <= radius) return true;
      contradicted = true;
    }
  }
  if (contradiction > 0.0) return !contradicted;
  return !in_view;
}

void MonoOdometry::CullMovingPoints(const std::vector<int>& point_of,
                                    const std::vector<Eigen::Vector2d>& pixels,
                                    const std::vector<uint8_t>& inlier, MonoFrameResult* result) {
  std::unordered_set<int> culled;
  for (size_t i = 0; i < point_of.size() && i < inlier.size(); ++i) {
    const auto it = points_.find(point_of[i]);
    if (it == points_.end()) continue;
    if (inlier[i]) {
      it->second.outlier_frames = 0;
    } else if (++it->second.outlier_frames >= options_.vo.cull_outlier_frames) {
      if (culled.insert(point_of[i]).second) result->culled_pixels.push_back(pixels[i]);
    }
  }
  if (culled.empty()) return;
  for (auto& kf : window_) {
    for (int& id : kf->point_ids) {
      if (id >= 0 && culled.count(id)) id = -1;
    }
  }
  for (const int id : culled) points_.erase(id);
  result->culled_points = culled.size();
}

void MonoOdometry::ApplyWheelScale() {
  const double gain = options_.vo.wheel_scale_gain;
  if (gain <= 0.0 || window_.size() < 2) return;
  const Keyframe& first = *window_.front();
  const Keyframe& newest = *window_.back();
  const auto wheel = WheelDistance(first.frame.stamp, newest.frame.stamp);
  const double visual =
      (newest.world_camera.translation() - first.world_camera.translation()).norm();
  if (!wheel || *wheel < options_.vo.wheel_min_baseline_m || !(visual > 1e-9)) return;
  const double f = 1.0 + gain * (*wheel / visual - 1.0);
  // Scaled about the newest keyframe: the poses already given out stay where they are.
  ScaleLocalMap(newest.world_camera.translation(), f);
  scale_known_ = true;
}

void MonoOdometry::ScaleLocalMap(const Eigen::Vector3d& centre, double f) {
  const auto scaled = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    return centre + f * (x - centre);
  };
  for (auto& k : window_) k->world_camera.translation() = scaled(k->world_camera.translation());
  for (auto& [id, p] : points_) p.world = scaled(p.world);
  for (auto& [stamp, pose] : recent_) pose.translation() = scaled(pose.translation());
  if (previous_frame_) {
    previous_world_camera_.translation() = scaled(previous_world_camera_.translation());
  }
}

double MonoOdometry::HoldSceneDepth(const std::vector<int>& tracked_point) {
  const double band = options_.vo.scene_depth_band;
  if (band <= 0.0 || scale_known_ || !map_depth_ || window_.empty()) return 1.0;
  const Keyframe& newest = *window_.back();
  const std::optional<double> depth =
      MedianTrackedDepth(newest.frame, newest.world_camera, tracked_point);
  if (!depth) return 1.0;
  const double low = *map_depth_ / band, high = *map_depth_ * band;
  if (*depth >= low && *depth <= high) return 1.0;
  const double f = (*depth < low ? low : high) / *depth;
  ScaleLocalMap(newest.world_camera.translation(), f);
  return f;
}

void MonoOdometry::AdjustWindow() {
  const BundleAdjustmentOptions& ba = options_.bundle_adjustment;
  const int window = options_.vo.ba_window_keyframes;
  if (window <= 0 || window_.size() < 2) return;
  const size_t n = std::min<size_t>(window, window_.size());
  const size_t first = window_.size() - n;
  BaProblem problem;
  std::unordered_map<int, int> point_index;
  std::vector<int> point_ids;
  struct ObservationRef {
    size_t keyframe;
    int keypoint;
  };
  std::vector<ObservationRef> refs;
  const size_t fixed = std::min<size_t>(options_.vo.ba_fixed_keyframes, n);
  const auto add_observation = [&](size_t camera, size_t keyframe, size_t kp, int point) {
    const Keyframe& kf = *window_[keyframe];
    BaObservation obs;
    obs.camera = static_cast<int>(camera);
    obs.point = point;
    obs.pixel_px = kf.frame.px[kp];
    obs.pixel_sigma_px =
        PyramidPixelSigma(kf.frame.features.keypoints[kp], options_.features.orb_scale_factor);
    problem.observations.push_back(obs);
    refs.push_back({keyframe, static_cast<int>(kp)});
  };
  for (size_t c = 0; c < n; ++c) {
    const Keyframe& kf = *window_[first + c];
    problem.world_camera.push_back(kf.world_camera);
    problem.fixed.push_back(c < fixed ? 1 : 0);
    for (size_t kp = 0; kp < kf.point_ids.size(); ++kp) {
      const int id = kf.point_ids[kp];
      if (id < 0) continue;
      auto it = point_index.find(id);
      if (it == point_index.end()) {
        it = point_index.emplace(id, static_cast<int>(problem.points_world.size())).first;
        problem.points_world.push_back(points_.at(id).world);
        point_ids.push_back(id);
      }
      add_observation(c, first + c, kp, it->second);
    }
  }
  // Older keyframes of the local map that see the window's points join as fixed cameras: their
  // observations tie the points, and with them the scale, to the older map.
  if (options_.vo.ba_covisible_fixed) {
    for (size_t k = 0; k < first; ++k) {
      const Keyframe& kf = *window_[k];
      const size_t camera = problem.world_camera.size();
      bool sees = false;
      for (size_t kp = 0; kp < kf.point_ids.size(); ++kp) {
        const auto it =
            kf.point_ids[kp] < 0 ? point_index.end() : point_index.find(kf.point_ids[kp]);
        if (it == point_index.end()) continue;
        if (!sees) {
          problem.world_camera.push_back(kf.world_camera);
          problem.fixed.push_back(1);
          sees = true;
        }
        add_observation(camera, k, kp, it->second);
      }
    }
  }
  if (problem.observations.empty()) return;
  std::vector<uint8_t> inlier;
  BaSummary summary;
  if (!BundleAdjust(intrinsics_, ba, &problem, &summary, &inlier).ok()) return;
  for (size_t c = 0; c < n; ++c) window_[first + c]->world_camera = problem.world_camera[c];
  for (size_t i = 0; i < point_ids.size(); ++i)
    points_[point_ids[i]].world = problem.points_world[i];
  for (size_t k = 0; k < refs.size() && k < inlier.size(); ++k) {
    if (inlier[k]) continue;
    int& id = window_[refs[k].keyframe]->point_ids[refs[k].keypoint];
    if (const auto it = points_.find(id); it != points_.end()) --it->second.keyframes;
    id = -1;
  }
}

void MonoOdometry::DropOldKeyframes() {
  const size_t keep = static_cast<size_t>(
      std::max({options_.vo.local_map_keyframes, options_.vo.ba_window_keyframes,
                options_.vo.track_reference_keyframes, 2}));
  if (window_.size() <= keep) return;
  while (window_.size() > keep) window_.pop_front();
  std::unordered_set<int> seen;
  for (const auto& kf : window_) {
    for (const int id : kf->point_ids) {
      if (id >= 0) seen.insert(id);
    }
  }
  for (auto it = points_.begin(); it != points_.end();) {
    it = seen.count(it->first) ? std::next(it) : points_.erase(it);
  }
}

void MonoOdometry::Reset(MonoFrameResult* result) {
  if (options_.vo.carry_scale_over_reset && recent_.size() >= 2) {
    const double dt = DurationSeconds(recent_.back().first, recent_.front().first);
    if (dt > 1e-6) {
      carried_speed_ =
          (recent_.back().second.translation() - recent_.front().second.translation()).norm() / dt;
    }
  }
  bridge_.clear();
  if (recent_.size() >= 2) bridge_ = recent_;
  good_keyframe_.reset();
  good_points_.clear();
  // relocalize_while_initializing: the map stays until a new one is initialized.
  kept_map_ = options_.vo.relocalize_while_initializing && !window_.empty();
  if (!kept_map_) {
    window_.clear();
    points_.clear();
  }
  recent_.clear();
  prediction_error_px_.reset();
  previous_frame_.reset();
  moving_pixels_.clear();
  previous_moving_pixels_.clear();
  reference_.reset();
  lost_frames_ = 0;
  state_ = MonoState::kInitializing;
  ++num_resets_;
  result->reset = true;
}

Pose3 MonoOdometry::ReferencePose(Time stamp) const {
  const Pose3 last = last_pose_.value_or(Pose3::Identity());
  const double max_s = options_.vo.reset_bridge_max_s;
  if (!(max_s > 0.0) || bridge_.size() < 2 || !last_pose_) return last;
  const auto& [t0, p0] = bridge_.front();
  const auto& [t1, p1] = bridge_.back();
  const double dt_last = DurationSeconds(t1, t0);
  if (!(dt_last > 1e-6)) return last;
  return CarryOn(p0, p1, std::clamp(DurationSeconds(stamp, t1), 0.0, max_s) / dt_last);
}

}  // namespace icgm
