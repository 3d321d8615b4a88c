#include "core/slam/map_refinement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <set>
#include <utility>

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, MapRefinementOptions* o) {
  reader.Read("enabled", &o->enabled);
  reader.Read("max_neighbours", &o->max_neighbours, 0, 1000);
  reader.Read("max_neighbour_distance_m", &o->max_neighbour_distance_m, 0.0, 1000.0);
  reader.Read("max_neighbour_angle_deg", &o->max_neighbour_angle_deg, 0.0, 180.0);
  reader.Read("max_disagreement_m", &o->max_disagreement_m, 0.0, 1000.0);
  reader.Read("max_disagreement_deg", &o->max_disagreement_deg, 0.0, 180.0);
  reader.Read("skip_wheel_keyframes", &o->skip_wheel_keyframes);
  reader.Read("odometry_prior_weight", &o->odometry_prior_weight, 0.0, 1e6);
}

namespace {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  size_t Find(size_t a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  void Join(size_t a, size_t b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<size_t> parent_;
};

// Keyframe pairs (i < j) to register: links first, then nearest by pose.
std::vector<std::pair<int, int>> SelectPairs(const HybridMap& map, const MapRefinementOptions& o) {
  const int n = map.size();
  std::vector<std::set<int>> partners(static_cast<size_t>(n));
  for (const Link& l : map.links()) {
    if (l.from_id < 0 || l.to_id < 0 || l.from_id >= n || l.to_id >= n || l.from_id == l.to_id) {
      continue;
    }
    partners[l.from_id].insert(l.to_id);
    partners[l.to_id].insert(l.from_id);
  }
  // Keyframes placed by wheel odometry: vision failed or followed something moving there (the
  // fusion gate), so their features are not trusted as static structure.
  const auto usable = [&](int id) {
    return !o.skip_wheel_keyframes ||
           map.keyframe(id).relative_source != RelativePoseSource::kWheelOdometry;
  };
  std::set<std::pair<int, int>> pairs;
  for (int i = 0; i < n; ++i) {
    if (!usable(i)) continue;
    const Pose3& pi = map.keyframe(i).global_pose;
    std::vector<std::pair<double, int>> near;
    for (int j = 0; j < n; ++j) {
      if (j == i || !usable(j)) continue;
      const Pose3 d = Between(pi, map.keyframe(j).global_pose);
      const double t = TranslationNorm(d);
      const double r = RotationAngleRad(d) * 180.0 / M_PI;
      if (t > o.max_neighbour_distance_m || r > o.max_neighbour_angle_deg) continue;
      near.emplace_back(t / std::max(o.max_neighbour_distance_m, 1e-9) +
                            r / std::max(o.max_neighbour_angle_deg, 1e-9),
                        j);
    }
    std::sort(near.begin(), near.end());
    std::set<int> chosen(partners[i].begin(), partners[i].end());
    for (const auto& [score, j] : near) {
      if (static_cast<int>(chosen.size()) >= o.max_neighbours) break;
      chosen.insert(j);
    }
    for (int j : chosen) {
      if (usable(j)) pairs.insert({std::min(i, j), std::max(i, j)});
    }
  }
  return {pairs.begin(), pairs.end()};
}

}  // namespace

Status RefineMapPoses(const HybridMap& map, const KeyframeRegistration& registration,
                      const CameraIntrinsics& intrinsics, const MapRefinementOptions& options,
                      std::vector<Pose3>* poses, MapRefinementSummary* summary) {
  const auto t0 = std::chrono::steady_clock::now();
  MapRefinementSummary s;
  const int n = map.size();
  poses->clear();
  for (const Keyframe& kf : map.keyframes()) poses->push_back(kf.global_pose);
  if (summary) *summary = s;
  if (n < 2) return Status::Error("map refinement: fewer than two keyframes");

  // Node of keypoint k of keyframe i: offset[i] + k.
  std::vector<size_t> offset(static_cast<size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i) offset[i + 1] = offset[i] + map.keyframe(i).keypoints.size();
  UnionFind tracks(offset[n]);
  std::vector<uint8_t> linked(offset[n], 0);

  const double max_disagreement_rad = options.max_disagreement_deg * M_PI / 180.0;
  for (const auto& [a, b] : SelectPairs(map, options)) {
    // Query b (later), candidate a: beta = b in a's frame.
    const Keyframe& ka = map.keyframe(a);
    const Keyframe& kb = map.keyframe(b);
    ++s.pairs_tried;
    const RegistrationOutcome r = registration.Register(kb, ka);
    if (!r.status.ok() || r.inlier_matches.empty()) continue;
    const Pose3 diff = Between(Between(ka.global_pose, kb.global_pose), r.relative_pose);
    if (TranslationNorm(diff) > options.max_disagreement_m ||
        RotationAngleRad(diff) > max_disagreement_rad) {
      continue;
    }
    ++s.pairs_used;
    for (const auto& [kq, kc] : r.inlier_matches) {
      const size_t nb = offset[b] + static_cast<size_t>(kq);
      const size_t na = offset[a] + static_cast<size_t>(kc);
      tracks.Join(na, nb);
      linked[na] = linked[nb] = 1;
    }
  }

  // One point per track; observations of its keypoints (first keypoint per keyframe).
  BaProblem problem;
  problem.world_camera = *poses;
  problem.fixed.assign(static_cast<size_t>(n), 0);
  problem.fixed[0] = 1;
  std::vector<int> point_of_root(offset[n], -1);
  std::vector<Vec3> sum;
  std::vector<int> count;
  std::set<std::pair<int, int>> seen;  // (point, keyframe)
  const double scale = registration.options().octave_scale_factor;
  for (int i = 0; i < n; ++i) {
    const Keyframe& kf = map.keyframe(i);
    for (size_t k = 0; k < kf.keypoints.size(); ++k) {
      const size_t node = offset[i] + k;
      if (!linked[node]) continue;
      const size_t root = tracks.Find(node);
      int& point = point_of_root[root];
      if (point < 0) {
        point = static_cast<int>(sum.size());
        sum.push_back(Vec3::Zero());
        count.push_back(0);
      }
      if (!seen.insert({point, i}).second) continue;
      BaObservation o;
      o.camera = i;
      o.point = point;
      o.pixel_px = Eigen::Vector2d(kf.keypoints[k].pt.x, kf.keypoints[k].pt.y);
      o.pixel_sigma_px = PyramidPixelSigma(kf.keypoints[k], scale);
      const Vec3& pc = kf.points_m[k];
      o.depth_m = pc.allFinite() ? pc.z() : 0.0;
      if (pc.allFinite()) {
        sum[point] += kf.global_pose * pc;
        ++count[point];
      }
      problem.observations.push_back(o);
    }
  }
  problem.points_world.resize(sum.size());
  for (size_t p = 0; p < sum.size(); ++p) {
    problem.points_world[p] = count[p] > 0 ? Vec3(sum[p] / count[p]) : Vec3::Zero();
  }
  // Tracks without any depth have no initial point; drop their observations.
  problem.observations.erase(
      std::remove_if(problem.observations.begin(), problem.observations.end(),
                     [&](const BaObservation& o) { return count[o.point] == 0; }),
      problem.observations.end());
  s.tracks = static_cast<int>(std::count_if(count.begin(), count.end(), [](int c) { return c; }));

  if (options.odometry_prior_weight > 0) {
    for (const Link& l : map.links()) {
      if (l.type != LinkType::kOdometry) continue;
      BaRelativePose prior;
      prior.from = l.from_id;
      prior.to = l.to_id;
      prior.measured = l.relative_pose;
      prior.information = l.information * options.odometry_prior_weight;
      problem.priors.push_back(prior);
    }
  }
  const Status st =
      BundleAdjust(intrinsics, options.bundle_adjustment, &problem, &s.bundle_adjustment);
  s.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (summary) *summary = s;
  if (!st.ok()) return Status::Error("map refinement: " + st.reason());
  for (int i = 0; i < n; ++i) (*poses)[i] = Orthonormalized(problem.world_camera[i]);
  return Status::Ok();
}

}  // namespace icgm
