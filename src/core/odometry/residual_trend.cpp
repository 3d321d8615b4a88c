#include "core/odometry/residual_trend.h"

#include <algorithm>
#include <cmath>

namespace icgm {

namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  return v[mid];
}

}  // namespace

void ResidualTrend::Reset(size_t reference_index, size_t num_keypoints) {
  started_ = true;
  reference_index_ = reference_index;
  frame_ = 0;
  tracks_.assign(num_keypoints, {});
  voted_.assign(num_keypoints, 0);
}

bool ResidualTrend::Drifting(const std::deque<Sample>& track, Eigen::Vector2d* direction) const {
  const size_t n = static_cast<size_t>(options_.frames);
  if (track.size() < n) return false;
  // Least-squares line r(t) = a + b t through the last n samples (both image axes).
  double t_mean = 0.0;
  Eigen::Vector2d r_mean = Eigen::Vector2d::Zero();
  for (const Sample& s : track) {
    t_mean += static_cast<double>(s.frame);
    r_mean += s.residual_px;
  }
  t_mean /= n;
  r_mean /= n;
  double sxx = 0.0;
  Eigen::Vector2d sxy = Eigen::Vector2d::Zero();
  for (const Sample& s : track) {
    const double dt = static_cast<double>(s.frame) - t_mean;
    sxx += dt * dt;
    sxy += dt * (s.residual_px - r_mean);
  }
  if (sxx <= 0.0) return false;
  const Eigen::Vector2d slope = sxy / sxx;
  double sse = 0.0;
  for (const Sample& s : track) {
    const Eigen::Vector2d fit = r_mean + slope * (static_cast<double>(s.frame) - t_mean);
    sse += (s.residual_px - fit).squaredNorm();
  }
  // Scatter about the line per axis, at least noise_px.
  const double sigma = std::max(options_.noise_px, std::sqrt(sse / (2.0 * std::max<double>(n - 2, 1))));
  const double growth = slope.norm() * (track.back().frame - track.front().frame);
  if (growth < options_.min_growth_px || slope.norm() * std::sqrt(sxx) < options_.min_slope_sigmas * sigma ||
      track.back().residual_px.norm() < options_.min_drift_px) {
    return false;
  }
  *direction = slope.normalized();
  return true;
}

std::vector<int> ResidualTrend::Observe(const std::vector<TrendObservation>& observations) {
  ++frame_;
  Eigen::Vector2d common = Eigen::Vector2d::Zero();
  if (options_.remove_median && !observations.empty()) {
    std::vector<double> x, y;
    for (const TrendObservation& o : observations) {
      x.push_back(o.residual_px.x());
      y.push_back(o.residual_px.y());
    }
    common = {Median(x), Median(y)};
  }
  // Drifting keypoints of this frame, with their pixel and direction.
  struct Candidate {
    int keypoint;
    cv::Point2f px;
    Eigen::Vector2d direction;
  };
  std::vector<Candidate> drifting;
  size_t tracked = 0;  // observations within max_residual_px
  for (const TrendObservation& o : observations) {
    const int k = o.reference_keypoint;
    if (k < 0 || static_cast<size_t>(k) >= tracks_.size() || voted_[k]) continue;
    std::deque<Sample>& track = tracks_[k];
    const Eigen::Vector2d residual = o.residual_px - common;
    if (residual.norm() > options_.max_residual_px) {
      track.clear();
      continue;
    }
    ++tracked;
    track.push_back({frame_, residual});
    while (track.size() > static_cast<size_t>(options_.frames)) track.pop_front();
    Eigen::Vector2d direction;
    if (Drifting(track, &direction)) drifting.push_back({k, o.reference_px, direction});
  }
  // Neighbours on the same body drift alike.
  const double radius2 = options_.neighbour_radius_px * options_.neighbour_radius_px;
  const double min_cos = std::cos(options_.neighbour_max_angle_deg * M_PI / 180.0);
  std::vector<int> voted;
  for (const Candidate& c : drifting) {
    int neighbours = 0;
    for (const Candidate& o : drifting) {
      if (o.keypoint == c.keypoint) continue;
      const double dx = o.px.x - c.px.x, dy = o.px.y - c.px.y;
      if (dx * dx + dy * dy <= radius2 && o.direction.dot(c.direction) >= min_cos) ++neighbours;
    }
    if (neighbours >= options_.min_neighbours) voted.push_back(c.keypoint);
  }
  // Most of the frame drifting: the motion followed the walkers, the room drifts against it.
  if (static_cast<double>(voted.size()) > options_.max_share * tracked) return {};
  for (const int k : voted) voted_[k] = 1;
  return voted;
}

}  // namespace icgm
