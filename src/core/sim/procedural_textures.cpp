#include "core/sim/procedural_textures.h"

#include <algorithm>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace icgm::sim {
namespace {

int UniformInt(Rng& rng, int lo, int hi) {  // inclusive
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

std::string RandomWord(Rng& rng, int min_len, int max_len) {
  static const char kLetters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::string s;
  const int n = UniformInt(rng, min_len, max_len);
  for (int i = 0; i < n; ++i) s.push_back(kLetters[UniformInt(rng, 0, 35)]);
  return s;
}

// Text lines filling roughly `area` with height line_px.
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

}  // namespace

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
  int x = static_cast<int>(Uniform(rng, 0.1, 0.6) * texels_per_m);
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

cv::Mat MakeClothingTexture(Rng& rng, int cols, int rows, bool trousers) {
  const cv::Scalar base = trousers ? RandomColor(rng, false) * Uniform(rng, 0.2, 0.7)
                                   : RandomColor(rng, Chance(rng, 0.6));
  cv::Mat img(rows, cols, CV_8UC3, base);
  const int cell = UniformInt(rng, 3, 9);
  if (trousers) {
    // Belt with buckle, side seams, pockets front and back (u = 0 is the front).
    const int belt = std::max(2, rows / 14);
    img.rowRange(0, belt).setTo(cv::Scalar(25, 30, 40));
    cv::rectangle(img, cv::Rect(0, 0, std::max(2, cols / 16), belt), cv::Scalar(170, 190, 200),
                  cv::FILLED);
    for (int k = 1; k < 4; k += 2) {
      cv::line(img, {cols * k / 4, belt}, {cols * k / 4, rows}, Shade(base, 1.6), 1);
    }
    for (int k = 0; k < 4; ++k) {
      const int x = cols * (2 * k + 1) / 8 - cols / 16;
      cv::rectangle(img, cv::Rect(x, belt + rows / 12, cols / 8, rows / 6), Shade(base, 1.5), 1);
    }
    AddNoise(rng, 8.0, false, &img);
    return img;
  }
  switch (UniformInt(rng, 0, 4)) {
    case 0:  // multi-coloured horizontal stripes of varying width
      for (int y = 0; y < rows; y += UniformInt(rng, 2 * cell, 4 * cell)) {
        cv::rectangle(img, cv::Rect(0, y, cols, UniformInt(rng, 2, 2 * cell)),
                      RandomColor(rng, true), cv::FILLED);
      }
      break;
    case 1: {  // tartan: two crossing stripe sets
      const cv::Scalar a = RandomColor(rng, true), b = RandomColor(rng, true);
      for (int y = 0; y < rows; y += 4 * cell) img.rowRange(y, std::min(rows, y + cell)).setTo(a);
      for (int x = 0; x < cols; x += 4 * cell) img.colRange(x, std::min(cols, x + cell)).setTo(b);
      break;
    }
    case 2:  // checker
      DrawChecker(&img, cv::Rect(0, 0, cols, rows), 2 * cell, base, RandomColor(rng, true));
      break;
    case 3:  // dots
      for (int k = 0; k < cols * rows / (cell * cell * 4); ++k) {
        cv::circle(img, {UniformInt(rng, 0, cols), UniformInt(rng, 0, rows)},
                   UniformInt(rng, 1, cell / 2 + 1), RandomColor(rng, true), cv::FILLED,
                   cv::LINE_AA);
      }
      break;
    default:
      break;  // plain
  }
  // Print on the chest (u just right of 0 and wrapping to the end) and on the back.
  if (Chance(rng, 0.7)) {
    const int w = cols / 7, h = rows / 3;
    for (const int x : {0, cols - w, cols / 2 - w / 2}) {
      const cv::Rect r(x, rows / 5, w, h);
      img(r).setTo(RandomColor(rng, true));
      cv::circle(img, {x + w / 2, rows / 5 + h / 3}, std::max(2, h / 5), RandomColor(rng, true),
                 cv::FILLED, cv::LINE_AA);
      DrawText(rng, &img, cv::Rect(x, rows / 5 + h / 2, w, h / 2), std::max(4, h / 4),
               cv::Scalar(250, 250, 250));
    }
  }
  // Collar and hem.
  img.rowRange(0, std::max(2, rows / 12)).setTo(Shade(base, 0.5));
  img.rowRange(rows - std::max(2, rows / 16), rows).setTo(Shade(base, 0.6));
  // Sometimes a backpack on the back (u = half the circumference).
  if (Chance(rng, 0.35)) {
    const cv::Scalar bag = RandomColor(rng, Chance(rng, 0.5)) * 0.7;
    const cv::Rect r(cols / 2 - cols / 6, rows / 8, cols / 3, rows * 3 / 4);
    cv::rectangle(img, r, bag, cv::FILLED);
    cv::rectangle(img,
                  cv::Rect(r.x + r.width / 6, r.y + r.height / 2, r.width * 2 / 3, r.height / 3),
                  Shade(bag, 1.4), 2);
    cv::line(img, {r.x + r.width / 2, r.y + r.height / 2}, {r.x + r.width / 2, r.y + r.height},
             cv::Scalar(20, 20, 20), 1);
  }
  AddNoise(rng, 6.0, false, &img);
  return img;
}

cv::Mat MakeHeadTexture(Rng& rng, int cols, int rows) {
  const double tone = Uniform(rng, 0.45, 1.0);
  const cv::Scalar skin(120 * tone + 40, 150 * tone + 40, 190 * tone + 50);
  const cv::Scalar hair = Chance(rng, 0.7) ? cv::Scalar(25, 25, 30) : RandomColor(rng, false) * 0.5;
  cv::Mat img(rows, cols, CV_8UC3, hair);
  // Face spans the front third (u near 0 and near cols), below the hairline.
  const int face_w = cols / 6, hairline = rows / 4;
  img(cv::Rect(0, hairline, face_w, rows - hairline)).setTo(skin);
  img(cv::Rect(cols - face_w, hairline, face_w, rows - hairline)).setTo(skin);
  const int eye_y = rows * 45 / 100, eye_r = std::max(1, rows / 22);
  cv::circle(img, cv::Point(face_w / 2, eye_y), eye_r, cv::Scalar(30, 30, 30), cv::FILLED);
  cv::circle(img, cv::Point(cols - face_w / 2, eye_y), eye_r, cv::Scalar(30, 30, 30), cv::FILLED);
  cv::line(img, cv::Point(cols - face_w / 3, rows * 3 / 4), cv::Point(cols - 1, rows * 3 / 4),
           cv::Scalar(60, 60, 140), std::max(1, rows / 30));
  cv::line(img, cv::Point(0, rows * 3 / 4), cv::Point(face_w / 3, rows * 3 / 4),
           cv::Scalar(60, 60, 140), std::max(1, rows / 30));
  AddNoise(rng, 5.0, false, &img);
  return img;
}

}  // namespace icgm::sim
