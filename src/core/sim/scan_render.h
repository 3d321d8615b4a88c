// The closed-loop robot's planar range scanner (ScannerOptions): rays cast in the horizontal
// plane at the scanner's height against the room's walls, the boxes reaching that plane and the
// dynamic cylinders (walkers' body parts) crossing it. 2-D geometry only: a box or cylinder is
// seen when its height range contains the plane.
#pragma once

#include <vector>

#include "core/common/planar_scan.h"
#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/sim/loop_route.h"
#include "core/sim/scene.h"
#include "core/sim/sim_options.h"
#include "core/sim/texture_drawing.h"

namespace icgm::sim {

// The scanner's mounting on the base (T_base_scanner): forward_m ahead of base_link at
// height_m, facing the base's heading.
Pose3 ScannerMountPose(const ScannerOptions& options);

// Distance along the ray from `origin` in unit direction `dir` (floor plane) to the first
// surface of the scene at `height_m` (walls, boxes, cylinders); infinity when none.
double CastPlanarRay(const StaticScene& scene, const std::vector<CylinderPrimitive>& cylinders,
                     const Eigen::Vector2d& origin, const Eigen::Vector2d& dir, double height_m);

// One scan with the base at `base` (world), stamped `stamp`: beams as ScannerOptions says,
// ranges with N(0, range_noise_m^2) noise drawn from `rng`; beyond max_range_m: no return
// (infinity, as LaserScan carries it).
PlanarScan RenderPlanarScan(const ScannerOptions& options, const StaticScene& scene,
                            const std::vector<CylinderPrimitive>& cylinders, const PlanarPose& base,
                            Time stamp, Rng& rng);

}  // namespace icgm::sim
