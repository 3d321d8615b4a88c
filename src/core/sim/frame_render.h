// The rendering steps every simulator frame goes through, shared by the fixed-route Simulator
// and the ClosedLoopSimulator: ray-cast the scene with the pedestrians' bodies, then (with
// sensor effects) motion blur over the exposure, depth noise and image noise. The random
// numbers of frame `frame_index` come from their own stream (seed, Stream::kFrame, index), so a
// frame is the same whichever simulator and whatever order renders it.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "core/common/pose.h"
#include "core/sim/ray_caster.h"
#include "core/sim/scene.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

namespace icgm::sim {

// The camera's pose `offset_s` seconds from the frame's instant (negative: before it) in the
// camera frame at that instant (T_camera_world * T_world_camera(t + offset)).
using ExposureMotion = std::function<Pose3(double offset_s)>;

// Fills f->bgr, f->depth_m and f->dynamic_mask for a camera at f->T_world_camera (set by the
// caller with the other ground truth). `dynamic`: the pedestrians' body parts (empty without
// pedestrians); `motion` is used for the motion blur only (options.exposure_s > 0).
void RenderSensorFrame(const SimOptions& options, const RayCaster& caster,
                       const StaticScene& scene, const std::vector<CylinderPrimitive>& dynamic,
                       size_t frame_index, const RenderFlags& flags,
                       const ExposureMotion& motion, SimFrame* f);

}  // namespace icgm::sim
