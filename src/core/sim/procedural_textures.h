// Procedural BGR textures for the simulated cafeteria (nothing is loaded from disk): floor tiles,
// poster-covered walls and furniture. All are deterministic functions of the random
// engine's state and rich in sharp, high-contrast detail at several scales (corners for ORB).
// Sizes are in texels; the caller decides the metric texel size.
#pragma once

#include <opencv2/core.hpp>

#include "core/sim/texture_drawing.h"

namespace icgm::sim {

// Floor tiles of tile_px texels with grout, speckles and stains.
cv::Mat MakeFloorTexture(Rng& rng, int cols, int rows, int tile_px);
// Ceiling panels with light fixtures.
cv::Mat MakeCeilingTexture(Rng& rng, int cols, int rows, int panel_px);
// A wall of cols x rows texels (row 0 at the ceiling): paint, skirting board and posters over
// `poster_coverage` of its length (none when 0); texels_per_m places them at plausible heights.
cv::Mat MakeWallTexture(Rng& rng, int cols, int rows, double texels_per_m, double poster_coverage);
// A poster: background plus rectangles, blobs, checkers, gradients, stripes and text.
cv::Mat MakePoster(Rng& rng, int cols, int rows);
// Table top with trays, plates and cups; table side (cloth pattern).
cv::Mat MakeTableTopTexture(Rng& rng, int cols, int rows);
cv::Mat MakeTableSideTexture(Rng& rng, int cols, int rows);
// Shelf front with rows of products and price labels.
cv::Mat MakeShelfTexture(Rng& rng, int cols, int rows);
}  // namespace icgm::sim
