// Procedural textures of pedestrians: clothing (shirts with prints, stripes, tartan, dots,
// backpacks; trousers with belt, seams and pockets) and heads. Textures wrap around a vertical
// body part: u runs around it with u = 0 at the front (the walking direction), row 0 at the top.
#pragma once

#include <opencv2/core.hpp>

#include "core/sim/texture_drawing.h"

namespace icgm::sim {

cv::Mat MakeClothingTexture(Rng& rng, int cols, int rows, bool trousers);
// Face at u = 0, hair at the back and top.
cv::Mat MakeHeadTexture(Rng& rng, int cols, int rows);

}  // namespace icgm::sim
