#include "core/sim/texture_drawing.h"

#include <algorithm>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace icgm::sim {

int UniformInt(Rng& rng, int lo, int hi) {
  if (hi <= lo) return lo;
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}
double Uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
bool Chance(Rng& rng, double p) { return Uniform(rng, 0.0, 1.0) < p; }

cv::Scalar Shade(const cv::Scalar& c, double f) {
  return cv::Scalar(std::min(255.0, c[0] * f), std::min(255.0, c[1] * f),
                    std::min(255.0, c[2] * f));
}

namespace {

std::string RandomWord(Rng& rng, int min_len, int max_len) {
  static const char kLetters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::string s;
  const int n = UniformInt(rng, min_len, max_len);
  for (int i = 0; i < n; ++i) s.push_back(kLetters[UniformInt(rng, 0, 35)]);
  return s;
}

}  // namespace

void DrawText(Rng& rng, cv::Mat* img, const cv::Rect& area, int line_px, const cv::Scalar& color) {
  const double scale = line_px / 30.0;
  const int thickness = std::max(1, line_px / 10);
  for (int y = area.y + line_px; y <= area.y + area.height; y += line_px + line_px / 2) {
    int x = area.x;
    while (x < area.x + area.width) {
      const std::string w = RandomWord(rng, 2, 7);
      int base = 0;
      const cv::Size sz = cv::getTextSize(w, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &base);
      if (x + sz.width > area.x + area.width) break;
      cv::putText(*img, w, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale, color, thickness,
                  cv::LINE_AA);
      x += sz.width + line_px / 2;
    }
  }
}

void DrawChecker(cv::Mat* img, const cv::Rect& r, int cell, const cv::Scalar& a,
                 const cv::Scalar& b) {
  for (int y = r.y; y < r.y + r.height; y += cell) {
    for (int x = r.x; x < r.x + r.width; x += cell) {
      const bool odd = (((x - r.x) / cell) + ((y - r.y) / cell)) % 2;
      cv::rectangle(
          *img,
          cv::Rect(x, y, std::min(cell, r.x + r.width - x), std::min(cell, r.y + r.height - y)),
          odd ? a : b, cv::FILLED);
    }
  }
}

void DrawGradient(cv::Mat* img, const cv::Rect& r, const cv::Scalar& a, const cv::Scalar& b) {
  for (int y = r.y; y < r.y + r.height; ++y) {
    const double s = (y - r.y) / std::max(1.0, r.height - 1.0);
    cv::line(*img, cv::Point(r.x, y), cv::Point(r.x + r.width - 1, y), a * (1.0 - s) + b * s);
  }
}

cv::Rect RandomSubRect(Rng& rng, const cv::Size& size, double min_frac, double max_frac) {
  const int w = std::max(2, static_cast<int>(size.width * Uniform(rng, min_frac, max_frac)));
  const int h = std::max(2, static_cast<int>(size.height * Uniform(rng, min_frac, max_frac)));
  return cv::Rect(UniformInt(rng, 0, std::max(0, size.width - w)),
                  UniformInt(rng, 0, std::max(0, size.height - h)), w, h);
}

cv::Scalar RandomColor(Rng& rng, bool saturated) {
  if (!saturated) {
    const double base = Uniform(rng, 120, 225);
    return cv::Scalar(base + Uniform(rng, -25, 25), base + Uniform(rng, -25, 25),
                      base + Uniform(rng, -25, 25));
  }
  cv::Scalar c;
  for (int i = 0; i < 3; ++i) c[i] = Uniform(rng, 0, 255);
  c[UniformInt(rng, 0, 2)] = Uniform(rng, 0, 60);  // one dark channel: vivid hue
  return c;
}

void AddNoise(Rng& rng, double sigma, bool mono, cv::Mat* bgr) {
  if (sigma <= 0) return;
  cv::RNG cv_rng(rng());
  cv::Mat noise(bgr->size(), mono ? CV_16SC1 : CV_16SC3);
  cv_rng.fill(noise, cv::RNG::NORMAL, 0, sigma);
  if (mono) cv::merge(std::vector<cv::Mat>{noise, noise, noise}, noise);
  cv::Mat wide;
  bgr->convertTo(wide, CV_16SC3);
  wide += noise;
  wide.convertTo(*bgr, CV_8UC3);
}
}  // namespace icgm::sim
