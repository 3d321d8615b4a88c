#include "core/odometry/keyframe_bundle_adjustment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <Eigen/Cholesky>

#include "core/odometry/keypoint_grid.h"
#include "core/optimization/bundle_adjustment.h"

namespace icgm {

namespace {

constexpr double kGridCellPx = 16.0;

int TrackRoot(std::vector<int>* parent, int i) {
  while ((*parent)[i] != i) {
    (*parent)[i] = (*parent)[(*parent)[i]];
    i = (*parent)[i];
  }
  return i;
}

bool LiftedAndStatic(const KeyframeBaView& v, size_t i) {
  return (v.usable.empty() || v.usable[i]) && v.points_camera[i].allFinite();
}

}  // namespace

std::vector<std::vector<int>> AssociateKeyframes(const std::vector<KeyframeBaView>& views,
                                                 const CameraIntrinsics& intrinsics,
                                                 const KeyframeBaOptions& options,
                                                 size_t* num_tracks) {
  std::vector<int> offset(views.size() + 1, 0);
  for (size_t v = 0; v < views.size(); ++v) {
    offset[v + 1] = offset[v] + static_cast<int>(views[v].pixels_px.size());
  }
  std::vector<int> parent(static_cast<size_t>(offset.back()));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<KeypointGrid> grids;
  grids.reserve(views.size());
  for (const KeyframeBaView& v : views) grids.emplace_back(v.pixels_px, v.usable, kGridCellPx);
  const int norm = views.empty() || views[0].binary ? cv::NORM_HAMMING : cv::NORM_L2;

  for (size_t a = 0; a < views.size(); ++a) {
    const KeyframeBaView& va = views[a];
    for (size_t b = a + 1; b < views.size(); ++b) {
      const KeyframeBaView& vb = views[b];
      const Pose3 b_a = vb.odom_camera.inverse() * va.odom_camera;
      // Per keypoint of b: the best keypoint of a (descriptor distance), mutual best only.
      std::vector<std::pair<double, int>> best_for_b(vb.pixels_px.size(),
                                                     {std::numeric_limits<double>::max(), -1});
      std::vector<std::pair<double, int>> best_for_a(va.pixels_px.size(),
                                                     {std::numeric_limits<double>::max(), -1});
      for (size_t i = 0; i < va.pixels_px.size(); ++i) {
        if (!LiftedAndStatic(va, i)) continue;
        const Eigen::Vector3d p = b_a * va.points_camera[i];
        if (p.z() < 0.1) continue;
        const Eigen::Vector2d u = intrinsics.Project(p);
        const double radius = options.match_px * va.pixel_sigma_px[i];
        const double depth_tol = options.depth_abs_m + options.depth_rel_per_m * p.z() * p.z();
        grids[b].ForEachNear(u, radius, [&](int j) {
          if (!vb.points_camera[j].allFinite()) return;
          if (std::abs(vb.points_camera[j].z() - p.z()) > depth_tol) return;
          const double d =
              cv::norm(va.descriptors.row(static_cast<int>(i)), vb.descriptors.row(j), norm);
          if (d > options.max_descriptor_distance) return;
          if (d < best_for_a[i].first) best_for_a[i] = {d, j};
          if (d < best_for_b[j].first) best_for_b[j] = {d, static_cast<int>(i)};
        });
      }
      for (size_t i = 0; i < best_for_a.size(); ++i) {
        const int j = best_for_a[i].second;
        if (j < 0 || best_for_b[j].second != static_cast<int>(i)) continue;
        const int ra = TrackRoot(&parent, offset[a] + static_cast<int>(i));
        const int rb = TrackRoot(&parent, offset[b] + j);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }
  // Tracks: groups of two views or more that hold at most one keypoint per view.
  std::unordered_map<int, std::vector<std::pair<int, int>>> groups;  // root -> (view, keypoint)
  for (size_t v = 0; v < views.size(); ++v) {
    for (int i = 0; i < offset[v + 1] - offset[v]; ++i) {
      groups[TrackRoot(&parent, offset[v] + i)].push_back({static_cast<int>(v), i});
    }
  }
  std::vector<std::vector<int>> track(views.size());
  for (size_t v = 0; v < views.size(); ++v) track[v].assign(views[v].pixels_px.size(), -1);
  // Deterministic ids: by root node order.
  std::vector<int> roots;
  roots.reserve(groups.size());
  for (const auto& g : groups) {
    if (g.second.size() >= 2) roots.push_back(g.first);
  }
  std::sort(roots.begin(), roots.end());
  int next = 0;
  for (const int root : roots) {
    const auto& members = groups[root];
    std::vector<int> seen;
    bool conflict = false;
    for (const auto& m : members) {
      if (std::find(seen.begin(), seen.end(), m.first) != seen.end()) conflict = true;
      seen.push_back(m.first);
    }
    if (conflict) continue;
    for (const auto& m : members) track[m.first][m.second] = next;
    ++next;
  }
  if (num_tracks) *num_tracks = static_cast<size_t>(next);
  return track;
}

KeyframeBaResult AdjustKeyframes(const std::vector<KeyframeBaView>& views,
                                 const CameraIntrinsics& intrinsics,
                                 const KeyframeBaOptions& options) {
  KeyframeBaResult out;
  for (const KeyframeBaView& v : views) out.odom_camera.push_back(v.odom_camera);
  const int fixed = std::max(1, options.fixed_keyframes);
  if (static_cast<int>(views.size()) <= fixed) {
    out.status = Status::Error("keyframe bundle adjustment: " + std::to_string(views.size()) +
                               " keyframes, " + std::to_string(fixed) + " fixed");
    return out;
  }
  for (const KeyframeBaView& v : views) {
    const size_t n = v.pixels_px.size();
    if (v.pixel_sigma_px.size() != n || v.points_camera.size() != n ||
        static_cast<size_t>(v.descriptors.rows) != n ||
        (!v.usable.empty() && v.usable.size() != n)) {
      out.status = Status::Error("keyframe bundle adjustment: per-keypoint sizes differ");
      return out;
    }
  }
  size_t num_tracks = 0;
  const std::vector<std::vector<int>> track =
      AssociateKeyframes(views, intrinsics, options, &num_tracks);
  out.points = num_tracks;
  if (static_cast<int>(num_tracks) < options.min_points) {
    out.status =
        Status::Error("keyframe bundle adjustment: " + std::to_string(num_tracks) +
                      " points seen by two keyframes, below " + std::to_string(options.min_points));
    return out;
  }
  BaProblem problem;
  problem.world_camera = out.odom_camera;
  problem.fixed.assign(views.size(), 0);
  for (int i = 0; i < fixed; ++i) problem.fixed[static_cast<size_t>(i)] = 1;
  // Each point starts at the mean of its observations lifted with their depth.
  problem.points_world.assign(num_tracks, Eigen::Vector3d::Zero());
  std::vector<int> lifted(num_tracks, 0);
  for (size_t v = 0; v < views.size(); ++v) {
    for (size_t i = 0; i < track[v].size(); ++i) {
      const int t = track[v][i];
      if (t < 0) continue;
      problem.points_world[static_cast<size_t>(t)] +=
          views[v].odom_camera * views[v].points_camera[i];
      ++lifted[static_cast<size_t>(t)];
      BaObservation o;
      o.camera = static_cast<int>(v);
      o.point = t;
      o.pixel_px = Eigen::Vector2d(views[v].pixels_px[i].x, views[v].pixels_px[i].y);
      o.pixel_sigma_px = views[v].pixel_sigma_px[i];
      o.depth_m = views[v].points_camera[i].z();
      problem.observations.push_back(o);
    }
  }
  for (size_t t = 0; t < num_tracks; ++t) problem.points_world[t] /= std::max(1, lifted[t]);
  if (options.link_covariance_scale > 0.0) {
    for (size_t v = 0; v < views.size(); ++v) {
      const KeyframeBaView& view = views[v];
      if (view.link_from < 0 || view.link_from >= static_cast<int>(v)) continue;
      const Mat6 c = view.link_covariance * options.link_covariance_scale;
      Eigen::LDLT<Mat6> ldlt(c);
      if (!c.allFinite() || ldlt.info() != Eigen::Success) continue;
      BaRelativePose prior;
      prior.from = view.link_from;
      prior.to = static_cast<int>(v);
      prior.measured = view.link_relative;
      prior.information = ldlt.solve(Mat6::Identity());
      prior.information = 0.5 * (prior.information + prior.information.transpose());
      if (Eigen::LLT<Mat6>(prior.information).info() != Eigen::Success) continue;
      problem.priors.push_back(prior);
    }
  }

  BundleAdjustmentOptions ba;
  ba.max_iterations = options.iterations;
  ba.max_solver_time_s = 0.0;  // the result must not depend on the machine's load
  ba.huber_sigma = options.huber_sigmas;
  ba.use_depth = true;
  ba.depth_sigma_m = options.depth_sigma_m;
  ba.depth_sigma_per_m2 = options.depth_sigma_per_m2;
  ba.outlier_rounds = 1;
  ba.min_observations = 2;
  BaSummary summary;
  const Status solved = BundleAdjust(intrinsics, ba, &problem, &summary);
  if (!solved.ok()) {
    out.status = Status::Error("keyframe bundle adjustment: " + solved.reason());
    return out;
  }
  out.observations = static_cast<size_t>(summary.observations);
  out.outliers = static_cast<size_t>(summary.outliers);
  out.initial_rms = summary.initial_rms;
  out.final_rms = summary.final_rms;
  for (size_t v = 0; v < views.size(); ++v) {
    const Pose3 d = Between(views[v].odom_camera, problem.world_camera[v]);
    out.max_correction_m = std::max(out.max_correction_m, TranslationNorm(d));
    out.max_correction_deg = std::max(out.max_correction_deg, RotationAngleRad(d) * 180.0 / M_PI);
  }
  if (out.max_correction_m > options.max_correction_m ||
      out.max_correction_deg > options.max_correction_deg) {
    out.status = Status::Error("keyframe bundle adjustment: correction " +
                               std::to_string(out.max_correction_m) + " m / " +
                               std::to_string(out.max_correction_deg) + " deg beyond the bound");
    return out;
  }
  for (size_t v = 0; v < views.size(); ++v)
    out.odom_camera[v] = Orthonormalized(problem.world_camera[v]);
  return out;
}

}  // namespace icgm
