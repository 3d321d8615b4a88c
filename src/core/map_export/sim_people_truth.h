// Ground truth of walkers for a map built from a simulated scenario: the simulator's dynamic
// mask (255 where a pedestrian is the visible surface) at each keyframe's stamp, rendered again
// from the scenario (rendering is a deterministic function of the scenario).
#pragma once

#include <functional>
#include <map>

#include <opencv2/core.hpp>

#include "core/common/status.h"
#include "core/map/hybrid_map.h"
#include "core/map_export/people_share.h"
#include "core/sim/simulator.h"

namespace icgm {

class SimPeopleTruth {
 public:
  // Renders the masks of the frames whose stamps match `map`'s keyframes (within 1 ms). Fails
  // naming the first keyframe that matches no frame (a map of another scenario). `progress`:
  // (keyframes done, keyframes).
  Status Build(const sim::Simulator& simulator, const HybridMap& map,
               const std::function<void(size_t, size_t)>& progress = nullptr);
  // Whether a walker is the visible surface at full-image `pixel` of keyframe `keyframe_id`.
  bool OnPerson(int keyframe_id, const cv::Point2f& pixel) const;
  PersonTruth AsFunction() const {
    return [this](int id, const cv::Point2f& px) { return OnPerson(id, px); };
  }

 private:
  std::map<int, cv::Mat> masks_;  // keyframe id -> CV_8UC1 dynamic mask
};

}  // namespace icgm
