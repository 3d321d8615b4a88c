#include "core/map_export/sim_people_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace icgm {

Status SimPeopleTruth::Build(const sim::Simulator& simulator, const HybridMap& map,
                             const std::function<void(size_t, size_t)>& progress) {
  masks_.clear();
  const size_t n = static_cast<size_t>(map.size());
  for (size_t i = 0; i < n; ++i) {
    const Keyframe& k = map.keyframe(static_cast<int>(i));
    // Stamps increase with the frame index: binary search for the nearest.
    size_t lo = 0, hi = simulator.size();
    while (lo < hi) {
      const size_t mid = (lo + hi) / 2;
      if (simulator.stamp(mid) < k.stamp) lo = mid + 1; else hi = mid;
    }
    size_t best = simulator.size();
    int64_t best_ns = 1000000;  // 1 ms
    for (size_t c : {lo > 0 ? lo - 1 : lo, lo}) {
      if (c >= simulator.size()) continue;
      const int64_t d = std::llabs(simulator.stamp(c).nanoseconds() - k.stamp.nanoseconds());
      if (d <= best_ns) {
        best_ns = d;
        best = c;
      }
    }
    if (best == simulator.size()) {
      return Status::Error("keyframe " + std::to_string(k.id) +
                           " matches no frame of the scenario (a map of another scenario?)");
    }
    masks_[k.id] = simulator.Render(best).dynamic_mask;
    if (progress) progress(i + 1, n);
  }
  return Status::Ok();
}

bool SimPeopleTruth::OnPerson(int keyframe_id, const cv::Point2f& pixel) const {
  const auto it = masks_.find(keyframe_id);
  if (it == masks_.end() || it->second.empty()) return false;
  const int u = static_cast<int>(std::lround(pixel.x));
  const int v = static_cast<int>(std::lround(pixel.y));
  const cv::Mat& mask = it->second;
  if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) return false;
  return mask.at<uint8_t>(v, u) != 0;
}

}  // namespace icgm
