// Geometry of the simulated world (world frame: z up, floor at z = 0): a closed room, furniture
// boxes and vertical cylinders, each with a metric texture. BuildCafeteria furnishes the room
// deterministically from the random engine, keeping the robot's route clear.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/sim/loop_route.h"
#include "core/sim/procedural_textures.h"
#include "core/sim/sim_options.h"
#include "core/sim/texture.h"

namespace icgm::sim {

using TexturePtr = std::shared_ptr<const Texture>;

// Axis-aligned box. Side faces sample `side` with u along the face and v downwards from the top
// edge; the top face samples `top` with (u, v) = (x, y) relative to the minimum corner.
struct BoxPrimitive {
  Eigen::Vector3f min_m;
  Eigen::Vector3f max_m;
  TexturePtr side;
  TexturePtr top;
};

// Vertical cylinder. The side samples `texture` with u = arc length counter-clockwise from the
// heading direction (u = 0 faces heading_rad) and v downwards from the top; `dynamic` surfaces
// are marked in the dynamic mask.
struct CylinderPrimitive {
  float x_m = 0.0f;
  float y_m = 0.0f;
  float radius_m = 0.1f;
  float z_min_m = 0.0f;
  float z_max_m = 1.0f;
  float heading_rad = 0.0f;
  TexturePtr texture;
  bool dynamic = true;
};

// The room's inside faces; walls are indexed south (y = 0), east (x = W), north (y = L),
// west (x = 0), each texture spanning its wall left to right as seen from inside.
struct Room {
  float width_m = 20.0f;
  float length_m = 20.0f;
  float height_m = 3.2f;
  TexturePtr floor;
  TexturePtr ceiling;
  TexturePtr walls[4];
};

struct StaticScene {
  Room room;
  std::vector<BoxPrimitive> boxes;
};

// Distance from a floor point (x_m, y_m) to the path the camera takes.
using PathDistance = std::function<double(double x_m, double y_m)>;

// Tables, shelves and pillars (then desks against the walls, chairs at the desks) placed at
// random where they leave `clearance_m` free around the camera's path (and a walkway between);
// posters on walls and pillars; textures toned down by the options' contrasts.
StaticScene BuildCafeteria(const RoomOptions& options, const PathDistance& path, Rng& rng,
                           double clearance_m = 1.2);
// The same around the robot's loop route.
StaticScene BuildCafeteria(const RoomOptions& options, const LoopRoute& route, Rng& rng,
                           double clearance_m = 1.2);

}  // namespace icgm::sim
