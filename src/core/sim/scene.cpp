#include "core/sim/scene.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace icgm::sim {
namespace {

TexturePtr MakeTexture(const cv::Mat& bgr, double texel_m) {
  return std::make_shared<const Texture>(bgr, texel_m);
}

int Texels(double metres, double texel_m) {
  return std::max(8, static_cast<int>(std::lround(metres / texel_m)));
}

// True when a box footprint [x0, x1] x [y0, y1] grown by `margin` stays inside the room, clear
// of the route and of every placed box.
bool FootprintFree(const StaticScene& scene, const PathDistance& route, double x0, double y0,
                   double x1, double y1, double route_clearance_m, double walkway_m,
                   double wall_margin_m) {
  if (x0 < wall_margin_m || y0 < wall_margin_m || x1 > scene.room.width_m - wall_margin_m ||
      y1 > scene.room.length_m - wall_margin_m) {
    return false;
  }
  // Route clearance: a route crossing the footprint also passes close to its outline, so
  // sampling the outline (spacing well below the clearance) covers both cases.
  for (int i = 0; i <= 8; ++i) {
    const double s = i / 8.0;
    const double xs = x0 + s * (x1 - x0), ys = y0 + s * (y1 - y0);
    if (route(xs, y0) < route_clearance_m || route(xs, y1) < route_clearance_m ||
        route(x0, ys) < route_clearance_m || route(x1, ys) < route_clearance_m) {
      return false;
    }
  }
  for (const BoxPrimitive& b : scene.boxes) {
    if (x0 < b.max_m.x() + walkway_m && x1 > b.min_m.x() - walkway_m &&
        y0 < b.max_m.y() + walkway_m && y1 > b.min_m.y() - walkway_m) {
      return false;
    }
  }
  return true;
}

// Tries random placements of a w x d footprint (either orientation); false when none fits.
// With wall_margin_m 0, snap_probability of the attempts put it against a wall.
bool PlaceBox(const PathDistance& route, Rng& rng, double w, double d, double h,
              double route_clearance_m, double walkway_m, double wall_margin_m, TexturePtr side,
              TexturePtr top, StaticScene* scene, double snap_probability = 0.5) {
  for (int attempt = 0; attempt < 200; ++attempt) {
    const bool rotated = Uniform(rng, 0, 1) < 0.5;
    const double sx = rotated ? d : w, sy = rotated ? w : d;
    // Half of the attempts snap to a wall (shelves and counters stand against walls).
    double x0 = Uniform(rng, 0, scene->room.width_m - sx);
    double y0 = Uniform(rng, 0, scene->room.length_m - sy);
    if (wall_margin_m == 0.0 && Uniform(rng, 0, 1) < snap_probability) {
      if (Uniform(rng, 0, 1) < 0.5) {
        x0 = Uniform(rng, 0, 1) < 0.5 ? 0.0 : scene->room.width_m - sx;
      } else {
        y0 = Uniform(rng, 0, 1) < 0.5 ? 0.0 : scene->room.length_m - sy;
      }
    }
    if (!FootprintFree(*scene, route, x0, y0, x0 + sx, y0 + sy, route_clearance_m, walkway_m,
                       wall_margin_m)) {
      continue;
    }
    BoxPrimitive b;
    b.min_m = Eigen::Vector3f(x0, y0, 0.0f);
    b.max_m = Eigen::Vector3f(x0 + sx, y0 + sy, h);
    b.side = std::move(side);
    b.top = std::move(top);
    scene->boxes.push_back(std::move(b));
    return true;
  }
  return false;
}

// The texture with its deviations from the mean colour scaled by `contrast` (1: unchanged).
TexturePtr MakeTexture(const cv::Mat& bgr, double texel_m, double contrast) {
  if (contrast >= 1.0) return MakeTexture(bgr, texel_m);
  const cv::Mat mean(bgr.size(), bgr.type(), cv::mean(bgr));
  cv::Mat toned;
  cv::addWeighted(bgr, contrast, mean, 1.0 - contrast, 0.0, toned);
  return MakeTexture(toned, texel_m);
}

}  // namespace

StaticScene BuildCafeteria(const RoomOptions& o, const LoopRoute& route, Rng& rng,
                           double clearance_m) {
  return BuildCafeteria(
      o, [&route](double x, double y) { return route.DistanceTo(x, y); }, rng, clearance_m);
}

