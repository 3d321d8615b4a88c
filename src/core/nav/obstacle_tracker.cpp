#include "core/nav/obstacle_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/nav/planar_pose.h"

namespace icgm {

bool CameraView::Contains(const Eigen::Vector2d& centre_m, double radius_m) const {
  const Eigen::Vector2d d = centre_m - viewpoint_m;
  const double range = d.norm();
  if (range <= radius_m || range + radius_m > range_m) return false;
  const double bearing = std::abs(WrapAngleRad(std::atan2(d.y(), d.x()) - yaw_rad));
  return bearing + std::asin(radius_m / range) <= half_fov_rad;
}

ObstacleTracker::ObstacleTracker(ObstacleTrackerOptions options) : options_(options) {}

void ObstacleTracker::Clear() {
  tracks_.clear();
  histories_.clear();
  lost_.clear();
  started_ = false;
}

std::vector<ObstacleTracker::Cluster> ObstacleTracker::ClusterCells(
    const std::vector<Eigen::Vector2d>& cells_m) const {
  // Union-find over the pairs within link_distance_m (a few hundred cells per frame).
  const size_t n = cells_m.size();
  std::vector<size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&parent](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  const double link2 = options_.link_distance_m * options_.link_distance_m;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      if ((cells_m[i] - cells_m[j]).squaredNorm() <= link2) parent[find(i)] = find(j);
    }
  }
  std::vector<int> label(n, -1);
  std::vector<Cluster> clusters;
  std::vector<int> counts;
  std::vector<size_t> root_of;
  for (size_t i = 0; i < n; ++i) {
    const size_t r = find(i);
    auto it = std::find(root_of.begin(), root_of.end(), r);
    if (it == root_of.end()) {
      root_of.push_back(r);
      clusters.emplace_back();
      counts.push_back(0);
      it = root_of.end() - 1;
    }
    const int k = static_cast<int>(it - root_of.begin());
    label[i] = k;
    clusters[k].centre += cells_m[i];
    ++counts[k];
  }
  for (size_t k = 0; k < clusters.size(); ++k) clusters[k].centre /= counts[k];
  for (size_t i = 0; i < n; ++i) {
    Cluster& c = clusters[label[i]];
    c.radius_m = std::max(c.radius_m, (cells_m[i] - c.centre).norm());
  }
  return clusters;
}

namespace {

// Per axis, the median of the slopes between every pair of samples more than 1 ms apart.
Eigen::Vector2d MedianPairSlope(const std::deque<std::pair<double, Eigen::Vector2d>>& s) {
  std::vector<double> sx, sy;
  for (size_t i = 0; i < s.size(); ++i) {
    for (size_t j = i + 1; j < s.size(); ++j) {
      const double dt = s[j].first - s[i].first;
      if (std::abs(dt) < 1e-3) continue;
      const Eigen::Vector2d slope = (s[j].second - s[i].second) / dt;
      sx.push_back(slope.x());
      sy.push_back(slope.y());
    }
  }
  const auto median = [](std::vector<double>& v) {
    if (v.empty()) return 0.0;
    const size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + m, v.end());
    if (v.size() % 2 == 1) return v[m];
    return 0.5 * (v[m] + *std::max_element(v.begin(), v.begin() + m));
  };
  return Eigen::Vector2d(median(sx), median(sy));
}

}  // namespace

namespace {

// Least-squares slope of position over time (zero without a spread in time).
Eigen::Vector2d LeastSquaresSlope(const std::deque<std::pair<double, Eigen::Vector2d>>& s) {
  double mt = 0.0;
  Eigen::Vector2d mp = Eigen::Vector2d::Zero();
  for (const auto& [t, p] : s) mt += t, mp += p;
  mt /= s.size();
  mp /= s.size();
  double stt = 0.0;
  Eigen::Vector2d stp = Eigen::Vector2d::Zero();
  for (const auto& [t, p] : s) {
    stt += (t - mt) * (t - mt);
    stp += (t - mt) * (p - mp);
  }
  return stt > 1e-9 ? Eigen::Vector2d(stp / stt) : Eigen::Vector2d::Zero();
}

}  // namespace

