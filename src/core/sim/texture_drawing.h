// Drawing primitives shared by the procedural texture generators: random draws from the
// simulation's engine and shapes (text, checkers, gradients) drawn into BGR images.
#pragma once

#include <random>
#include <string>

#include <opencv2/core.hpp>

namespace icgm::sim {

using Rng = std::mt19937_64;

// Uniform integer in [lo, hi] (lo when hi <= lo) and uniform real in [lo, hi).
int UniformInt(Rng& rng, int lo, int hi);
double Uniform(Rng& rng, double lo, double hi);
bool Chance(Rng& rng, double p);

// A saturated (vivid hue) or muted random colour.
cv::Scalar RandomColor(Rng& rng, bool saturated);
// Colour scaled by f, saturating at 255.
cv::Scalar Shade(const cv::Scalar& c, double f);
// Adds zero-mean Gaussian grey-level noise (same on all channels when `mono`).
void AddNoise(Rng& rng, double sigma, bool mono, cv::Mat* bgr);

// Random words (capital letters and digits) in lines of height line_px filling `area`.
void DrawText(Rng& rng, cv::Mat* img, const cv::Rect& area, int line_px, const cv::Scalar& color);
// Checkerboard of `cell`-texel squares over r.
void DrawChecker(cv::Mat* img, const cv::Rect& r, int cell, const cv::Scalar& a,
                 const cv::Scalar& b);
// Vertical gradient from a (top) to b (bottom) over r.
void DrawGradient(cv::Mat* img, const cv::Rect& r, const cv::Scalar& a, const cv::Scalar& b);
// A random sub-rectangle of `size` with sides between min_frac and max_frac of it.
cv::Rect RandomSubRect(Rng& rng, const cv::Size& size, double min_frac, double max_frac);

}  // namespace icgm::sim