StaticScene BuildCafeteria(const RoomOptions& o, const PathDistance& route, Rng& rng,
                           double clearance_m) {
  StaticScene scene;
  Room& room = scene.room;
  room.width_m = static_cast<float>(o.width_m);
  room.length_m = static_cast<float>(o.length_m);
  room.height_m = static_cast<float>(o.height_m);
  const double texel = o.texel_size_m;
  const double floor_texel = texel;
  room.floor =
      MakeTexture(MakeFloorTexture(rng, Texels(o.width_m, floor_texel),
                                   Texels(o.length_m, floor_texel), Texels(0.5, floor_texel)),
                  floor_texel, o.floor_contrast);
  room.ceiling = MakeTexture(
      MakeCeilingTexture(rng, Texels(o.width_m, 0.05), Texels(o.length_m, 0.05), Texels(1.2, 0.05)),
      0.05);
  for (int w = 0; w < 4; ++w) {
    const double len = (w % 2 == 0) ? o.width_m : o.length_m;
    room.walls[w] = MakeTexture(MakeWallTexture(rng, Texels(len, texel), Texels(o.height_m, texel),
                                                1.0 / texel, o.poster_coverage),
                                texel, o.wall_contrast);
  }
  // Pillars first (structural, floor to ceiling), then shelves, then tables.
  for (int i = 0; i < o.num_pillars; ++i) {
    const double side_m = 0.6;
    auto tex = MakeTexture(MakeWallTexture(rng, Texels(4 * side_m, texel),
                                           Texels(o.height_m, texel), 1.0 / texel, 0.9),
                           texel, o.wall_contrast);
    PlaceBox(route, rng, side_m, side_m, o.height_m, clearance_m, 1.0, 1.0, tex, tex, &scene);
  }
  for (int i = 0; i < o.num_shelves; ++i) {
    const double w = Uniform(rng, 1.2, 2.4), d = 0.5, h = Uniform(rng, 1.4, 2.0);
    auto front = MakeTexture(MakeShelfTexture(rng, Texels(w, texel), Texels(h, texel)), texel,
                             o.furniture_contrast);
    auto top = MakeTexture(MakeTableSideTexture(rng, Texels(w, texel), Texels(d, texel)), texel,
                           o.furniture_contrast);
    PlaceBox(route, rng, w, d, h, clearance_m, 0.9, 0.0, front, top, &scene);
  }
  for (int i = 0; i < o.num_tables; ++i) {
    const double w = Uniform(rng, 1.0, 1.8), d = Uniform(rng, 0.7, 0.9), h = 0.75;
    auto side = MakeTexture(MakeTableSideTexture(rng, Texels(w, texel), Texels(h, texel)), texel,
                            o.furniture_contrast);
    auto top = MakeTexture(MakeTableTopTexture(rng, Texels(w, texel), Texels(d, texel)), texel,
                           o.furniture_contrast);
    PlaceBox(route, rng, w, d, h, clearance_m, 0.7, 0.7, side, top, &scene);
  }
  // Desks against the walls: wooden tops with a few things on them, wooden sides.
  size_t desks = 0;
  for (int i = 0; i < o.num_desks; ++i) {
    const double w = Uniform(rng, 1.2, 1.8), d = Uniform(rng, 0.7, 0.8), h = 0.75;
    auto side = MakeTexture(MakeTableTopTexture(rng, Texels(w, texel), Texels(h, texel)), texel,
                            o.furniture_contrast);
    auto top = MakeTexture(MakeTableTopTexture(rng, Texels(w, texel), Texels(d, texel)), texel,
                           o.furniture_contrast);
    desks += PlaceBox(route, rng, w, d, h, clearance_m, 0.3, 0.0, side, top, &scene, 1.0);
  }
  // Chairs: dark upholstered blocks pulled up to the front of a random desk.
  const size_t first_desk = scene.boxes.size() - std::min<size_t>(scene.boxes.size(), desks);
  for (int i = 0; i < o.num_chairs && first_desk < scene.boxes.size(); ++i) {
    const BoxPrimitive desk =
        scene.boxes[UniformInt(rng, static_cast<int>(first_desk), scene.boxes.size() - 1)];
    cv::Mat fabric(Texels(0.9, texel), Texels(2.0, texel), CV_8UC3,
                   RandomColor(rng, false) * 0.45);
    cv::rectangle(fabric, cv::Rect(0, fabric.rows / 2, fabric.cols, fabric.rows / 10),
                  cv::Scalar(25, 25, 25), cv::FILLED);  // seat edge
    AddNoise(rng, 4.0, false, &fabric);
    auto tex = MakeTexture(fabric, texel, o.furniture_contrast);
    // The desk's open side faces away from the wall it stands against.
    const float gap = 0.05f, w = 0.5f;
    const float along = static_cast<float>(Uniform(rng, 0.0, 1.0));
    Eigen::Vector2f lo;
    const float eps = 1e-3f;
    if (desk.min_m.x() <= eps || desk.max_m.x() >= scene.room.width_m - eps) {
      const float x = desk.min_m.x() <= eps ? desk.max_m.x() + gap : desk.min_m.x() - gap - w;
      lo = {x, desk.min_m.y() + along * (desk.max_m.y() - desk.min_m.y() - w)};
    } else {
      const float y = desk.min_m.y() <= eps ? desk.max_m.y() + gap : desk.min_m.y() - gap - w;
      lo = {desk.min_m.x() + along * (desk.max_m.x() - desk.min_m.x() - w), y};
    }
    if (!FootprintFree(scene, route, lo.x(), lo.y(), lo.x() + w, lo.y() + w, clearance_m, 0.0,
                       0.0)) {
      continue;
    }
    BoxPrimitive chair;
    chair.min_m = Eigen::Vector3f(lo.x(), lo.y(), 0.0f);
    chair.max_m = Eigen::Vector3f(lo.x() + w, lo.y() + w, 0.9f);
    chair.side = tex;
    chair.top = tex;
    scene.boxes.push_back(std::move(chair));
  }
  return scene;
}

}  // namespace icgm::sim