void ObstacleTracker::FitVelocity(const History& history, TrackedObstacle* track) const {
  const auto& s = history.samples;
  if (s.size() < 2) {
    track->velocity_mps.setZero();
    return;
  }
  Eigen::Vector2d v = options_.robust_velocity ? MedianPairSlope(s) : LeastSquaresSlope(s);
  if (v.norm() > options_.max_speed_mps) v *= options_.max_speed_mps / v.norm();
  track->velocity_mps = v;
}

void ObstacleTracker::Update(Time stamp, const std::vector<Eigen::Vector2d>& cells_m,
                             const std::optional<Eigen::Vector2d>& viewpoint_m,
                             const std::optional<CameraView>& view) {
  now_ = stamp;
  started_ = true;
  const double now_s = stamp.seconds();
  std::vector<Cluster> clusters = ClusterCells(cells_m);
  // The body's centre behind the seen cells, away from the camera.
  const auto body_offset = [&](const Eigen::Vector2d& centre) -> Eigen::Vector2d {
    if (options_.body_offset_m <= 0.0 || !viewpoint_m) return Eigen::Vector2d::Zero();
    const Eigen::Vector2d ray = centre - *viewpoint_m;
    if (ray.norm() < 1e-6) return Eigen::Vector2d::Zero();
    return options_.body_offset_m * ray.normalized();
  };
  clusters.erase(std::remove_if(clusters.begin(), clusters.end(),
                                [this](const Cluster& c) {
                                  return c.radius_m > options_.max_cluster_radius_m;
                                }),
                 clusters.end());
  // Greedy nearest association: the closest (track, cluster) pairs first.
  struct Pair {
    double d;
    size_t track, cluster;
  };
  std::vector<Pair> pairs;
  for (size_t t = 0; t < tracks_.size(); ++t) {
    const Eigen::Vector2d predicted = Predict(tracks_[t], 0.0);
    for (size_t c = 0; c < clusters.size(); ++c) {
      const double d = (clusters[c].centre - predicted).norm();
      if (d <= options_.gate_m) pairs.push_back({d, t, c});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d < b.d; });
  std::vector<bool> track_used(tracks_.size(), false), cluster_used(clusters.size(), false);
  for (const Pair& p : pairs) {
    if (track_used[p.track] || cluster_used[p.cluster]) continue;
    track_used[p.track] = cluster_used[p.cluster] = true;
    TrackedObstacle& track = tracks_[p.track];
    History& history = histories_[p.track];
    const Cluster& c = clusters[p.cluster];
    history.samples.emplace_back(now_s, c.centre);
    while (!history.samples.empty() &&
           now_s - history.samples.front().first > options_.history_s + 1e-9) {
      history.samples.pop_front();
    }
    track.position_m = c.centre;
    track.body_offset_m = body_offset(c.centre);
    track.radius_m = std::max({options_.min_radius_m, c.radius_m, 0.8 * track.radius_m});
    track.last_seen = stamp;
    track.held = false;
    track.remembered = false;
    ++track.observations;
    FitVelocity(history, &track);
    track.moving = track.observations >= options_.min_observations &&
                   track.velocity_mps.norm() >= options_.moving_speed_mps;
    track.was_moving = track.was_moving || track.moving;
  }
  // Drop tracks unseen for too long; new tracks for the clusters left.
  std::vector<TrackedObstacle> kept;
  std::vector<History> kept_history;
  const bool reidentify = options_.reidentify_s > 0.0;
  // Walker identity: the clusters left matched to lost walkers, the unseen walker tracks still
  // kept (their prediction missed) and the dropped ones remembered, nearest pairs first.
  std::vector<int> continues(clusters.size(), -1);  // index into tracks_ (>= 0) or lost_ (< -1)
  if (reidentify) {
    const auto reach = [&](const TrackedObstacle& w, const Eigen::Vector2d& c) {
      const double age = now_s - w.last_seen.seconds();
      const Eigen::Vector2d from = w.position_m, to = w.position_m + w.velocity_mps * age;
      const Eigen::Vector2d seg = to - from;
      const double u = seg.squaredNorm() > 1e-12
                           ? std::clamp((c - from).dot(seg) / seg.squaredNorm(), 0.0, 1.0)
                           : 0.0;
      return (c - (from + u * seg)).norm();
    };
    std::vector<Pair> lost_pairs;  // track index: tracks_ index, or tracks_.size() + lost_ index
    for (size_t c = 0; c < clusters.size(); ++c) {
      if (cluster_used[c]) continue;
      for (size_t t = 0; t < tracks_.size(); ++t) {
        if (track_used[t] || !IsWalker(tracks_[t])) continue;
        const double d = reach(tracks_[t], clusters[c].centre);
        if (d <= options_.reidentify_gate_m) lost_pairs.push_back({d, t, c});
      }
      for (size_t l = 0; l < lost_.size(); ++l) {
        if (now_s - lost_[l].last_seen.seconds() > options_.reidentify_s) continue;
        const double d = reach(lost_[l], clusters[c].centre);
        if (d <= options_.reidentify_gate_m) lost_pairs.push_back({d, tracks_.size() + l, c});
      }
    }
    std::sort(lost_pairs.begin(), lost_pairs.end(),
              [](const Pair& a, const Pair& b) { return a.d < b.d; });
    std::vector<bool> lost_used(tracks_.size() + lost_.size(), false);
    for (const Pair& p : lost_pairs) {
      if (lost_used[p.track] || cluster_used[p.cluster]) continue;
      lost_used[p.track] = cluster_used[p.cluster] = true;
      continues[p.cluster] = p.track < tracks_.size()
                                 ? static_cast<int>(p.track)
                                 : -2 - static_cast<int>(p.track - tracks_.size());
      if (p.track < tracks_.size()) track_used[p.track] = true;  // continued below, not kept
    }
  }
  std::vector<TrackedObstacle> continued;  // the lost walkers found again, in cluster order
  for (size_t c = 0; c < clusters.size(); ++c) {
    if (continues[c] == -1) continue;
    continued.push_back(continues[c] >= 0 ? tracks_[continues[c]] : lost_[-2 - continues[c]]);
  }
  std::vector<TrackedObstacle> still_lost;
  if (reidentify) {
    std::vector<bool> taken(lost_.size(), false);
    for (const int k : continues) {
      if (k < -1) taken[-2 - k] = true;
    }
    for (size_t l = 0; l < lost_.size(); ++l) {
      if (!taken[l] && now_s - lost_[l].last_seen.seconds() <= options_.reidentify_s) {
        still_lost.push_back(lost_[l]);
      }
    }
  }
  for (size_t t = 0; t < tracks_.size(); ++t) {
    TrackedObstacle& track = tracks_[t];
    const bool found_again =
        std::find(continues.begin(), continues.end(), static_cast<int>(t)) != continues.end();
    if (found_again) continue;
    if (options_.standing_hold_s > 0.0 && !track_used[t] && !track.moving && !track.held &&
        track.observations >= options_.standing_hold_min_frames) {
      track.held = true;  // out of view while standing or slow: held where it was last seen
      track.velocity_mps.setZero();
    }
    if (options_.side_memory_s > 0.0 && !track_used[t] && view) {
      // Out of the view: remembered. Wholly back in view and not seen: its place is free.
      const Disc disc = RememberedDisc(track, 0.0);
      if (!view->Contains(disc.centre_m, disc.radius_m)) {
        track.remembered = true;
        track.moving = track.moving && options_.side_memory_keeps_moving;
      } else if (track.remembered) {
        continue;
      }
    }
    const double timeout = track.remembered ? options_.side_memory_s
                           : track.held     ? options_.standing_hold_s
                                            : options_.track_timeout_s;
    if (now_s - track.last_seen.seconds() > timeout) {
      if (reidentify && IsWalker(track) && now_s - track.last_seen.seconds() <= options_.reidentify_s) {
        still_lost.push_back(track);
      }
      continue;
    }
    kept.push_back(tracks_[t]);
    kept_history.push_back(std::move(histories_[t]));
  }
  lost_.swap(still_lost);
  // A track (new, or a lost walker found again with its identity) starts a fresh position
  // history at cluster c, seen once now.
  const auto start_at_cluster = [&](TrackedObstacle track, size_t c) {
    track.position_m = clusters[c].centre;
    track.body_offset_m = body_offset(clusters[c].centre);
    track.radius_m = std::max(options_.min_radius_m, clusters[c].radius_m);
    track.last_seen = stamp;
    track.observations = 1;
    kept.push_back(track);
    History h;
    h.samples.emplace_back(now_s, clusters[c].centre);
    kept_history.push_back(std::move(h));
  };
  size_t next_continued = 0;
  for (size_t c = 0; c < clusters.size(); ++c) {
    if (continues[c] != -1) {
      // A lost walker found again: its identity, a fresh position history. Moving again only
      // from min_observations fresh sightings (no velocity from two noisy centroids);
      // was_moving keeps it a walker meanwhile.
      TrackedObstacle track = continued[next_continued++];
      track.velocity_mps.setZero();
      track.held = false;
      track.moving = false;
      start_at_cluster(track, c);
      ++reidentified_;
      continue;
    }
    if (cluster_used[c]) continue;
    TrackedObstacle track;
    track.id = next_id_++;
    start_at_cluster(track, c);
  }
  tracks_.swap(kept);
  histories_.swap(kept_history);
}

