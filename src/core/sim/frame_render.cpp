#include "core/sim/frame_render.h"

#include "core/sim/depth_noise.h"
#include "core/sim/texture_drawing.h"
#include "core/sim/motion_blur.h"
#include "core/sim/random_streams.h"

namespace icgm::sim {

void RenderSensorFrame(const SimOptions& options, const RayCaster& caster,
                       const StaticScene& scene, const std::vector<CylinderPrimitive>& dynamic,
                       size_t frame_index, const RenderFlags& flags,
                       const ExposureMotion& motion, SimFrame* f) {
  IdealImage ideal;
  caster.Render(scene, dynamic, f->T_world_camera, &ideal);
  f->bgr = ideal.bgr;
  f->dynamic_mask = ideal.mask;
  if (!flags.sensor_effects) {
    f->depth_m = ideal.depth_m;
    return;
  }
  if (options.exposure_s > 0.0) {
    const double half = 0.5 * options.exposure_s;
    ApplyMotionBlur(options.intrinsics, ideal.depth_m, motion(-half), motion(half), &f->bgr);
  }
  Rng frame_rng(StreamSeed(options.seed, Stream::kFrame, frame_index));
  ApplyDepthNoise(options.depth_noise, ideal.depth_m, frame_rng, &f->depth_m);
  AddNoise(frame_rng, options.image_noise_sigma, false, &f->bgr);
}

}  // namespace icgm::sim
