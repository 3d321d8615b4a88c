// A pedestrian's body as textured vertical cylinders (two legs, torso, two arms, head) that
// swing with the gait phase, so walkers deform non-rigidly as real ones do.
#pragma once

#include <vector>

#include "core/sim/clothing_textures.h"
#include "core/sim/scene.h"

namespace icgm::sim {

// Per-person appearance, fixed for the whole sequence.
struct PedestrianLook {
  float height_m = 1.7f;
  float torso_radius_m = 0.19f;
  TexturePtr legs;
  TexturePtr torso;
  TexturePtr arms;
  TexturePtr head;
};

// Where a pedestrian is at one instant: floor position, walking direction and gait phase
// (radians; one cycle is two steps).
struct PedestrianState {
  float x_m = 0.0f;
  float y_m = 0.0f;
  float heading_rad = 0.0f;
  float gait_phase_rad = 0.0f;
  // Stride swing amplitude of the feet in metres (0 when standing).
  float swing_m = 0.0f;
};

// Random height, build and clothing.
PedestrianLook MakePedestrianLook(Rng& rng, double texel_size_m);

// Appends the six body-part cylinders (all `dynamic`).
void AppendBodyParts(const PedestrianLook& look, const PedestrianState& state,
                     std::vector<CylinderPrimitive>* out);

// Radius of a disc on the floor containing the whole body.
inline float BodyRadius(const PedestrianLook& look) { return look.torso_radius_m + 0.16f; }

}  // namespace icgm::sim
