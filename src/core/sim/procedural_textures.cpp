#include "core/sim/procedural_textures.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "core/sim/texture_drawing.h"

namespace icgm::sim {

cv::Mat MakePoster(Rng& rng, int cols, int rows) {
  cv::Mat img(rows, cols, CV_8UC3, RandomColor(rng, Chance(rng, 0.5)));
  const cv::Size size(cols, rows);
  const int elements = UniformInt(rng, 4, 9);
  for (int i = 0; i < elements; ++i) {
    const cv::Rect r = RandomSubRect(rng, size, 0.1, 0.6);
    const cv::Scalar c = RandomColor(rng, true);
    switch (UniformInt(rng, 0, 5)) {
      case 0:
        cv::rectangle(img, r, c, cv::FILLED);
        break;
      case 1:
        cv::ellipse(img, (r.tl() + r.br()) / 2, r.size() / 2, Uniform(rng, 0, 180), 0, 360, c,
                    cv::FILLED, cv::LINE_AA);
        break;
      case 2:
        DrawChecker(&img, r, std::max(2, std::min(r.width, r.height) / UniformInt(rng, 3, 8)), c,
                    RandomColor(rng, Chance(rng, 0.5)));
        break;
      case 3:
        DrawGradient(&img, r, c, RandomColor(rng, true));
        break;
      case 4: {
        const int stripe = std::max(2, r.width / UniformInt(rng, 4, 12));
        for (int x = r.x; x < r.x + r.width; x += 2 * stripe) {
          cv::rectangle(img, cv::Rect(x, r.y, std::min(stripe, r.x + r.width - x), r.height), c,
                        cv::FILLED);
        }
        break;
      }
      default:
        for (int k = 0; k < 6; ++k) {
          cv::circle(
              img,
              cv::Point(UniformInt(rng, r.x, r.x + r.width), UniformInt(rng, r.y, r.y + r.height)),
              UniformInt(rng, 2, std::max(3, r.height / 4)), RandomColor(rng, true), cv::FILLED,
              cv::LINE_AA);
        }
    }
  }
  // Title and body text at two scales, dark or light.
  const cv::Scalar ink = Chance(rng, 0.5) ? cv::Scalar(20, 20, 20) : cv::Scalar(245, 245, 245);
  const int title_px = std::max(6, rows / UniformInt(rng, 6, 10));
  DrawText(rng, &img, cv::Rect(cols / 12, rows / 20, cols * 5 / 6, title_px * 2), title_px, ink);
  const int body_px = std::max(4, rows / UniformInt(rng, 18, 30));
  DrawText(rng, &img, cv::Rect(cols / 12, rows * 2 / 3, cols * 5 / 6, rows / 4), body_px, ink);
  cv::rectangle(img, cv::Rect(0, 0, cols, rows), cv::Scalar(30, 30, 30), std::max(1, cols / 60));
  AddNoise(rng, 4.0, false, &img);
  return img;
}

cv::Mat MakeFloorTexture(Rng& rng, int cols, int rows, int tile_px) {
  const cv::Scalar a = RandomColor(rng, false) * 0.8, b = RandomColor(rng, false) * 0.6;
  cv::Mat img(rows, cols, CV_8UC3);
  for (int y = 0; y < rows; y += tile_px) {
    for (int x = 0; x < cols; x += tile_px) {
      const bool odd = ((x / tile_px) + (y / tile_px)) % 2;
      const cv::Scalar c = Shade(odd ? a : b, Uniform(rng, 0.85, 1.15));
      cv::rectangle(img, cv::Rect(x, y, tile_px, tile_px), c, cv::FILLED);
      // Speckles: small dark and bright flecks typical of terrazzo tiles.
      for (int k = 0; k < 6; ++k) {
        cv::circle(img, cv::Point(x + UniformInt(rng, 0, tile_px), y + UniformInt(rng, 0, tile_px)),
                   UniformInt(rng, 1, std::max(1, tile_px / 14)),
                   Shade(c, Chance(rng, 0.5) ? 0.4 : 1.5), cv::FILLED);
      }
    }
  }
  for (int y = 0; y < rows; y += tile_px)
    cv::line(img, {0, y}, {cols, y}, cv::Scalar(60, 60, 60), 2);
  for (int x = 0; x < cols; x += tile_px)
    cv::line(img, {x, 0}, {x, rows}, cv::Scalar(60, 60, 60), 2);
  const int stains = cols * rows / (tile_px * tile_px * 3);
  for (int k = 0; k < stains; ++k) {
    cv::ellipse(img, cv::Point(UniformInt(rng, 0, cols), UniformInt(rng, 0, rows)),
                cv::Size(UniformInt(rng, 2, tile_px / 3), UniformInt(rng, 2, tile_px / 4)),
                Uniform(rng, 0, 180), 0, 360, RandomColor(rng, Chance(rng, 0.3)) * 0.5, cv::FILLED,
                cv::LINE_AA);
  }
  AddNoise(rng, 6.0, true, &img);
  return img;
}

cv::Mat MakeCeilingTexture(Rng& rng, int cols, int rows, int panel_px) {
  cv::Mat img(rows, cols, CV_8UC3, cv::Scalar(200, 205, 210));
  for (int y = 0; y < rows; y += panel_px) {
    for (int x = 0; x < cols; x += panel_px) {
      if (Chance(rng, 0.25)) {
        cv::rectangle(
            img, cv::Rect(x + panel_px / 6, y + panel_px / 6, panel_px * 2 / 3, panel_px * 2 / 3),
            cv::Scalar(250, 250, 250), cv::FILLED);
      }
      cv::rectangle(img, cv::Rect(x, y, panel_px, panel_px), cv::Scalar(120, 120, 125), 2);
    }
  }
  AddNoise(rng, 5.0, true, &img);
  return img;
}

cv::Mat MakeWallTexture(Rng& rng, int cols, int rows, double texels_per_m, double poster_coverage) {
  const cv::Scalar paint = RandomColor(rng, false);
  cv::Mat img(rows, cols, CV_8UC3);
  DrawGradient(&img, cv::Rect(0, 0, cols, rows), Shade(paint, 1.1), Shade(paint, 0.85));
  const auto row_at = [&](double height_m) {
    return std::clamp(rows - static_cast<int>(height_m * texels_per_m), 0, rows - 1);
  };
  // Wainscot below 0.9 m with vertical panels, skirting board below 0.12 m.
  const cv::Scalar wainscot = RandomColor(rng, false) * 0.7;
  cv::rectangle(img, cv::Rect(0, row_at(0.9), cols, rows - row_at(0.9)), wainscot, cv::FILLED);
  const int panel = static_cast<int>(0.6 * texels_per_m);
  for (int x = 0; x < cols; x += panel) {
    cv::rectangle(img,
                  cv::Rect(x + panel / 10, row_at(0.8), panel * 8 / 10, row_at(0.2) - row_at(0.8)),
                  Shade(wainscot, 0.75), 3);
  }
  cv::rectangle(img, cv::Rect(0, row_at(0.12), cols, rows - row_at(0.12)), cv::Scalar(40, 40, 45),
                cv::FILLED);
  // Posters left to right with random gaps, so that about poster_coverage of the wall is covered.
  // Coverage 0: a bare wall (no draws, so other coverages keep their random sequence).
  int x = poster_coverage > 0.0 ? static_cast<int>(Uniform(rng, 0.1, 0.6) * texels_per_m) : cols;
  while (x < cols) {
    const int w = static_cast<int>(Uniform(rng, 0.5, 1.6) * texels_per_m);
    const double h_m = Uniform(rng, 0.6, 1.3);
    const double bottom_m = Uniform(rng, 0.95, 1.3);
    const int h = static_cast<int>(h_m * texels_per_m);
    const int y = row_at(bottom_m + h_m);
    if (x + w < cols && y >= 0) {
      MakePoster(rng, w, h).copyTo(img(cv::Rect(x, y, w, h)));
    }
    const double gap_mean = w * (1.0 - poster_coverage) / std::max(poster_coverage, 0.05);
    x += w + static_cast<int>(Uniform(rng, 0.5, 1.5) * gap_mean) + 2;
  }
  AddNoise(rng, 4.0, true, &img);
  return img;
}

cv::Mat MakeTableTopTexture(Rng& rng, int cols, int rows) {
  const cv::Scalar wood = RandomColor(rng, false) * 0.75;
  cv::Mat img(rows, cols, CV_8UC3, wood);
  for (int y = 0; y < rows; y += UniformInt(rng, 3, 9)) {  // grain
    cv::line(img, {0, y}, {cols, y + UniformInt(rng, -4, 4)}, Shade(wood, Uniform(rng, 0.7, 1.2)),
             1);
  }
  const int items = std::max(3, cols * rows / 900);
  for (int k = 0; k < items; ++k) {
    const cv::Point p(UniformInt(rng, 0, cols), UniformInt(rng, 0, rows));
    const int r = UniformInt(rng, std::max(3, rows / 14), std::max(4, rows / 6));
    if (Chance(rng, 0.5)) {  // plate with food
      cv::circle(img, p, r, cv::Scalar(240, 240, 240), cv::FILLED, cv::LINE_AA);
      cv::circle(img, p, r * 2 / 3, RandomColor(rng, true), cv::FILLED, cv::LINE_AA);
    } else {  // tray
      cv::rectangle(img, cv::Rect(p.x, p.y, 2 * r, r + r / 2), RandomColor(rng, true), cv::FILLED);
    }
  }
  AddNoise(rng, 5.0, false, &img);
  return img;
}

cv::Mat MakeTableSideTexture(Rng& rng, int cols, int rows) {
  cv::Mat img(rows, cols, CV_8UC3, RandomColor(rng, true));
  const int cell = UniformInt(rng, 4, 14);
  if (Chance(rng, 0.5)) {
    DrawChecker(&img, cv::Rect(0, 0, cols, rows), cell, RandomColor(rng, true),
                RandomColor(rng, false));
  } else {
    for (int y = 0; y < rows; y += 2 * cell) {
      cv::rectangle(img, cv::Rect(0, y, cols, cell), RandomColor(rng, false), cv::FILLED);
    }
    for (int x = 0; x < cols; x += 3 * cell) {
      cv::rectangle(img, cv::Rect(x, 0, cell / 2 + 1, rows), RandomColor(rng, true), cv::FILLED);
    }
  }
  AddNoise(rng, 5.0, false, &img);
  return img;
}

cv::Mat MakeShelfTexture(Rng& rng, int cols, int rows) {
  cv::Mat img(rows, cols, CV_8UC3, cv::Scalar(70, 80, 90));
  const int shelf_h = std::max(8, rows / 5);
  for (int y = 0; y < rows; y += shelf_h) {
    int x = 2;
    while (x < cols) {
      const int w = UniformInt(rng, std::max(3, shelf_h / 4), std::max(4, shelf_h * 2 / 3));
      const int h = UniformInt(rng, shelf_h / 2, shelf_h * 9 / 10);
      const cv::Scalar c = RandomColor(rng, true);
      cv::rectangle(img, cv::Rect(x, y + shelf_h - h - 3, w, h), c, cv::FILLED);
      cv::rectangle(img, cv::Rect(x + w / 4, y + shelf_h - h / 2 - 3, w / 2, h / 4),
                    Shade(RandomColor(rng, false), 1.2), cv::FILLED);  // label
      x += w + UniformInt(rng, 1, 4);
    }
    cv::rectangle(img, cv::Rect(0, y + shelf_h - 4, cols, 4), cv::Scalar(200, 200, 200),
                  cv::FILLED);
  }
  AddNoise(rng, 4.0, false, &img);
  return img;
}
}  // namespace icgm::sim
