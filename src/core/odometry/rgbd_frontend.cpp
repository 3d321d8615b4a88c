#include "core/odometry/rgbd_frontend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <utility>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/odometry/hypothesis_evidence.h"
#include "core/registration/depth_points.h"
#include "core/registration/sensor_timing.h"

namespace icgm {

namespace {
using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The information of a covariance (right perturbations, pose_refinement.h); none when it is not
// finite or cannot be inverted.
std::optional<Mat6> Information(const Mat6& covariance) {
  Eigen::LDLT<Mat6> ldlt(covariance);
  if (ldlt.info() != Eigen::Success || !covariance.allFinite()) return std::nullopt;
  return Mat6(ldlt.solve(Mat6::Identity()));
}

// Information-weighted mean of two estimates of one pose, one Gauss-Newton step in the tangent
// space at `a`; none when the result is not finite.
std::optional<Pose3> InformationWeightedMean(const Pose3& a, const Mat6& info_a, const Pose3& b,
                                             const Mat6& info_b) {
  const Vec6 delta = LogSE3(Between(a, b));
  if (!delta.allFinite()) return std::nullopt;
  const Vec6 mean = (info_b + info_a).ldlt().solve(info_b * delta);
  if (!mean.allFinite()) return std::nullopt;
  return Orthonormalized(a * ExpSE3(mean));
}

// The same from covariances; `a` when either cannot be used.
Pose3 CovarianceWeightedMean(const Pose3& a, const Mat6& cov_a, const Pose3& b, const Mat6& cov_b) {
  const std::optional<Mat6> info_a = Information(cov_a), info_b = Information(cov_b);
  if (!info_a || !info_b) return a;
  return InformationWeightedMean(a, *info_a, b, *info_b).value_or(a);
}

}  // namespace

// One processed frame: its features, depth and estimated pose.
struct RgbdFrontend::Frame {
  size_t index = 0;
  Time stamp;
  FeatureSet features;
  cv::Mat depth_m;
  // As a keyframe, corrected by the keyframe bundle adjustment while it is in its window, hence
  // mutable behind the shared const pointers.
  mutable Pose3 odom_camera = Pose3::Identity();
  // The registration that placed it (keyframe_ba links): the reference's frame index,
  // T_reference_this and its covariance; unset when not registered to a keyframe.
  std::optional<size_t> link_reference;
  Pose3 link_relative = Pose3::Identity();
  Mat6 link_covariance = Mat6::Identity();
  // Pose predicted before registration (ICGM motion prior); unset when none is available.
  std::optional<Pose3> predicted_odom_camera;
  // Per keypoint: 1 when it lies in the dynamic region carried over from the previous frame
  // (never matched); empty when nothing is masked.
  std::vector<uint8_t> excluded;
  // Dynamic cells of this frame, from its depth residuals against its reference.
  DynamicMask dynamic;
  // The previous frame's dynamic cells carried into this one (dynamic_masking).
  DynamicMask carried;
  // 8-bit grey image for the edge evidence (select_by_evidence; empty for features extracted
  // elsewhere).
  cv::Mat grey;
  // As a reference: per keypoint, how many later frames showed it in a region the walkers left
  // (dynamic_masking); at reference_dynamic_votes it is no longer matched. Grows while the
  // frame serves as a reference, hence mutable behind the shared const pointers.
  mutable std::vector<uint16_t> dynamic_votes;
  // residual_trend: per keypoint, 1 when it matched a reference keypoint the trend voted out
  // (kept out of a new keyframe); empty when none did.
  std::vector<uint8_t> trend_excluded;
  // map_hypothesis: the frame located in the local map without a start pose, with its map
  // correspondences (unset when off).
  std::shared_ptr<const MapHypothesis> map_hypothesis;
};

// Registration of a current frame to a reference frame.
struct RgbdFrontend::Attempt {
  RegistrationResult registration;
  size_t matches = 0;
  size_t kept = 0;
  // Per keypoint of the current frame: 1 when its match survived ICGM.
  std::vector<uint8_t> robust;
  // Current-frame pixels of the matches given to registration.
  std::vector<cv::Point2f> registered_px;
  std::vector<cv::Point2f> registered_reference_px;  // the reference's side of the same
  // The matches given to registration, as flags over the frame pair's matches.
  std::vector<uint8_t> used;
  // The frame registered to (set by RegisterTo).
  const Frame* reference = nullptr;
  // Whole-frame depth and edge agreement of the registered motion (select_by_evidence).
  DepthConsistency consistency;
  DepthConsistency edges;
  // The other accepted hypotheses of the same frame pair (select_by_evidence), for the choice
  // across references (select_across_references).
  std::vector<RegistrationResult> alternatives;
  // Every hypothesis the evidence choice judged and the index of the chosen one (-1: no
  // choice was made), for the frame's report.
  std::vector<JudgedHypothesis> judged;
  int chosen = -1;
  // residual_trend: the frame pair's matches after masking, and the current keypoints matched
  // to reference keypoints the trend had voted out.
  std::vector<cv::DMatch> matches_kept;
  std::vector<int> trend_excluded_current;
  // Grid pixels whose depth, and edge pixels whose grey value, the motion explains.
  size_t Evidence() const { return consistency.agreeing + edges.agreeing; }
  bool ok() const { return registration.status.ok(); }
};

// The ratio-test matches of one frame pair.
struct RgbdFrontend::MatchSet {
  std::vector<cv::Point2f> ref_px, cur_px;
  std::vector<double> sigma;
  std::vector<int> cur_index;  // keypoint of the current frame per match
};

namespace {

// Keypoints (and descriptor rows) whose flag in `keep` is non-zero.
FeatureSet SubsetFeatures(const FeatureSet& in, const std::vector<uint8_t>& keep) {
  FeatureSet out;
  out.binary = in.binary;
  std::vector<int> rows;
  for (size_t i = 0; i < in.size(); ++i) {
    if (!keep[i]) continue;
    out.keypoints.push_back(in.keypoints[i]);
    rows.push_back(static_cast<int>(i));
  }
  if (!in.descriptors.empty()) {
    out.descriptors.create(static_cast<int>(rows.size()), in.descriptors.cols,
                           in.descriptors.type());
    for (size_t r = 0; r < rows.size(); ++r) {
      in.descriptors.row(rows[r]).copyTo(out.descriptors.row(static_cast<int>(r)));
    }
  }
  return out;
}

template <typename T>
std::vector<T> Subset(const std::vector<T>& in, const std::vector<uint8_t>& keep) {
  std::vector<T> out;
  for (size_t i = 0; i < in.size() && i < keep.size(); ++i) {
    if (keep[i]) out.push_back(in[i]);
  }
  return out;
}

}  // namespace

RgbdFrontend::RgbdFrontend(const FrontendOptions& options, const CameraIntrinsics& intrinsics)
    : options_(options),
      intrinsics_(intrinsics),
      extractor_(FeatureExtractor::Create(options.features)),
      matcher_(options.matcher),
      wheel_(options.wheel),
      fusion_(options.fusion),
      undistortion_(intrinsics),
      pyramid_octaves_(options.features.detector == Detector::kOrb ||
                       options.features.detector == Detector::kGfttOrb),
      velocity_history_(static_cast<size_t>(options.velocity_prior_steps),
                        options.fusion.max_constant_velocity_s, options.velocity_prior_median,
                        options.velocity_prior_from_rest),
      registered_velocity_history_(static_cast<size_t>(options.velocity_prior_steps),
                                   options.fusion.max_constant_velocity_s),
      prior_reset_(options.prior_reset),
      pose_window_(options.window, options.fusion.max_constant_velocity_s),
      residual_trend_(options.residual_trend) {}

RgbdFrontend::~RgbdFrontend() = default;

Status RgbdFrontend::AddWheelOdometry(Time stamp, const Pose3& odom_base) {
  return wheel_.Add(stamp, odom_base);
}

const FeatureSet* RgbdFrontend::last_frame_features(Time* stamp) const {
  if (!previous_) return nullptr;
  if (stamp) *stamp = previous_->stamp;
  return &previous_->features;
}

double RgbdFrontend::PixelSigma(const cv::KeyPoint& k) const {
  // Pyramid detectors localise a keypoint of octave o to about scale_factor^o pixels.
  return pyramid_octaves_ ? PyramidPixelSigma(k, options_.features.orb_scale_factor) : 1.0;
}

std::vector<cv::Point2f> RgbdFrontend::ObserveResidualTrend(const Attempt& attempt,
                                                           Frame* current) {
  const Frame& ref = *attempt.reference;
  if (!residual_trend_.tracking(ref.index)) residual_trend_.Reset(ref.index, ref.features.size());
  const bool predicted =
      options_.residual_trend.against_prediction && current->predicted_odom_camera.has_value();
  const Pose3 cur_ref =
      (predicted ? *current->predicted_odom_camera : current->odom_camera).inverse() *
      ref.odom_camera;
  const std::vector<cv::DMatch>& matches = attempt.matches_kept;
  std::vector<cv::Point2f> ref_px;
  for (const cv::DMatch& m : matches) ref_px.push_back(ref.features.keypoints[m.queryIdx].pt);
  std::vector<Vec3> points;
  std::vector<uint8_t> lifted;
  KeypointsToPoints(ref_px, ref.depth_m, intrinsics_, options_.registration.depth, &points,
                    &lifted);
  std::vector<TrendObservation> observations;
  for (size_t k = 0; k < matches.size(); ++k) {
    const Vec3 p = cur_ref * points[k];
    if (!lifted[k] || p.z() <= 1e-3) continue;
    const cv::KeyPoint& kc = current->features.keypoints[matches[k].trainIdx];
    const double sigma =
        std::max(PixelSigma(ref.features.keypoints[matches[k].queryIdx]), PixelSigma(kc));
    observations.push_back({matches[k].queryIdx, ref_px[k],
                            (Eigen::Vector2d(kc.pt.x, kc.pt.y) - intrinsics_.Project(p)) / sigma});
  }
  const std::vector<int> voted = residual_trend_.Observe(observations);
  // Voted out: no longer matched (as a keypoint the walkers were seen leaving), and the current
  // keypoints matched to them, now or before, are kept out of a new keyframe.
  std::vector<cv::Point2f> voted_px;
  if (!voted.empty()) ref.dynamic_votes.resize(ref.features.size(), 0);
  const uint16_t dropped = static_cast<uint16_t>(options_.reference_dynamic_votes);
  for (const int k : voted) {
    ref.dynamic_votes[k] = std::max(ref.dynamic_votes[k], dropped);
    voted_px.push_back(ref.features.keypoints[k].pt);
  }
  std::vector<int> excluded = attempt.trend_excluded_current;
  residual_trend_.AppendMatchedToVoted(matches, &excluded);
  if (!excluded.empty()) {
    current->trend_excluded.assign(current->features.size(), 0);
    for (const int i : excluded) current->trend_excluded[i] = 1;
  }
  return voted_px;
}

RgbdFrontend::Attempt RgbdFrontend::RegisterTo(const Frame& reference, const Frame& current,
                                               StageTimes* times) const {
  Attempt a;
  a.reference = &reference;
  a.robust.assign(current.features.size(), 0);
  auto t0 = Clock::now();
  std::vector<cv::DMatch> matches = matcher_.Match(reference.features, current.features);
  // Keypoints in a dynamic region (carried into this frame, or voted out of the reference)
  // never take part.
  const auto& votes = reference.dynamic_votes;
  // residual_trend: current keypoints matched to reference keypoints the trend voted out.
  std::vector<int> trend_excluded;
  if (options_.residual_trend.on() && residual_trend_.tracking(reference.index)) {
    residual_trend_.AppendMatchedToVoted(matches, &trend_excluded);
  }
  const auto masked = [&](const cv::DMatch& m) {
    return (!current.excluded.empty() && current.excluded[m.trainIdx]) ||
           (!votes.empty() && votes[m.queryIdx] >= options_.reference_dynamic_votes);
  };
  matches.erase(std::remove_if(matches.begin(), matches.end(), masked), matches.end());
  times->matching_ms += MsSince(t0);
  a.matches = matches.size();

  t0 = Clock::now();
  MatchSet all;
  for (const cv::DMatch& m : matches) {
    const cv::KeyPoint& kr = reference.features.keypoints[m.queryIdx];
    const cv::KeyPoint& kc = current.features.keypoints[m.trainIdx];
    all.ref_px.push_back(kr.pt);
    all.cur_px.push_back(kc.pt);
    all.sigma.push_back(std::max(PixelSigma(kr), PixelSigma(kc)));
    all.cur_index.push_back(m.trainIdx);
  }
  // Where each reference keypoint would appear in the current image if it were static and the
  // camera moved as predicted (NaN without usable reference depth; such matches would be
  // dropped by the registration anyway). Serves ICGM's motion prior and the prediction's
  // hypothesis.
  std::vector<Vec3> ref_points;
  std::vector<uint8_t> lifted;
  if (!reference.depth_m.empty()) {
    KeypointsToPoints(all.ref_px, reference.depth_m, intrinsics_, options_.registration.depth,
                      &ref_points, &lifted);
  }
  // Where the reference keypoints appear with the current frame at `odom_camera`.
  const auto projected_at = [&](const Pose3& odom_camera) {
    const Pose3 cur_ref = odom_camera.inverse() * reference.odom_camera;
    std::vector<Eigen::Vector2d> px(all.ref_px.size(), Eigen::Vector2d::Constant(std::nan("")));
    for (size_t k = 0; k < px.size(); ++k) {
      if (!lifted[k]) continue;
      const Vec3 p = cur_ref * ref_points[k];
      if (p.z() > 1e-3) px[k] = intrinsics_.Project(p);
    }
    return px;
  };
  std::vector<Eigen::Vector2d> predicted;
  if (current.predicted_odom_camera && !reference.depth_m.empty() &&
      ((options_.use_icgm && options_.icgm.motion_prior) || options_.select_by_evidence)) {
    predicted = projected_at(*current.predicted_odom_camera);
  }
  // The same where the local map locates the current frame (map_hypothesis).
  std::vector<Eigen::Vector2d> map_predicted;
  if (current.map_hypothesis && current.map_hypothesis->status.ok() && !reference.depth_m.empty() &&
      options_.select_by_evidence) {
    map_predicted = projected_at(current.map_hypothesis->odom_camera);
  }
  std::vector<uint8_t> keep(matches.size(), 1);
  if (options_.use_icgm && matches.size() >= 2) {
    std::vector<Eigen::Vector2d> pa, pb;
    MatchedPoints(reference.features.keypoints, current.features.keypoints, matches, &pa, &pb);
    const bool prior = options_.icgm.motion_prior && !predicted.empty();
    keep = RunIcgm(pa, pb, options_.icgm, prior ? &predicted : nullptr).kept;
  }
  times->icgm_ms += MsSince(t0);

  t0 = Clock::now();
  const bool depth_ok = !reference.depth_m.empty() && !current.depth_m.empty();
  // Registration on the matches flagged in `use`.
  const auto register_subset = [&](const std::vector<uint8_t>& use, uint64_t seed_offset,
                                   Attempt* out) {
    const std::vector<cv::Point2f> ref_px = Subset(all.ref_px, use);
    out->registered_px = Subset(all.cur_px, use);
    out->registered_reference_px = ref_px;
    out->used = use;
    const std::vector<double> sigma = Subset(all.sigma, use);
    out->kept = ref_px.size();
    if (!depth_ok) {
      out->registration.matches_2d = out->kept;
      out->registration.status = Status::Error("no usable depth image");
      return;
    }
    RegistrationOptions registration = options_.registration;
    registration.rng_seed += seed_offset;
    out->registration =
        RegisterRgbd(ref_px, reference.depth_m, out->registered_px, current.depth_m, intrinsics_,
                     registration, options_.weight_by_octave ? &sigma : nullptr);
  };
  register_subset(keep, 0, &a);
  for (size_t i = 0; i < keep.size(); ++i) {
    if (keep[i]) a.robust[all.cur_index[i]] = 1;
  }
  // refit_each_hypothesis: ChooseByEvidence refits every hypothesis before judging it.
  const bool judged_after_refit = options_.static_inlier_refit && options_.refit_each_hypothesis &&
                                  options_.select_by_evidence && depth_ok && matches.size() >= 3;
  if (options_.select_by_evidence && depth_ok && matches.size() >= 3) {
    ChooseByEvidence(reference, current, all, predicted, map_predicted, keep, register_subset, &a);
  }
  if (options_.static_inlier_refit && !judged_after_refit && depth_ok && a.ok()) {
    RefitOnStaticInliers(reference, current, all, register_subset, &a);
  }
  if (options_.dense_refinement && a.ok()) {
    const DenseRefinementResult dense = RefineDense(
        reference.depth_m, current.depth_m, reference.grey, current.grey,
        a.registration.relative_pose, intrinsics_, options_.dense, options_.depth_consistency,
        current.carried, reference.dynamic);
    if (dense.status.ok()) a.registration.relative_pose = dense.ref_cur;
  }
  times->registration_ms += MsSince(t0);
  // Set last: the evidence choice may replace the attempt by another hypothesis's.
  if (options_.residual_trend.on()) {
    a.matches_kept = std::move(matches);
    a.trend_excluded_current = std::move(trend_excluded);
  }
  return a;
}

void RgbdFrontend::ChooseByEvidence(const Frame& reference, const Frame& current,
                                    const MatchSet& all,
                                    const std::vector<Eigen::Vector2d>& predicted,
                                    const std::vector<Eigen::Vector2d>& map_predicted,
                                    const std::vector<uint8_t>& first_use,
                                    const SubsetRegistration& register_subset,
                                    Attempt* best) const {
  // evidence_min_depth_m: only the room beyond the walkers' distance judges.
  DepthConsistencyOptions judged = options_.depth_consistency;
  judged.min_depth_m = std::max(judged.min_depth_m, options_.evidence_min_depth_m);
  const auto evidence = [&](Attempt* h) {
    if (h->ok()) {
      h->consistency =
          CheckDepthConsistency(reference.depth_m, current.depth_m, h->registration.relative_pose,
                                intrinsics_, judged);
      h->edges = CheckEdgeConsistency(reference.grey, current.grey, current.depth_m,
                                      h->registration.relative_pose, intrinsics_, judged);
      // The previous frame as a second judge: walkers stand elsewhere there than in the
      // reference, the static scene does not.
      if (options_.evidence_from_previous_frame && previous_ &&
          previous_->index != reference.index && !previous_->depth_m.empty()) {
        const Pose3 prev_cur = previous_->odom_camera.inverse() * reference.odom_camera *
                               h->registration.relative_pose;
        const DepthConsistency d = CheckDepthConsistency(previous_->depth_m, current.depth_m,
                                                         prev_cur, intrinsics_, judged);
        const DepthConsistency e = CheckEdgeConsistency(previous_->grey, current.grey,
                                                        current.depth_m, prev_cur, intrinsics_,
                                                        judged);
        h->consistency.agreeing += d.agreeing;
        h->consistency.compared += d.compared;
        h->edges.agreeing += e.agreeing;
        h->edges.compared += e.compared;
      }
    }
  };
  // Which matches a hypothesis used as inliers, as flags over `all`.
  const auto inlier_flags = [&](const std::vector<uint8_t>& use, const Attempt& h) {
    std::vector<int> used;
    for (size_t i = 0; i < use.size(); ++i) {
      if (use[i]) used.push_back(static_cast<int>(i));
    }
    std::vector<uint8_t> flags(use.size(), 0);
    for (const int k : h.registration.inlier_indices) flags[used[k]] = 1;
    return flags;
  };
  // Each candidate: the matches to register, the RANSAC seed offset and where they came from.
  struct Candidate {
    std::vector<uint8_t> use;
    uint64_t seed_offset = 0;
    HypothesisKind kind = HypothesisKind::kIcgm;
  };
  std::vector<Candidate> candidates;
  // The first registration's matches with further seeds (evidence_ransac_runs).
  for (int run = 1; run < options_.evidence_ransac_runs; ++run) {
    candidates.push_back({first_use, static_cast<uint64_t>(run), HypothesisKind::kSeed});
  }
  // The matches the first hypothesis left out: a second consistent set.
  if (best->ok()) {
    std::vector<uint8_t> rest = inlier_flags(first_use, *best);
    for (auto& f : rest) f = !f;
    candidates.push_back({std::move(rest), 0, HypothesisKind::kLeftOut});
  }
  // evidence_far_hypothesis_m: the kept matches beyond the walkers, on their own.
  if (options_.evidence_far_hypothesis_m > 0.0 && !reference.depth_m.empty()) {
    std::vector<uint8_t> far(first_use.size(), 0);
    for (size_t k = 0; k < far.size(); ++k) {
      const int x = static_cast<int>(std::lround(all.ref_px[k].x));
      const int y = static_cast<int>(std::lround(all.ref_px[k].y));
      if (!first_use[k] || x < 0 || y < 0 || x >= reference.depth_m.cols ||
          y >= reference.depth_m.rows) {
        continue;
      }
      const float z = reference.depth_m.at<float>(y, x);
      far[k] = std::isfinite(z) && z >= options_.evidence_far_hypothesis_m;
    }
    candidates.push_back({std::move(far), 0, HypothesisKind::kFar});
  }
  // The matches that agree with the predicted motion, and with the map's location.
  for (const std::vector<Eigen::Vector2d>* expected : {&predicted, &map_predicted}) {
    if (expected->empty()) continue;
    std::vector<uint8_t> agree(all.cur_px.size(), 0);
    for (size_t k = 0; k < agree.size(); ++k) {
      const Eigen::Vector2d obs(all.cur_px[k].x, all.cur_px[k].y);
      agree[k] = (*expected)[k].allFinite() &&
                 ((*expected)[k] - obs).norm() <= options_.icgm.motion_prior_tolerance_px;
    }
    candidates.push_back({std::move(agree), 0,
                          expected == &predicted ? HypothesisKind::kPrediction
                                                 : HypothesisKind::kMap});
  }
  const std::vector<int> first_inliers = best->registration.inlier_indices;
  // refit_each_hypothesis: each hypothesis is judged after its own static refit (the matches
  // left out above are those of the first registration, before its refit).
  const bool refit_each = options_.static_inlier_refit && options_.refit_each_hypothesis;
  // A hypothesis's record: its kind and the current pixels of its inliers among `use` (taken
  // before any refit; the evidence is filled in once judged).
  const auto record = [&](HypothesisKind kind, const std::vector<uint8_t>& use, const Attempt& h) {
    JudgedHypothesis j;
    j.kind = kind;
    j.inliers = h.registration.inliers;
    j.relative_pose = h.registration.relative_pose;
    const std::vector<uint8_t> inliers = inlier_flags(use, h);
    std::vector<cv::Point2f> reference_px;
    for (size_t i = 0; i < inliers.size(); ++i) {
      if (!inliers[i]) continue;
      j.inlier_px.push_back(all.cur_px[i]);
      reference_px.push_back(all.ref_px[i]);
    }
    j.median_depth_m = MedianDepthAt(reference.depth_m, reference_px);
    return j;
  };
  JudgedHypothesis first_record;
  if (best->ok()) first_record = record(HypothesisKind::kIcgm, first_use, *best);
  if (refit_each && best->ok()) {
    RefitOnStaticInliers(reference, current, all, register_subset, best);
  }
  evidence(best);
  const int min_matches = std::max(3, options_.registration.min_matches_3d);
  std::vector<Attempt> hypotheses;
  std::vector<JudgedHypothesis> judged_hypotheses;
  const size_t matches = best->matches;
  // Inlier sets already among the hypotheses from `first_use` (further seeds add only new ones).
  std::vector<std::vector<int>> first_use_sets;
  if (best->ok()) {
    first_use_sets.push_back(first_inliers);
    first_record.evidence = {best->consistency.agreeing, best->edges.agreeing};
    judged_hypotheses.push_back(std::move(first_record));
    hypotheses.push_back(std::move(*best));
  }
  for (const auto& [use, seed_offset, kind] : candidates) {
    if (std::count(use.begin(), use.end(), 1) < min_matches) continue;
    Attempt h;
    h.reference = &reference;
    h.matches = matches;
    register_subset(use, seed_offset, &h);
    if (!h.ok()) continue;
    if (seed_offset > 0) {
      const std::vector<int>& set = h.registration.inlier_indices;
      if (std::find(first_use_sets.begin(), first_use_sets.end(), set) != first_use_sets.end()) {
        continue;
      }
      first_use_sets.push_back(set);
    }
    h.robust.assign(current.features.size(), 0);
    const std::vector<uint8_t> inliers = inlier_flags(use, h);
    for (size_t i = 0; i < inliers.size(); ++i) {
      if (inliers[i]) h.robust[all.cur_index[i]] = 1;
    }
    JudgedHypothesis j = record(kind, use, h);
    if (refit_each) RefitOnStaticInliers(reference, current, all, register_subset, &h);
    evidence(&h);
    j.evidence = {h.consistency.agreeing, h.edges.agreeing};
    judged_hypotheses.push_back(std::move(j));
    hypotheses.push_back(std::move(h));
  }
  if (hypotheses.empty()) return;
  // The evidence (depth and edge agreement) decides; within evidence_margin of the best, the
  // hypothesis nearest the predicted motion wins.
  std::vector<HypothesisEvidence> counts;
  for (const Attempt& h : hypotheses) counts.push_back({h.consistency.agreeing, h.edges.agreeing});
  std::vector<double> score = EvidenceScores(counts, options_.evidence_normalized);
  // map_hypothesis.evidence_weight: the map correspondences each motion explains, over the
  // most any hypothesis explains, join the evidence.
  if (options_.map_hypothesis.evidence_weight > 0.0 && current.map_hypothesis &&
      current.map_hypothesis->correspondences.size() > 0) {
    std::vector<size_t> support;
    for (const Attempt& h : hypotheses) {
      support.push_back(MapSupport(current.map_hypothesis->correspondences,
                                   reference.odom_camera * h.registration.relative_pose,
                                   intrinsics_, MapSupportOptions()));
    }
    const size_t most_support = *std::max_element(support.begin(), support.end());
    for (size_t i = 0; most_support > 0 && i < hypotheses.size(); ++i) {
      score[i] += options_.map_hypothesis.evidence_weight * static_cast<double>(support[i]) /
                  static_cast<double>(most_support);
    }
  }
  // evidence_spread_weight: how widely each set's inliers spread over the view.
  if (options_.evidence_spread_weight > 0.0) {
    std::vector<size_t> spread;
    for (const JudgedHypothesis& j : judged_hypotheses) {
      spread.push_back(SpreadCells(j.inlier_px,
                                   cv::Size(intrinsics_.width_px, intrinsics_.height_px), 8, 6));
    }
    const size_t widest = *std::max_element(spread.begin(), spread.end());
    for (size_t i = 0; widest > 0 && i < hypotheses.size(); ++i) {
      score[i] += options_.evidence_spread_weight * static_cast<double>(spread[i]) /
                  static_cast<double>(widest);
    }
  }
  size_t most = 0;
  for (size_t i = 1; i < hypotheses.size(); ++i) {
    if (score[i] > score[most]) most = i;
  }
  // Each hypothesis's distance to the predicted motion (translation / 5 cm + rotation / 2 deg).
  std::vector<double> prediction_distance(hypotheses.size(), std::nan(""));
  if (current.predicted_odom_camera) {
    const Pose3 predicted_ref_cur = reference.odom_camera.inverse() * *current.predicted_odom_camera;
    for (size_t i = 0; i < hypotheses.size(); ++i) {
      const Pose3 d = Between(predicted_ref_cur, hypotheses[i].registration.relative_pose);
      prediction_distance[i] =
          TranslationNorm(d) / 0.05 + RotationAngleRad(d) * 180.0 / M_PI / 2.0;
    }
  }
  size_t chosen = most;
  if (current.predicted_odom_camera) {
    const double floor = (1.0 - options_.evidence_margin) * score[most];
    double nearest = INFINITY;
    for (size_t i = 0; i < hypotheses.size(); ++i) {
      if (score[i] < floor) continue;
      if (prediction_distance[i] < nearest) {
        nearest = prediction_distance[i];
        chosen = i;
      }
    }
  }
  // evidence_rotation_margin: among those close to the best, the smallest rotation wins.
  if (options_.evidence_rotation_margin > 0.0 &&
      (options_.evidence_rotation_margin_frames == 0 ||
       current.index < static_cast<size_t>(options_.evidence_rotation_margin_frames))) {
    const double floor = (1.0 - options_.evidence_rotation_margin) * score[most];
    double smallest = RotationAngleRad(hypotheses[chosen].registration.relative_pose);
    for (size_t i = 0; i < hypotheses.size(); ++i) {
      if (score[i] < floor) continue;
      const double angle = RotationAngleRad(hypotheses[i].registration.relative_pose);
      if (angle < smallest) {
        smallest = angle;
        chosen = i;
      }
    }
  }
  // evidence_depth_order_margin: of the sets explaining the frame about as well, the farthest.
  if (options_.evidence_depth_order_margin > 0.0) {
    std::vector<double> depth;
    std::vector<size_t> inliers;
    for (const JudgedHypothesis& j : judged_hypotheses) {
      depth.push_back(j.median_depth_m);
      inliers.push_back(j.inliers);
    }
    chosen = ChooseByDepthOrder(score, depth, inliers, chosen,
                                options_.evidence_depth_order_margin,
                                options_.evidence_depth_order_min_gap_m,
                                static_cast<size_t>(options_.evidence_depth_order_min_inliers));
  }
  // evidence_prediction_gate_m: a winner far from the prediction gives way to a set near it.
  if (options_.evidence_prediction_gate_m > 0.0 && current.predicted_odom_camera &&
      (options_.evidence_prediction_gate_frames == 0 ||
       current.index < static_cast<size_t>(options_.evidence_prediction_gate_frames))) {
    const Pose3 predicted_ref_cur = reference.odom_camera.inverse() * *current.predicted_odom_camera;
    std::vector<double> from_prediction_m;
    std::vector<size_t> inliers;
    for (size_t i = 0; i < hypotheses.size(); ++i) {
      from_prediction_m.push_back(
          TranslationNorm(Between(predicted_ref_cur, hypotheses[i].registration.relative_pose)));
      inliers.push_back(judged_hypotheses[i].inliers);
    }
    chosen = ChooseWithinPredictionGate(
        score, from_prediction_m, inliers, chosen, options_.evidence_prediction_gate_m,
        static_cast<size_t>(options_.evidence_prediction_gate_min_inliers));
  }
  std::vector<RegistrationResult> others;
  for (size_t i = 0; i < hypotheses.size(); ++i) {
    if (i != chosen) others.push_back(std::move(hypotheses[i].registration));
  }
  for (size_t i = 0; i < judged_hypotheses.size(); ++i) {
    judged_hypotheses[i].score = score[i];
    judged_hypotheses[i].prediction_distance = prediction_distance[i];
  }
  *best = std::move(hypotheses[chosen]);
  best->alternatives = std::move(others);
  best->judged = std::move(judged_hypotheses);
  best->chosen = static_cast<int>(chosen);
}

void RgbdFrontend::RefitOnStaticInliers(const Frame& reference, const Frame& current,
                                        const MatchSet& all,
                                        const SubsetRegistration& register_subset,
                                        Attempt* a) const {
  DepthConsistencyOptions masks = options_.depth_consistency;
  if (options_.static_refit_fill_max_step_m > 0.0) {
    masks.fill_max_step_m = options_.static_refit_fill_max_step_m;
  }
  DynamicMask moved_in, moved_out;
  CheckDepthConsistency(reference.depth_m, current.depth_m, a->registration.relative_pose,
                        intrinsics_, masks, &moved_in, &moved_out);
  // The chosen motion's inliers, as flags over `all`, without those on what moved.
  std::vector<uint8_t> survivors(all.cur_px.size(), 0);
  std::vector<int> used;
  for (size_t i = 0; i < a->used.size(); ++i) {
    if (a->used[i]) used.push_back(static_cast<int>(i));
  }
  size_t dropped = 0;
  for (const int k : a->registration.inlier_indices) {
    const int i = used[k];
    if (moved_in.Contains(all.cur_px[i]) || moved_out.Contains(all.ref_px[i])) {
      ++dropped;
    } else {
      survivors[i] = 1;
    }
  }
  const int min_matches = std::max(3, options_.registration.min_matches_3d);
  if (dropped == 0 || std::count(survivors.begin(), survivors.end(), 1) < min_matches) return;
  Attempt refit;
  register_subset(survivors, 0, &refit);
  if (!refit.ok()) return;
  a->registration = std::move(refit.registration);
  a->registered_px = std::move(refit.registered_px);
  a->registered_reference_px = std::move(refit.registered_reference_px);
  a->used = std::move(refit.used);
  a->kept = refit.kept;
}

std::vector<std::shared_ptr<const RgbdFrontend::Frame>> RgbdFrontend::RecentKeyframes(
    int max_keyframes) const {
  // The most recent keyframes, and the reference when it is not among them (revisited).
  std::vector<std::shared_ptr<const Frame>> keyframes;
  for (auto it = window_.rbegin();
       it != window_.rend() && static_cast<int>(keyframes.size()) < max_keyframes; ++it) {
    keyframes.push_back(*it);
  }
  if (reference_ && std::find(keyframes.begin(), keyframes.end(), reference_) == keyframes.end()) {
    keyframes.push_back(reference_);
  }
  return keyframes;
}

void RgbdFrontend::LiftKeyframe(const Frame& kf, std::vector<Vec3>* points,
                                std::vector<uint8_t>* use) const {
  std::vector<cv::Point2f> pixels;
  pixels.reserve(kf.features.size());
  for (const cv::KeyPoint& k : kf.features.keypoints) pixels.push_back(k.pt);
  KeypointsToPoints(pixels, kf.depth_m, intrinsics_, options_.registration.depth, points, use);
}

std::vector<uint8_t> RgbdFrontend::StaticKeypoints(const Frame& kf,
                                                   const std::vector<uint8_t>& lifted) const {
  // Keypoints the walkers were seen leaving (dynamic_votes) are not static.
  std::vector<uint8_t> use = lifted;
  for (size_t i = 0; i < kf.dynamic_votes.size() && i < use.size(); ++i) {
    if (kf.dynamic_votes[i] >= options_.reference_dynamic_votes) use[i] = 0;
  }
  return use;
}

TimedMapPoints RgbdFrontend::KeyframeMapPoints(const Frame& kf) const {
  TimedMapPoints out;
  out.stamp_s = static_cast<double>(kf.stamp.nanoseconds()) * 1e-9;
  if (kf.depth_m.empty()) return out;
  std::vector<Vec3> points;
  std::vector<uint8_t> lifted;
  LiftKeyframe(kf, &points, &lifted);
  AddKeyframePoints(kf.features.descriptors, kf.features.binary, points,
                    StaticKeypoints(kf, lifted), kf.odom_camera, &out.points);
  return out;
}

struct RgbdFrontend::MapHypothesisCache {
  struct Entry {
    std::shared_ptr<const Frame> keyframe;  // held, so that its address is not reused
    std::vector<Vec3> lifted_points;        // LiftKeyframe (depth and keypoints do not change)
    std::vector<uint8_t> lifted;
    // What the map points were made with (both may change after the keyframe was made).
    std::vector<uint8_t> use;
    Pose3 odom_camera = Pose3::Identity();
    PersistenceCache::Keyframe points;
  };
  std::map<const Frame*, Entry> entries;
  uint64_t last_id = 0;
  PersistenceCache persistence;
};

PersistenceCache::Keyframe RgbdFrontend::CachedKeyframeMapPoints(
    const std::shared_ptr<const Frame>& kf) const {
  MapHypothesisCache& cache = *map_hypothesis_cache_;
  auto it = cache.entries.find(kf.get());
  if (it == cache.entries.end()) {
    MapHypothesisCache::Entry entry;
    entry.keyframe = kf;
    if (!kf->depth_m.empty()) LiftKeyframe(*kf, &entry.lifted_points, &entry.lifted);
    it = cache.entries.emplace(kf.get(), std::move(entry)).first;
  }
  MapHypothesisCache::Entry& e = it->second;
  std::vector<uint8_t> use;
  if (!kf->depth_m.empty()) use = StaticKeypoints(*kf, e.lifted);
  if (!e.points.points || use != e.use || kf->odom_camera.matrix() != e.odom_camera.matrix()) {
    // As KeyframeMapPoints.
    auto points = std::make_shared<TimedMapPoints>();
    points->stamp_s = static_cast<double>(kf->stamp.nanoseconds()) * 1e-9;
    if (!kf->depth_m.empty()) {
      AddKeyframePoints(kf->features.descriptors, kf->features.binary, e.lifted_points, use,
                        kf->odom_camera, &points->points);
    }
    e.use = std::move(use);
    e.odom_camera = kf->odom_camera;
    e.points.id = ++cache.last_id;
    e.points.points = std::move(points);
  }
  return e.points;
}

LocalMapPoints RgbdFrontend::BuildLocalMap(int max_keyframes) const {
  std::vector<TimedMapPoints> recent;
  for (const auto& kf : RecentKeyframes(max_keyframes)) recent.push_back(KeyframeMapPoints(*kf));
  // persistence off: every point of the recent keyframes, in their order.
  return PersistentPoints(recent, {}, MapHypothesisOptions());
}

std::vector<double> RgbdFrontend::PixelSigmas(const Frame& frame) const {
  std::vector<double> sigma;
  sigma.reserve(frame.features.size());
  for (const cv::KeyPoint& k : frame.features.keypoints) sigma.push_back(PixelSigma(k));
  return sigma;
}

MapHypothesisOptions RgbdFrontend::MapSupportOptions() const {
  MapHypothesisOptions options = options_.map_hypothesis;
  options.depth_abs_m = options_.registration.inlier_threshold_m;
  options.depth_rel_per_m = options_.registration.reprojection_depth_rel_per_m;
  options.max_iterations = options_.registration.max_iterations;
  options.rng_seed = options_.registration.rng_seed;
  return options;
}

std::shared_ptr<const MapHypothesis> RgbdFrontend::LocateInMap(const Frame& current,
                                                               const Pose3& viewing_frame) const {
  const MapHypothesisOptions options = MapSupportOptions();
  // Keypoints in the dynamic region carried into the frame are never matched.
  std::vector<uint8_t> usable(current.features.size(), 1);
  for (size_t i = 0; i < current.excluded.size() && i < usable.size(); ++i) {
    usable[i] = !current.excluded[i];
  }
  // persistence: only the points the window's keyframes saw in place over seconds. What
  // depends on the keyframes alone is kept between frames.
  if (!map_hypothesis_cache_) map_hypothesis_cache_ = std::make_unique<MapHypothesisCache>();
  std::vector<PersistenceCache::Keyframe> recent, observers;
  const std::vector<std::shared_ptr<const Frame>> keyframes = RecentKeyframes(options.keyframes);
  std::vector<std::shared_ptr<const Frame>> used = keyframes;
  for (const auto& kf : keyframes) recent.push_back(CachedKeyframeMapPoints(kf));
  if (options.persistence_keyframes > 0) {
    for (const std::shared_ptr<const Frame>& kf : window_) {
      if (std::find(keyframes.begin(), keyframes.end(), kf) == keyframes.end()) {
        observers.push_back(CachedKeyframeMapPoints(kf));
        used.push_back(kf);
      }
    }
    observers.insert(observers.end(), recent.begin(), recent.end());
  }
  // Keyframes that left the window are dropped.
  auto& entries = map_hypothesis_cache_->entries;
  for (auto it = entries.begin(); it != entries.end();) {
    it = std::find(used.begin(), used.end(), it->second.keyframe) == used.end() ? entries.erase(it)
                                                                                : std::next(it);
  }
  return std::make_shared<const MapHypothesis>(LocateInLocalMap(
      map_hypothesis_cache_->persistence.Points(recent, observers, options),
      current.features.keypoints, current.features.descriptors, PixelSigmas(current), usable,
      current.depth_m, options_.registration.depth, viewing_frame, intrinsics_, options));
}

LocalMapTrackResult RgbdFrontend::TrackAgainstLocalMap(const Frame& current,
                                                       const Pose3& odom_camera) const {
  const LocalMapPoints map = BuildLocalMap(options_.local_map.keyframes);
  const std::vector<double> sigma = PixelSigmas(current);
  // Keypoints in a dynamic region (carried into the frame, or found by its registration's
  // depth residuals) are never matched.
  std::vector<uint8_t> usable(current.features.size(), 1);
  for (size_t i = 0; i < usable.size(); ++i) {
    usable[i] = (current.excluded.empty() || !current.excluded[i]) &&
                !current.dynamic.Contains(current.features.keypoints[i].pt);
  }
  LocalMapOptions options = options_.local_map;
  options.depth_abs_m = options_.registration.inlier_threshold_m;
  options.depth_rel_per_m = options_.registration.reprojection_depth_rel_per_m;
  return TrackLocalMap(map, current.features.keypoints, current.features.descriptors, sigma,
                       usable, current.depth_m, odom_camera, intrinsics_, options);
}

bool RgbdFrontend::AveragedTimingVelocity() const {
  return options_.depth_timing_averaged_velocity && options_.velocity_prior_steps > 1;
}

void RgbdFrontend::RememberPrevious(const std::optional<Pose3>& vision_pose) {
  if (options_.velocity_prior_steps <= 1) return;
  if (options_.velocity_prior_skip_origin && first_keyframe_index_ &&
      previous_->index == *first_keyframe_index_) {
    return;
  }
  velocity_history_.Add(previous_->stamp, options_.velocity_from_vision && vision_pose
                                              ? *vision_pose
                                              : previous_->odom_camera);
  if (options_.motion_prior_release_registered_velocity) {
    registered_velocity_history_.Add(previous_->stamp, registered_track_);
  }
}

bool RgbdFrontend::NeedsNewKeyframe(const Attempt& attempt, const Frame& current) const {
  const RegistrationResult& r = attempt.registration;
  if (static_cast<int>(r.inliers) < options_.keyframe_min_inliers) return true;
  if (r.inlier_ratio < options_.keyframe_min_inlier_ratio) return true;
  if (current.index - reference_since_ >= static_cast<size_t>(options_.max_keyframe_interval_phi)) {
    return true;
  }
  if (TranslationNorm(r.relative_pose) > options_.keyframe_max_translation_m) return true;
  return RotationAngleRad(r.relative_pose) * 180.0 / M_PI > options_.keyframe_max_rotation_deg;
}

std::optional<Pose3> RgbdFrontend::AdjustWithKeyframes(const Frame& current,
                                                       const Pose3& odom_camera) const {
  const KeyframeBaOptions& ba = options_.keyframe_ba;
  const size_t older = static_cast<size_t>(ba.keyframes - 1);
  if (window_.size() < 2) return std::nullopt;
  // The window keyframes, newest first: each at least min_spacing_* from the one picked after
  // it (the current frame first).
  std::vector<const Frame*> frames;
  Pose3 last = odom_camera;
  for (auto it = window_.rbegin(); it != window_.rend() && frames.size() < older; ++it) {
    const Pose3 d = Between((*it)->odom_camera, last);
    const bool spaced =
        (ba.min_spacing_m <= 0.0 && ba.min_spacing_deg <= 0.0) ||
        (ba.min_spacing_m > 0.0 && TranslationNorm(d) >= ba.min_spacing_m) ||
        (ba.min_spacing_deg > 0.0 && RotationAngleRad(d) * 180.0 / M_PI >= ba.min_spacing_deg);
    if (!spaced) continue;
    frames.push_back(it->get());
    last = (*it)->odom_camera;
  }
  if (frames.size() < 2) return std::nullopt;
  std::reverse(frames.begin(), frames.end());
  frames.push_back(&current);
  std::vector<KeyframeBaView> views(frames.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    const Frame& fr = *frames[f];
    KeyframeBaView& v = views[f];
    v.odom_camera = f + 1 < frames.size() ? fr.odom_camera : odom_camera;
    for (size_t g = 0; g < f && fr.link_reference; ++g) {
      if (frames[g]->index != *fr.link_reference) continue;
      v.link_from = static_cast<int>(g);
      v.link_relative = fr.link_relative;
      v.link_covariance = fr.link_covariance;
    }
    v.descriptors = fr.features.descriptors;
    v.binary = fr.features.binary;
    for (const cv::KeyPoint& k : fr.features.keypoints) {
      v.pixels_px.push_back(k.pt);
      v.pixel_sigma_px.push_back(PixelSigma(k));
    }
    std::vector<uint8_t> lifted;
    KeypointsToPoints(v.pixels_px, fr.depth_m, intrinsics_, options_.registration.depth,
                      &v.points_camera, &lifted);
    for (size_t i = 0; i < lifted.size(); ++i) {
      if (!lifted[i]) v.points_camera[i].setConstant(std::numeric_limits<double>::quiet_NaN());
    }
    // Verified static only: keyframes keep only features outside their dynamic regions, but
    // walkers may have been seen leaving some since (votes); the current frame's carried and
    // own dynamic regions are left out.
    v.usable.assign(v.pixels_px.size(), 1);
    for (size_t i = 0; i < v.usable.size(); ++i) {
      if (i < fr.dynamic_votes.size() && fr.dynamic_votes[i] >= options_.reference_dynamic_votes) {
        v.usable[i] = 0;
      }
      if (f + 1 == frames.size()) {
        v.usable[i] = (fr.excluded.empty() || !fr.excluded[i]) &&
                      !fr.dynamic.Contains(fr.features.keypoints[i].pt);
      }
    }
  }
  KeyframeBaOptions options = ba;
  options.depth_abs_m = options_.registration.inlier_threshold_m;
  options.depth_rel_per_m = options_.registration.reprojection_depth_rel_per_m;
  const KeyframeBaResult r = AdjustKeyframes(views, intrinsics_, options);
  if (!r.status.ok()) return std::nullopt;
  for (size_t f = 0; f + 1 < frames.size(); ++f) frames[f]->odom_camera = r.odom_camera[f];
  return r.odom_camera.back();
}

std::optional<RgbdFrontend::AnchorEstimate> RgbdFrontend::RegisterToAnchors(
    const Frame& current, StageTimes* times) const {
  for (const auto& anchor : anchors_) {
    const Attempt a = RegisterTo(*anchor, current, times);
    if (!a.ok() || static_cast<int>(a.registration.inliers) < options_.anchor.min_inliers) continue;
    return AnchorEstimate{anchor->odom_camera * a.registration.relative_pose,
                          static_cast<int>(a.registration.inliers)};
  }
  return std::nullopt;
}

KeyframePtr RgbdFrontend::MakeKeyframe(const Frame& frame, const cv::Mat& bgr,
                                       const Attempt* attempt, MotionSource source) {
  auto kf = std::make_shared<FrontendKeyframe>();
  kf->id = num_keyframes_++;
  kf->frame_index = frame.index;
  if (!first_keyframe_index_) first_keyframe_index_ = frame.index;
  kf->stamp = frame.stamp;
  kf->odom_camera = frame.odom_camera;
  kf->odom_base = frame.odom_camera * options_.fusion.base_to_camera.inverse();
  if (keyframe_) {
    kf->relative_pose = Between(keyframe_->odom_camera, frame.odom_camera);
    kf->relative_source = source;
    Pose3 wheel_motion;
    if (wheel_.RelativeMotion(keyframe_->stamp, frame.stamp, &wheel_motion).ok()) {
      kf->wheel_camera_motion = CameraMotionFromBase(wheel_motion, options_.fusion.base_to_camera);
    }
  }
  if (attempt && attempt->ok() && source == MotionSource::kVision) {
    kf->covariance = attempt->registration.covariance;
  }
  kf->features = frame.features;
  std::vector<cv::Point2f> pixels;
  pixels.reserve(frame.features.size());
  for (const cv::KeyPoint& k : frame.features.keypoints) pixels.push_back(k.pt);
  std::vector<uint8_t> valid;
  KeypointsToPoints(pixels, frame.depth_m, intrinsics_, options_.registration.depth, &kf->points_m,
                    &valid);
  for (size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) kf->points_m[i].setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  kf->robust = attempt ? attempt->robust : std::vector<uint8_t>(frame.features.size(), 0);
  kf->bgr = bgr;
  kf->depth_m = frame.depth_m;
  keyframe_ = kf;
  reference_ = std::make_shared<const Frame>(frame);
  reference_since_ = frame.index;
  if (options_.anchor.keyframes > 0 && !anchors_closed_) {
    const int inliers =
        attempt && attempt->ok() ? static_cast<int>(attempt->registration.inliers) : 0;
    if (QualifiesAsAnchor(options_.anchor, static_cast<int>(anchors_.size()),
                          kf->id == 0 ? nullptr : &inliers)) {
      anchors_.push_back(reference_);
    } else {
      anchors_closed_ = true;
    }
  }
  if (options_.keyframe_window > 0) {
    window_.push_back(reference_);
    while (window_.size() > static_cast<size_t>(options_.keyframe_window)) window_.pop_front();
  }
  if (keyframe_callback_) keyframe_callback_(keyframe_);
  return kf;
}

std::vector<std::shared_ptr<const RgbdFrontend::Frame>> RgbdFrontend::NearbyKeyframes(
    const Pose3& predicted) const {
  std::vector<std::pair<double, std::shared_ptr<const Frame>>> near;
  for (const auto& kf : window_) {
    if (kf == reference_) continue;
    const Pose3 d = Between(kf->odom_camera, predicted);
    const double t = TranslationNorm(d);
    const double r_deg = RotationAngleRad(d) * 180.0 / M_PI;
    if (t > options_.revisit_max_translation_m || r_deg > options_.revisit_max_rotation_deg) {
      continue;
    }
    near.emplace_back(
        t / options_.revisit_max_translation_m + r_deg / options_.revisit_max_rotation_deg, kf);
  }
  std::sort(near.begin(), near.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::shared_ptr<const Frame>> out;
  out.reserve(near.size());
  for (auto& n : near) out.push_back(std::move(n.second));
  return out;
}

RgbdFrontend::Attempt RgbdFrontend::RegisterToNearbyKeyframe(
    const Frame& current, const Pose3& predicted, StageTimes* times,
    std::shared_ptr<const Frame>* chosen) const {
  // Earlier keyframes whose pose is close to the predicted one, nearest first.
  const auto near = NearbyKeyframes(predicted);
  const size_t tries = std::min(near.size(), static_cast<size_t>(options_.revisit_attempts));
  for (size_t i = 0; i < tries; ++i) {
    Attempt a = RegisterTo(*near[i], current, times);
    if (a.ok() && static_cast<int>(a.registration.inliers) >= options_.keyframe_min_inliers &&
        AgreesWithReference(predicted, near[i]->odom_camera * a.registration.relative_pose)) {
      *chosen = near[i];
      return a;
    }
  }
  chosen->reset();
  return Attempt();
}

Pose3 RgbdFrontend::FuseWithNearbyKeyframes(const Frame& current, const Pose3& primary_pose,
                                            const Attempt& primary, int max_references,
                                            StageTimes* times,
                                            std::vector<PoseLink>* links) const {
  const auto near = NearbyKeyframes(primary_pose);
  if (options_.select_across_references && primary.reference) {
    return SelectAcrossReferences(current, primary_pose, primary, near, max_references, times);
  }
  const Pose3& predicted = primary_pose;
  const Mat6& covariance = primary.registration.covariance;
  if (links) links->push_back({primary_pose, covariance});
  // Information-weighted mean in the tangent space at `predicted` (right perturbation in the
  // current camera frame, the registration covariance convention); the keyframe poses are
  // taken as exact, so only the registration noise of each link is averaged.
  Eigen::LDLT<Mat6> ldlt(covariance);
  if (ldlt.info() != Eigen::Success || !covariance.allFinite()) return predicted;
  Mat6 info_sum = ldlt.solve(Mat6::Identity());
  Eigen::Matrix<double, 6, 1> weighted = Eigen::Matrix<double, 6, 1>::Zero();
  const size_t tries = std::min(near.size(), static_cast<size_t>(max_references));
  for (size_t i = 0; i < tries; ++i) {
    const Attempt a = RegisterTo(*near[i], current, times);
    if (!a.ok() || static_cast<int>(a.registration.inliers) < options_.keyframe_min_inliers / 2) {
      continue;
    }
    const Pose3 estimate = near[i]->odom_camera * a.registration.relative_pose;
    if (!AgreesWithReference(predicted, estimate)) continue;
    const Eigen::Matrix<double, 6, 1> delta = LogSE3(Between(predicted, estimate));
    const Mat6& c = a.registration.covariance;
    Eigen::LDLT<Mat6> l(c);
    if (l.info() != Eigen::Success || !c.allFinite() || !delta.allFinite()) continue;
    const Mat6 info = l.solve(Mat6::Identity());
    if (links) links->push_back({estimate, c});
    info_sum += info;
    weighted += info * delta;
  }
  const Eigen::Matrix<double, 6, 1> mean = info_sum.ldlt().solve(weighted);
  if (!mean.allFinite()) return predicted;
  return Orthonormalized(predicted * ExpSE3(mean));
}

Pose3 RgbdFrontend::SelectAcrossReferences(
    const Frame& current, const Pose3& primary_pose, const Attempt& primary,
    const std::vector<std::shared_ptr<const Frame>>& near, int max_references,
    StageTimes* times) const {
  // The registrations of this frame: to its reference and to up to max_references nearby
  // keyframes, each with its hypotheses (T_odom_cur candidates).
  struct Link {
    const Frame* reference;
    std::vector<const RegistrationResult*> hypotheses;  // the registration's choice first
  };
  std::vector<Attempt> extra;
  extra.reserve(near.size());
  const size_t tries = std::min(near.size(), static_cast<size_t>(max_references));
  for (size_t i = 0; i < tries; ++i) {
    Attempt a = RegisterTo(*near[i], current, times);
    if (a.ok() && static_cast<int>(a.registration.inliers) >= options_.keyframe_min_inliers / 2) {
      extra.push_back(std::move(a));
    }
  }
  std::vector<Link> links;
  const auto add_link = [&](const Attempt& a) {
    Link link{a.reference, {&a.registration}};
    for (const RegistrationResult& r : a.alternatives) link.hypotheses.push_back(&r);
    links.push_back(std::move(link));
  };
  add_link(primary);
  for (const Attempt& a : extra) add_link(a);
  // Judges: every reference registered to, and the previous frame. The static scene agrees
  // with the camera's true motion in all of them; walkers stand elsewhere in each, so a motion
  // that follows a walker in one reference disagrees with the others (persistence).
  std::vector<const Frame*> judges;
  for (const Link& l : links) judges.push_back(l.reference);
  if (previous_ && std::find(judges.begin(), judges.end(), previous_.get()) == judges.end() &&
      std::none_of(judges.begin(), judges.end(),
                   [&](const Frame* f) { return f->index == previous_->index; })) {
    judges.push_back(previous_.get());
  }
  const auto t0 = Clock::now();
  const auto evidence = [&](const Pose3& odom_cur) {
    const HypothesisEvidence e =
        AgreementWithJudges(judges, current, odom_cur, options_.depth_consistency);
    return e.depth_agreeing + e.edges_agreeing;
  };
  Pose3 best = primary_pose;
  size_t best_evidence = 0;
  for (const Link& l : links) {
    for (const RegistrationResult* h : l.hypotheses) {
      const Pose3 candidate = l.reference->odom_camera * h->relative_pose;
      const size_t e = evidence(candidate);
      if (e > best_evidence) {
        best_evidence = e;
        best = candidate;
      }
    }
  }
  times->registration_ms += MsSince(t0);
  // Information-weighted mean of the links' hypotheses that agree with the winner (one per
  // link, the nearest), in the tangent space at the winner.
  Mat6 info_sum = Mat6::Zero();
  Eigen::Matrix<double, 6, 1> weighted = Eigen::Matrix<double, 6, 1>::Zero();
  for (const Link& l : links) {
    const RegistrationResult* nearest = nullptr;
    double nearest_distance = INFINITY;
    for (const RegistrationResult* h : l.hypotheses) {
      const Pose3 estimate = l.reference->odom_camera * h->relative_pose;
      if (!AgreesWithReference(best, estimate)) continue;
      const Pose3 d = Between(best, estimate);
      const double distance = TranslationNorm(d) + RotationAngleRad(d) * 0.1;
      if (distance < nearest_distance) {
        nearest_distance = distance;
        nearest = h;
      }
    }
    if (!nearest) continue;
    const Eigen::Matrix<double, 6, 1> delta =
        LogSE3(Between(best, l.reference->odom_camera * nearest->relative_pose));
    Eigen::LDLT<Mat6> ldlt(nearest->covariance);
    if (ldlt.info() != Eigen::Success || !nearest->covariance.allFinite() || !delta.allFinite()) {
      continue;
    }
    const Mat6 info = ldlt.solve(Mat6::Identity());
    info_sum += info;
    weighted += info * delta;
  }
  const Eigen::Matrix<double, 6, 1> mean = info_sum.ldlt().solve(weighted);
  if (!mean.allFinite() || info_sum.isZero()) return best;
  return Orthonormalized(best * ExpSE3(mean));
}

Pose3 RgbdFrontend::FuseWithPrediction(const Pose3& predicted, const Pose3& measured,
                                       const Mat6& covariance, double sigma_scale) const {
  const std::optional<Mat6> measured_info = Information(covariance);
  if (!measured_info) return measured;
  const double st = options_.motion_prior_sigma_m * sigma_scale;
  const double sr = options_.motion_prior_sigma_deg * sigma_scale * M_PI / 180.0;
  Eigen::Matrix<double, 6, 1> prior_info;
  prior_info << 1 / (st * st), 1 / (st * st), 1 / (st * st), 1 / (sr * sr), 1 / (sr * sr),
      1 / (sr * sr);
  return InformationWeightedMean(predicted, Mat6(prior_info.asDiagonal()), measured, *measured_info)
      .value_or(measured);
}

bool RgbdFrontend::AgreesWithReference(const Pose3& primary, const Pose3& other) const {
  const Pose3 d = Between(primary, other);
  const double m = options_.reference_agreement_m, deg = options_.reference_agreement_deg;
  return (m <= 0.0 || TranslationNorm(d) <= m) &&
         (deg <= 0.0 || RotationAngleRad(d) * 180.0 / M_PI <= deg);
}

std::optional<Pose3> RgbdFrontend::VelocityRebaseAtKeyframe(const Frame& current,
                                                            const Attempt& attempt,
                                                            const Pose3& registered_pose,
                                                            size_t frames_since_reference) {
  if (options_.velocity_rebase_at_keyframe <= 0.0 || !options_.velocity_from_vision) {
    return std::nullopt;
  }
  // T_fused_registered as a world-frame correction, the chosen share of it.
  const Pose3 offset = current.odom_camera * registered_pose.inverse();
  const Vec3 offset_m = offset.translation();
  bool rebase = true;
  if (options_.velocity_rebase_persistent_deg > 0.0) {
    rebase = last_rebase_offset_m_ && offset_m.norm() > 0.0 &&
             last_rebase_offset_m_->norm() > 0.0 &&
             offset_m.dot(*last_rebase_offset_m_) >
                 std::cos(options_.velocity_rebase_persistent_deg * M_PI / 180.0) *
                     offset_m.norm() * last_rebase_offset_m_->norm();
    last_rebase_offset_m_ = offset_m;
  }
  const bool over_limit = options_.velocity_rebase_max_m_per_frame > 0.0 &&
                          offset_m.norm() / static_cast<double>(frames_since_reference) >
                              options_.velocity_rebase_max_m_per_frame;
  if (over_limit && !options_.velocity_rebase_evidence_overrides_limit) rebase = false;
  // Asked where it confirms every rebase, or (overrides_limit) where the limit turned it away.
  if (rebase && (options_.velocity_rebase_evidence_confirm || over_limit)) {
    rebase = attempt.reference &&
             RegisteredPoseExplainsMore(current, *attempt.reference, registered_pose);
  }
  if (!rebase) return std::nullopt;
  Vec6 share = Vec6::Constant(options_.velocity_rebase_at_keyframe);
  if (options_.velocity_rebase_by_covariance) {
    const Mat6& c = attempt.registration.covariance;
    const double prior_m2 = options_.motion_prior_sigma_m * options_.motion_prior_sigma_m;
    const double prior_rad = options_.motion_prior_sigma_deg * M_PI / 180.0;
    const double var_m2 = c.topLeftCorner<3, 3>().trace() / 3.0;
    const double var_rad2 = c.bottomRightCorner<3, 3>().trace() / 3.0;
    share.head<3>() *= prior_m2 / (prior_m2 + var_m2);
    share.tail<3>() *= prior_rad * prior_rad / (prior_rad * prior_rad + var_rad2);
  }
  return ExpSE3(share.cwiseProduct(LogSE3(offset)));
}

bool RgbdFrontend::RegisteredPoseExplainsMore(const Frame& current, const Frame& reference,
                                              const Pose3& registered_pose) const {
  DepthConsistencyOptions judged = options_.depth_consistency;
  judged.min_depth_m = std::max(judged.min_depth_m, options_.evidence_min_depth_m);
  std::vector<const Frame*> judges = {&reference};
  if (previous_ && previous_->index != reference.index && !previous_->depth_m.empty()) {
    judges.push_back(previous_.get());
  }
  const std::vector<double> score =
      EvidenceScores({AgreementWithJudges(judges, current, registered_pose, judged),
                      AgreementWithJudges(judges, current, current.odom_camera, judged)},
                     true);
  return score[0] > score[1];
}

HypothesisEvidence RgbdFrontend::AgreementWithJudges(const std::vector<const Frame*>& judges,
                                                     const Frame& current, const Pose3& odom_cur,
                                                     const DepthConsistencyOptions& options) const {
  HypothesisEvidence e;
  for (const Frame* j : judges) {
    const Pose3 judge_cur = j->odom_camera.inverse() * odom_cur;
    e.depth_agreeing +=
        CheckDepthConsistency(j->depth_m, current.depth_m, judge_cur, intrinsics_, options)
            .agreeing;
    e.edges_agreeing += CheckEdgeConsistency(j->grey, current.grey, current.depth_m, judge_cur,
                                             intrinsics_, options)
                            .agreeing;
  }
  return e;
}

double RgbdFrontend::DepthTimeOffsetS(Time stamp, Time depth_stamp) const {
  if (!options_.compensate_depth_timing) return 0.0;
  return icgm::DepthTimeOffsetS(stamp, depth_stamp, intrinsics_, options_.depth_timing_min_s);
}

FrontendFrameResult RgbdFrontend::ProcessFrame(Time stamp, const cv::Mat& bgr_input,
                                               const cv::Mat& depth_input,
                                               std::optional<Time> depth_stamp) {
  return Process(stamp, bgr_input, depth_input, nullptr, depth_stamp);
}

FrontendFrameResult RgbdFrontend::ProcessFeatures(Time stamp, FeatureSet features,
                                                  const cv::Mat& depth_m,
                                                  std::optional<Time> depth_stamp,
                                                  const cv::Mat& bgr,
                                                  bool keypoints_undistorted) {
  return Process(stamp, bgr, depth_m, &features, depth_stamp, keypoints_undistorted);
}

FrontendFrameResult RgbdFrontend::Process(Time stamp, const cv::Mat& bgr_input,
                                          const cv::Mat& depth_input, FeatureSet* features,
                                          std::optional<Time> depth_stamp,
                                          bool keypoints_undistorted) {
  const auto t_start = Clock::now();
  FrontendFrameResult out;
  out.frame_index = frame_count_++;
  out.stamp = stamp;
  const auto ignored = [&](const std::string& why) {
    out.status = Status::Error(why + "; frame ignored");
    out.odom_camera = fusion_.odom_camera();
    out.odom_base = fusion_.odom_base();
    return out;
  };
  if (has_stamp_ && stamp <= last_stamp_) {
    return ignored("frame stamp " + stamp.ToString() + " not after the previous " +
                   last_stamp_.ToString());
  }
  // A stamp far ahead of the previous one is believed only once a second frame follows it
  // closely: a single wrong stamp must not make every later frame look old.
  if (has_stamp_ && DurationSeconds(stamp, last_stamp_) > options_.max_stamp_jump_s) {
    const bool confirmed = stamp_jump_ && stamp > *stamp_jump_ &&
                           DurationSeconds(stamp, *stamp_jump_) <= options_.max_stamp_jump_s;
    if (!confirmed) {
      stamp_jump_ = stamp;
      return ignored("frame stamp " + stamp.ToString() + " jumps " +
                     std::to_string(DurationSeconds(stamp, last_stamp_)) +
                     " s ahead of the previous; held until a following frame confirms it");
    }
  }
  stamp_jump_.reset();
  has_stamp_ = true;
  last_stamp_ = stamp;

  // Pinhole model from here on (the caller's images are left as they are); features extracted
  // elsewhere on the raw image have their keypoints moved instead.
  auto t0 = Clock::now();
  const cv::Mat bgr = undistortion_.Colour(bgr_input);
  cv::Mat depth_m = undistortion_.Depth(depth_input);
  if (features && !keypoints_undistorted) undistortion_.MoveKeypoints(&features->keypoints);
  depth_m = CorrectedDepth(depth_m, intrinsics_);
  // Depth (and below, a rolling shutter's keypoints) at the colour stamp's instant: first with
  // the velocity of the previous step; a keyframe's again below with the velocity of this
  // frame's step, once registered.
  const cv::Mat depth_as_captured = depth_m;
  const double depth_dt_s = depth_m.type() == CV_32FC1 && previous_
                                ? DepthTimeOffsetS(stamp, depth_stamp.value_or(stamp))
                                : 0.0;
  std::optional<Vec6> prior_twist;
  const bool recent_previous =
      previous_ && DurationSeconds(stamp, previous_->stamp) <= options_.depth_timing_max_gap_s;
  if (recent_previous && AveragedTimingVelocity()) prior_twist = velocity_history_.Twist();
  if (!prior_twist && recent_previous && before_previous_) {
    prior_twist = VelocityTwist(before_previous_->first, before_previous_->second, previous_->stamp,
                                previous_->odom_camera, options_.depth_timing_max_gap_s);
  }
  if (prior_twist && depth_m.type() == CV_32FC1) {
    depth_m = DepthAtStamp(depth_m, intrinsics_, depth_dt_s, *prior_twist);
  }
  out.times.undistort_ms = MsSince(t0);
  Frame cur;
  cur.index = out.frame_index;
  cur.stamp = stamp;
  if (bgr.empty() && !features) out.status = Status::Error("empty colour image");
  const cv::Size camera_size(intrinsics_.width_px, intrinsics_.height_px);
  if (!depth_m.empty() && depth_m.type() == CV_32FC1 && depth_m.size() == camera_size) {
    cur.depth_m = depth_m;
  } else if (out.status.ok()) {
    out.status =
        Status::Error(depth_m.empty() || depth_m.type() != CV_32FC1
                          ? "depth image missing or not CV_32FC1 metres"
                          : "depth image " + std::to_string(depth_m.cols) + "x" +
                                std::to_string(depth_m.rows) + " differs from the camera's " +
                                std::to_string(camera_size.width) + "x" +
                                std::to_string(camera_size.height) + " (camera_info)");
  }
  t0 = Clock::now();
  if ((options_.select_by_evidence || options_.dense_refinement) && !bgr.empty() &&
      bgr.depth() == CV_8U) {
    if (bgr.channels() == 3) {
      cv::cvtColor(bgr, cur.grey, cv::COLOR_BGR2GRAY);
    } else if (bgr.channels() == 1) {
      cur.grey = bgr;
    }
  }
  if (features) {
    cur.features = std::move(*features);
  } else if (!bgr.empty()) {
    cur.features = extractor_->Extract(bgr);
  }
  const bool rolling_shutter = HasRollingShutter(intrinsics_);
  const std::vector<cv::KeyPoint> keypoints_as_captured =
      rolling_shutter ? cur.features.keypoints : std::vector<cv::KeyPoint>();
  if (prior_twist) {
    KeypointsAtStamp(intrinsics_, *prior_twist, cur.depth_m, &cur.features.keypoints);
  }
  out.times.features_ms = MsSince(t0);
  out.num_features = cur.features.size();

  const bool usable = cur.features.size() >= 3 && !cur.depth_m.empty();
  if (!fusion_.initialized()) {
    t0 = Clock::now();
    fusion_.Update(stamp, nullptr, &wheel_);
    out.times.fusion_ms = MsSince(t0);
    cur.odom_camera = fusion_.odom_camera();
    out.odom_camera = cur.odom_camera;
    out.odom_base = fusion_.odom_base();
    out.registration.status = Status::Error("first frame");
    if (usable) {
      MakeKeyframe(cur, bgr, nullptr, MotionSource::kNone);
      out.new_keyframe = true;
    }
    registered_track_ = cur.odom_camera;
    previous_ = std::make_unique<Frame>(cur);
    RememberPrevious();
    if (WindowOn()) pose_window_.Add(stamp, {}, cur.odom_camera);
    out.times.total_ms = MsSince(t_start);
    return out;
  }

  // Vision: to the keyframe, else to the previous frame.
  const Pose3 odom_prev = fusion_.odom_camera();
  // Predicted motion: the wheels', else (velocity_prior) the last steps' constant velocity.
  // It serves ICGM's motion prior, the evidence choice and the carried dynamic mask.
  Pose3 predicted_step = Pose3::Identity();
  MotionSource predicted_by = fusion_.Predict(stamp, &wheel_, &predicted_step);
  if (predicted_by == MotionSource::kConstantVelocity && options_.velocity_prior_steps > 1) {
    // The velocity over the last velocity_prior_steps steps instead of the last one.
    if (const std::optional<Pose3> averaged = velocity_history_.PredictStep(stamp)) {
      predicted_step = *averaged;
    } else if (options_.velocity_prior_skip_origin && velocity_history_.size() < 2) {
      predicted_by = MotionSource::kNone;  // the fusion's last step would start from the origin
    }
    // Released (registered to the previous frame, as the frames before): the velocity of the
    // registered steps alone.
    if (options_.motion_prior_release_registered_velocity &&
        options_.motion_prior_release_frames > 0 && reference_ &&
        reference_->index == previous_->index &&
        previous_referenced_in_row_ + 1 >= options_.motion_prior_release_frames) {
      if (const std::optional<Pose3> registered = registered_velocity_history_.PredictStep(stamp)) {
        predicted_step = *registered;
        out.motion_prior_released = true;
      }
    }
  }
  // Velocity gate: a predicted step faster than a hand moves (from the history or, when it
  // cannot predict, the fusion's last step) is no prior for this frame.
  if (predicted_by == MotionSource::kConstantVelocity &&
      !WithinSpeed(predicted_step, DurationSeconds(stamp, fusion_.stamp()),
                   options_.velocity_gate.max_speed_mps)) {
    predicted_by = MotionSource::kNone;
    out.velocity_gate_dropped_prior = true;
  }
  if (predicted_by == MotionSource::kWheel ||
      (predicted_by == MotionSource::kConstantVelocity && options_.velocity_prior)) {
    cur.predicted_odom_camera = odom_prev * predicted_step;
  }
  if (options_.dynamic_masking && previous_ && !previous_->dynamic.empty()) {
    const Pose3 cur_prev = cur.predicted_odom_camera ? predicted_step.inverse() : Pose3::Identity();
    const DynamicMask carried = PropagateDynamicMask(previous_->dynamic, previous_->depth_m,
                                                     cur_prev, intrinsics_,
                                                     options_.mask_growth_cells);
    cur.excluded.assign(cur.features.size(), 0);
    for (size_t i = 0; i < cur.features.size(); ++i) {
      cur.excluded[i] = carried.Contains(cur.features.keypoints[i].pt);
    }
    cur.carried = carried;
  }
  // Map hypothesis: the frame located among the last keyframes' static points, no start pose.
  if (options_.map_hypothesis.keyframes > 0 && options_.select_by_evidence && reference_ &&
      usable) {
    const auto t_map = Clock::now();
    cur.map_hypothesis = LocateInMap(cur, cur.predicted_odom_camera.value_or(odom_prev));
    out.times.registration_ms += MsSince(t_map);
  }
  // Anchors: the frame also registered to the run's first keyframes (not when its reference is
  // one); their estimate does not carry the chain's drift.
  std::optional<AnchorEstimate> anchor_estimate;
  if (!anchors_.empty() && usable && reference_ && !IsAnchor(reference_)) {
    anchor_estimate = RegisterToAnchors(cur, &out.times);
    // ... offered to the evidence choice: the frame pair's matches that agree with it.
    if (anchor_estimate && options_.anchor.hypothesis && options_.select_by_evidence &&
        !cur.map_hypothesis) {
      auto located = std::make_shared<MapHypothesis>();
      located->odom_camera = anchor_estimate->odom_camera;
      located->inliers = static_cast<size_t>(anchor_estimate->inliers);
      cur.map_hypothesis = std::move(located);
    }
  }
  Attempt attempt;
  bool to_previous = false;
  std::optional<Pose3> vision_prev_cur;
  std::vector<PoseLink> window_links;  // the frame's registration links (window, agreement)
  if (reference_) {
    attempt = RegisterTo(*reference_, cur, &out.times);
    if (attempt.ok()) {
      vision_prev_cur = Orthonormalized(odom_prev.inverse() * reference_->odom_camera *
                                        attempt.registration.relative_pose);
    }
  }
  if (!vision_prev_cur && options_.retry_previous_frame && previous_ &&
      (!reference_ || previous_->index != reference_->index)) {
    Attempt retry = RegisterTo(*previous_, cur, &out.times);
    if (retry.ok() || !reference_) {
      attempt = std::move(retry);
      to_previous = true;
      if (attempt.ok()) vision_prev_cur = attempt.registration.relative_pose;
    }
  }
  // Keyframe policy: a weak or old registration to the reference asks for a new one; a nearby
  // earlier keyframe of the window is preferred over starting a new link of the chain.
  bool new_keyframe = false;
  if (vision_prev_cur && !to_previous) {
    new_keyframe = NeedsNewKeyframe(attempt, cur);
    if (new_keyframe) {
      const Pose3 predicted = odom_prev * *vision_prev_cur;
      std::shared_ptr<const Frame> revisit;
      Attempt better = RegisterToNearbyKeyframe(cur, predicted, &out.times, &revisit);
      if (revisit) {
        attempt = std::move(better);
        vision_prev_cur = Orthonormalized(odom_prev.inverse() * revisit->odom_camera *
                                          attempt.registration.relative_pose);
        reference_ = revisit;
        reference_since_ = cur.index;
        out.revisited_keyframe = true;
        new_keyframe = false;
      }
    }
    const int extra =
        new_keyframe ? options_.keyframe_extra_references : options_.frame_extra_references;
    if (extra > 0) {
      const Pose3 fused = FuseWithNearbyKeyframes(cur, odom_prev * *vision_prev_cur, attempt,
                                                  extra, &out.times,
                                                  WindowOn() || AgreementOn() ? &window_links
                                                                              : nullptr);
      vision_prev_cur = Orthonormalized(odom_prev.inverse() * fused);
    }
  } else {
    // Registered to the previous frame only, or not at all: the reference is stale; restart
    // the chain from this frame if it can serve as a reference.
    new_keyframe = usable;
  }
  // Prior gate: a registered step far from the constant-velocity prediction gives way to it.
  // Near-set gate: the chosen consistent set lies in front of the room (a walker's).
  bool gated = false, near_gated = false;
  if ((options_.prior_gate_deg > 0.0 || options_.prior_gate_near_m > 0.0) && vision_prev_cur &&
      cur.predicted_odom_camera && predicted_by == MotionSource::kConstantVelocity &&
      prior_gated_in_row_ < options_.prior_gate_max_frames) {
    const Pose3 off = predicted_step.inverse() * *vision_prev_cur;
    gated = options_.prior_gate_deg > 0.0 &&
            (RotationAngleRad(off) * 180.0 / M_PI > options_.prior_gate_deg ||
             (options_.prior_gate_m > 0.0 && TranslationNorm(off) > options_.prior_gate_m));
    near_gated = !gated && !to_previous &&
                 ChosenSetNearerThan(attempt.judged, attempt.chosen, options_.prior_gate_near_m);
    gated = gated || near_gated;
  }
  prior_gated_in_row_ = gated ? prior_gated_in_row_ + 1 : 0;
  if (gated) {
    vision_prev_cur = predicted_step;
    // prior_gate_near_keyframes: a near-gated frame may still become a keyframe (at the
    // predicted pose).
    new_keyframe = new_keyframe && near_gated && options_.prior_gate_near_keyframes;
    out.prior_gated = true;
  }
  // Velocity gate: a registered step a hand cannot make (a walker carried the registration)
  // gives way to the prediction, or, without one, to standing still; it then joins neither the
  // velocity history nor the keyframes (as a prior-gated step).
  if (options_.velocity_gate.on() && vision_prev_cur && !gated &&
      velocity_gate_rejected_in_row_ < options_.velocity_gate_max_rejected) {
    const bool predicted = cur.predicted_odom_camera.has_value();
    out.velocity_gate_rejected =
        !CheckHandMotion(*vision_prev_cur, DurationSeconds(stamp, fusion_.stamp()),
                         predicted ? &predicted_step : nullptr, options_.velocity_gate)
             .ok();
    if (out.velocity_gate_rejected) {
      vision_prev_cur = predicted ? predicted_step : Pose3::Identity();
      new_keyframe = false;
      gated = true;
    }
  }
  velocity_gate_rejected_in_row_ =
      out.velocity_gate_rejected ? velocity_gate_rejected_in_row_ + 1 : 0;
  // Registration agreement: the frame's registrations (reference, nearby keyframes) agree.
  std::optional<RegistrationAgreement> agreement;
  if (AgreementOn() && vision_prev_cur && !gated && !to_previous) {
    agreement = CompareRegistrations(window_links, options_.registration_agreement);
    if (agreement) out.registration_spread_m = agreement->spread_m;
    if (agreement && !agreement->agree) agreement.reset();
  }
  out.registrations_agreed = agreement.has_value();
  // ... a new keyframe waits while they disagree (its pose would be the prediction's).
  out.keyframe_postponed = new_keyframe && !agreement && vision_prev_cur && !to_previous &&
                           !gated && attempt.ok() &&
                           keyframes_postponed_in_row_ < options_.agreement_keyframe_max_postponed;
  if (out.keyframe_postponed) new_keyframe = false;
  keyframes_postponed_in_row_ = out.keyframe_postponed ? keyframes_postponed_in_row_ + 1 : 0;
  if (vision_prev_cur && !to_previous && attempt.reference && !gated) {
    cur.link_reference = attempt.reference->index;
    cur.link_relative = attempt.registration.relative_pose;
    cur.link_covariance = attempt.registration.covariance;
  }
  // Dynamic regions of this frame from the depth residuals of its registration; what the
  // walkers left in the reference collects votes against its keypoints.
  if (options_.dynamic_masking && vision_prev_cur && attempt.reference) {
    const Frame& ref = *attempt.reference;
    const Pose3 ref_cur = ref.odom_camera.inverse() * odom_prev * *vision_prev_cur;
    DynamicMask left;
    CheckDepthConsistency(ref.depth_m, cur.depth_m, ref_cur, intrinsics_,
                          options_.depth_consistency, &cur.dynamic, &left);
    if (!left.empty()) {
      ref.dynamic_votes.resize(ref.features.size(), 0);
      for (size_t i = 0; i < ref.features.size(); ++i) {
        if (left.Contains(ref.features.keypoints[i].pt)) ++ref.dynamic_votes[i];
      }
    }
  }
  // Local map: the registered pose refined against the last keyframes' static points, with
  // this frame's own dynamic regions (just found) left out.
  if (options_.local_map.keyframes > 0 && vision_prev_cur && !to_previous && !gated) {
    const auto t_map = Clock::now();
    const LocalMapTrackResult tracked = TrackAgainstLocalMap(cur, odom_prev * *vision_prev_cur);
    if (tracked.status.ok()) {
      const Pose3 registered = odom_prev * *vision_prev_cur;
      const Pose3 refined =
          options_.local_map.fuse
              ? CovarianceWeightedMean(registered, attempt.registration.covariance,
                                       tracked.odom_camera,
                                       tracked.covariance * options_.local_map.covariance_scale)
              : tracked.odom_camera;
      // toward_prediction: a refinement moving away from the hand's inertia is set aside.
      const LocalMapOptions& lm = options_.local_map;
      if (lm.toward_prediction && cur.predicted_odom_camera &&
          predicted_by == MotionSource::kConstantVelocity) {
        const Vec3 predicted = cur.predicted_odom_camera->translation();
        out.local_map_set_aside = (refined.translation() - predicted).norm() >
                                  (registered.translation() - predicted).norm() +
                                      lm.toward_prediction_slack_m;
      }
      if (!out.local_map_set_aside) {
        vision_prev_cur = Orthonormalized(odom_prev.inverse() * refined);
      }
    }
    out.times.registration_ms += MsSince(t_map);
  }
  // Keyframe bundle adjustment: a new keyframe's pose and the last keyframes' adjusted
  // together on their static points; the window keyframes take the corrected poses.
  if (options_.keyframe_ba.keyframes >= 3 && new_keyframe && vision_prev_cur && !gated) {
    const auto t_ba = Clock::now();
    if (const std::optional<Pose3> adjusted =
            AdjustWithKeyframes(cur, odom_prev * *vision_prev_cur)) {
      vision_prev_cur = Orthonormalized(odom_prev.inverse() * *adjusted);
    }
    out.times.registration_ms += MsSince(t_ba);
  }
  // Motion prior: the vision estimate is fused with the constant-velocity prediction, each
  // weighted by its covariance, so the directions the registration hardly constrains (a pan
  // against a sideways slide with far features) follow the camera's inertia.
  const std::optional<Pose3> registered_step = vision_prev_cur;
  // Motion prior release: registered to the frame just before, motion_prior_release_frames
  // frames in a row (the prediction then only repeats the fused steps the registrations started
  // from).
  const bool previous_referenced = vision_prev_cur && !gated && previous_ && attempt.reference &&
                                   attempt.reference->index == previous_->index;
  previous_referenced_in_row_ = previous_referenced ? previous_referenced_in_row_ + 1 : 0;
  if (!previous_referenced) {
    release_offset_sum_.setZero();
    release_offset_norm_sum_ = 0.0;
  } else if (cur.predicted_odom_camera) {
    const Vec3 offset = (predicted_step.inverse() * *vision_prev_cur).translation();
    release_offset_sum_ += offset;
    release_offset_norm_sum_ += offset.norm();
  }
  const bool released = options_.motion_prior_release_frames > 0 &&
                        !options_.motion_prior_release_registered_velocity &&
                        previous_referenced_in_row_ >= options_.motion_prior_release_frames &&
                        (options_.motion_prior_release_persistence <= 0.0 ||
                         release_offset_sum_.norm() >=
                             options_.motion_prior_release_persistence * release_offset_norm_sum_);
  out.motion_prior_released = out.motion_prior_released || released;
  // Prior reset: registrations that keep disagreeing with the prediction, alike, take over.
  if (options_.prior_reset.on()) {
    if (vision_prev_cur && cur.predicted_odom_camera &&
        predicted_by == MotionSource::kConstantVelocity) {
      out.prior_reset =
          prior_reset_.Observe(stamp, odom_prev * *vision_prev_cur, *cur.predicted_odom_camera);
    } else {
      prior_reset_.Break();
    }
  }
  const bool windowed =
      WindowOn() && vision_prev_cur && predicted_by == MotionSource::kConstantVelocity;
  // motion_prior_start_frames: registered to the run's origin at its start, the pose stays.
  const bool start_unfused = static_cast<int>(cur.index) < options_.motion_prior_start_frames &&
                             attempt.reference && first_keyframe_index_ &&
                             attempt.reference->index == *first_keyframe_index_;
  if (windowed) {
    // The window instead: this frame's links (one when no nearby keyframe was registered to)
    // optimised with the last frames' and their constant velocity.
    if (window_links.empty()) {
      window_links.push_back({odom_prev * *vision_prev_cur, attempt.registration.covariance});
    }
    for (PoseLink& link : window_links) link.covariance *= options_.motion_prior_covariance_scale;
    vision_prev_cur = Orthonormalized(
        odom_prev.inverse() * pose_window_.Add(stamp, window_links, odom_prev * *vision_prev_cur));
  } else if (options_.motion_prior_sigma_m > 0.0 && vision_prev_cur && cur.predicted_odom_camera &&
             predicted_by == MotionSource::kConstantVelocity && !start_unfused &&
             !out.prior_reset &&
             !(released && options_.motion_prior_release_sigma_scale <= 0.0)) {
    double sigma_scale = released ? options_.motion_prior_release_sigma_scale : 1.0;
    // A velocity over fewer steps than the history spans is less certain.
    if (options_.motion_prior_sigma_by_steps && options_.velocity_prior_steps > 1 &&
        velocity_history_.steps() > 0 &&
        velocity_history_.steps() < velocity_history_.max_steps() &&
        static_cast<int>(attempt.registration.inliers) >=
            options_.motion_prior_sigma_by_steps_min_inliers) {
      sigma_scale *= std::pow(static_cast<double>(velocity_history_.max_steps()) /
                                  static_cast<double>(velocity_history_.steps()),
                              options_.motion_prior_sigma_by_steps_exponent);
    }
    // Agreeing registrations weigh by their agreement covariance, others by the claimed one
    // scaled.
    const Mat6 covariance = agreement && options_.registration_agreement.on()
                                ? agreement->covariance
                                : Mat6(attempt.registration.covariance *
                                       options_.motion_prior_covariance_scale);
    vision_prev_cur = odom_prev.inverse() *
                      FuseWithPrediction(*cur.predicted_odom_camera, odom_prev * *vision_prev_cur,
                                         covariance, sigma_scale);
  }
  // Anchors: the frame also registered to the first keyframes of the run, whose estimate does
  // not carry the chain's drift: the pose moves anchor.gain of the way towards it
  // (CorrectByAnchor). With anchor.moves_chain the velocity history is re-expressed by the
  // correction once the frame has joined it, so the correction moves the pose but never
  // enters the predicted velocity.
  std::optional<Pose3> anchor_correction;
  if (anchor_estimate && options_.anchor.gain > 0.0 && vision_prev_cur && !gated) {
    const Pose3 chained = odom_prev * *vision_prev_cur;
    const AnchorCorrection corrected = CorrectByAnchor(chained, anchor_estimate->odom_camera,
                                                       anchor_estimate->inliers, options_.anchor);
    if (corrected.status.ok()) {
      vision_prev_cur = Orthonormalized(odom_prev.inverse() * corrected.odom_camera);
      anchor_correction = Orthonormalized(corrected.odom_camera * chained.inverse());
      out.anchor_linked = true;
      // The chain (the window's keyframes, the reference among them) re-expressed with the
      // frame: later frames registered to them continue from the corrected pose.
      if (options_.anchor.moves_chain) {
        for (const auto& kf : window_) {
          if (!IsAnchor(kf))
            kf->odom_camera = Orthonormalized(*anchor_correction * kf->odom_camera);
        }
        if (reference_ && !IsAnchor(reference_) &&
            std::find(window_.begin(), window_.end(), reference_) == window_.end()) {
          reference_->odom_camera = Orthonormalized(*anchor_correction * reference_->odom_camera);
        }
      }
    }
  }
  out.registration = attempt.registration;
  out.registered_to_previous = to_previous && vision_prev_cur.has_value();
  out.num_matches = attempt.matches;
  out.num_icgm_kept = attempt.kept;
  out.registered_px = attempt.registered_px;
  out.registered_reference_px = attempt.registered_reference_px;
  if (attempt.reference) out.reference_index = attempt.reference->index;
  out.hypotheses = attempt.judged;
  out.chosen_hypothesis = attempt.chosen;
  if (attempt.reference && cur.predicted_odom_camera) {
    out.predicted_reference_current =
        attempt.reference->odom_camera.inverse() * *cur.predicted_odom_camera;
  }

  t0 = Clock::now();
  const FusionStep step =
      fusion_.Update(stamp, vision_prev_cur ? &*vision_prev_cur : nullptr, &wheel_);
  out.times.fusion_ms = MsSince(t0);
  out.source = step.source;
  out.wheel_status = step.wheel_status;
  cur.odom_camera = fusion_.odom_camera();
  out.odom_camera = cur.odom_camera;
  if (options_.residual_trend.on() && vision_prev_cur && !to_previous && !gated &&
      attempt.reference && attempt.ok() && step.source == MotionSource::kVision) {
    out.trend_voted_reference_px = ObserveResidualTrend(attempt, &cur);
  }
  out.odom_base = fusion_.odom_base();
  // A pose from elsewhere (wheels, constant velocity) holds the window's motion from here.
  if (WindowOn() && !windowed) pose_window_.Add(stamp, {}, cur.odom_camera);
  registered_track_ =
      registered_track_ *
      (registered_step && !gated ? *registered_step : Pose3(odom_prev.inverse() * cur.odom_camera));

  // The pose the velocity history follows (velocity_from_vision): as registered, else as fused.
  // agreement_velocity_only: only from frames whose registrations agreed.
  const std::optional<Pose3> vision_pose =
      step.source == MotionSource::kVision && registered_step &&
              (!options_.agreement_velocity_only || agreement)
          ? std::optional<Pose3>(odom_prev * *registered_step)
          : std::nullopt;
  const size_t frames_since_reference = attempt.reference && cur.index > attempt.reference->index
                                            ? cur.index - attempt.reference->index
                                            : 1;
  // Velocity rebase at a new keyframe (decided before the keyframe replaces the reference and
  // the frame the previous one, applied once the frame has joined the history).
  const std::optional<Pose3> rebase_correction =
      new_keyframe && vision_pose
          ? VelocityRebaseAtKeyframe(cur, attempt, *vision_pose, frames_since_reference)
          : std::nullopt;
  if (new_keyframe) {
    // With the velocity history's velocity the keyframe keeps its first carrying.
    const std::optional<Vec6> twist =
        vision_prev_cur && !AveragedTimingVelocity()
            ? VelocityTwist(previous_->stamp, odom_prev, stamp, cur.odom_camera,
                            options_.depth_timing_max_gap_s)
            : std::nullopt;
    if (twist && (depth_dt_s != 0.0 || rolling_shutter)) {
      cur.depth_m = DepthAtStamp(depth_as_captured, intrinsics_, depth_dt_s, *twist);
      if (rolling_shutter && keypoints_as_captured.size() == cur.features.size()) {
        cur.features.keypoints = keypoints_as_captured;
        KeypointsAtStamp(intrinsics_, *twist, cur.depth_m, &cur.features.keypoints);
      }
    }
    if (!cur.dynamic.empty() || !cur.excluded.empty() || !cur.trend_excluded.empty()) {
      // Keyframes keep only the features outside dynamic regions.
      std::vector<uint8_t> keep(cur.features.size(), 1);
      for (size_t i = 0; i < keep.size(); ++i) {
        keep[i] = !cur.dynamic.Contains(cur.features.keypoints[i].pt) &&
                  (cur.excluded.empty() || !cur.excluded[i]) &&
                  (cur.trend_excluded.empty() || !cur.trend_excluded[i]);
      }
      cur.features = SubsetFeatures(cur.features, keep);
      attempt.robust = Subset(attempt.robust, keep);
      cur.excluded.clear();
    }
    MakeKeyframe(cur, bgr, &attempt, step.source);
    out.new_keyframe = true;
  }
  if (previous_) before_previous_.emplace(previous_->stamp, previous_->odom_camera);
  previous_ = std::make_unique<Frame>(std::move(cur));
  RememberPrevious(vision_pose);
  if (rebase_correction) {
    velocity_history_.Rebase(*rebase_correction);
    out.velocity_rebased = true;
  }
  if (anchor_correction && options_.anchor.moves_chain) {
    velocity_history_.Rebase(*anchor_correction);
    // The frame before too: with this one it gives the velocity of the depth timing.
    if (before_previous_) before_previous_->second = *anchor_correction * before_previous_->second;
  }
  wheel_.TrimBefore(Time::FromNanoseconds(stamp.nanoseconds() - 10'000'000'000LL));
  out.times.total_ms = MsSince(t_start);
  return out;
}

}  // namespace icgm