std::vector<TrackedObstacle> ObstacleTracker::MovingTracks() const {
  std::vector<TrackedObstacle> out;
  for (const auto& t : tracks_) {
    if (t.moving) out.push_back(t);
  }
  return out;
}

Eigen::Vector2d ObstacleTracker::Predict(const TrackedObstacle& track, double t_s) const {
  if (track.remembered && !options_.side_memory_keeps_moving) return DampedPosition(track, t_s);
  const double age = DurationSeconds(now_, track.last_seen) + t_s;
  return track.position_m + track.velocity_mps * age;
}

Eigen::Vector2d ObstacleTracker::DampedPosition(const TrackedObstacle& track, double t_s) const {
  const double age = DurationSeconds(now_, track.last_seen) + t_s;
  const double tau = options_.side_memory_damping_s;
  const double travel_s = tau > 0.0 ? tau * (1.0 - std::exp(-age / tau)) : 0.0;
  return track.position_m + track.velocity_mps * travel_s;
}

Disc ObstacleTracker::RememberedDisc(const TrackedObstacle& track, double t_s) const {
  if (!track.remembered) return Disc{Predict(track, t_s), track.radius_m};
  const double age = DurationSeconds(now_, track.last_seen) + t_s;
  return Disc{DampedPosition(track, t_s),
              track.radius_m + options_.side_memory_growth_mps * age};
}

