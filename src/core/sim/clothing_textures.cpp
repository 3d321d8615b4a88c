#include "core/sim/clothing_textures.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "core/sim/texture_drawing.h"

namespace icgm::sim {

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