std::vector<Disc> ObstacleTracker::SweptDiscs(double horizon_s, double step_s) const {
  std::vector<Disc> discs;
  const int steps = step_s > 0.0 ? static_cast<int>(std::ceil(horizon_s / step_s - 1e-9)) : 0;
  for (const auto& t : tracks_) {
    if (!t.moving) continue;
    for (int k = 0; k <= steps; ++k) {
      discs.push_back({Predict(t, std::min(horizon_s, k * step_s)), t.radius_m});
    }
  }
  return discs;
}

double ObstacleTracker::PredictedClearance(const Eigen::Vector2d& p, double t_s) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : tracks_) {
    if (!t.moving) continue;
    best = std::min(best, (p - Predict(t, t_s)).norm() - t.radius_m);
  }
  return best;
}

double ObstacleTracker::StandingWalkerClearance(const Eigen::Vector2d& p, double t_s,
                                                bool unseen_only) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : tracks_) {
    if (t.moving || !t.was_moving || (unseen_only && !Unseen(t))) continue;
    best = std::min(best, (p - Predict(t, t_s)).norm() - t.radius_m);
  }
  return best;
}

Disc ObstacleTracker::BodyDisc(const TrackedObstacle& track, double t_s) const {
  return Disc{Predict(track, t_s) + track.body_offset_m,
              std::max(track.radius_m, options_.body_radius_m)};
}

}  // namespace icgm
