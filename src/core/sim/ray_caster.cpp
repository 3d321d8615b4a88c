#include "core/sim/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace icgm::sim {

// Rays are d = R_wc * (x_norm, y_norm, 1), so the ray parameter t equals the camera z depth.
struct RayCaster::View {
  Eigen::Matrix3f R;    // R_world_camera
  Eigen::Vector3f o;    // camera centre in the world
  float inv_fx = 0.0f;  // footprint of one pixel at unit range, radians
};

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNearM = 0.02f;

// Writes a shaded texel into the colour image.
inline void PutShaded(const Texture& tex, float u, float v, float footprint, float shade,
                      uint8_t* dst) {
  uint8_t c[3];
  tex.Sample(u, v, footprint, c);
  const int s = static_cast<int>(shade * 256.0f);
  dst[0] = static_cast<uint8_t>(std::min(255, (c[0] * s) >> 8));
  dst[1] = static_cast<uint8_t>(std::min(255, (c[1] * s) >> 8));
  dst[2] = static_cast<uint8_t>(std::min(255, (c[2] * s) >> 8));
}

// Pixel footprint on a surface: range / (f cos(incidence)), with |d|^2 = range^2 / t^2.
inline float Footprint(float t, float d2, float d_normal_abs, float inv_fx) {
  const float min_cos_d = 0.15f * std::sqrt(d2);
  return t * d2 * inv_fx / std::max(d_normal_abs, min_cos_d);
}

// atan2 with |error| < 1e-4 rad (minimax polynomial on [0, 1] plus octant folding); texture
// lookups on cylinders do not need libm's precision but call it for every covered pixel.
inline float FastAtan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float mx = std::max(ax, ay);
  if (mx == 0.0f) return 0.0f;
  const float a = std::min(ax, ay) / mx;
  const float s = a * a;
  float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  if (ay > ax) r = 1.57079637f - r;
  if (x < 0.0f) r = 3.14159274f - r;
  return y < 0.0f ? -r : r;
}

}  // namespace

RayCaster::RayCaster(const CameraIntrinsics& intrinsics) : intrinsics_(intrinsics) {
  x_norm_.resize(intrinsics.width_px);
  y_norm_.resize(intrinsics.height_px);
  for (int u = 0; u < intrinsics.width_px; ++u) {
    x_norm_[u] = static_cast<float>((u - intrinsics.cx_px) / intrinsics.fx_px);
  }
  for (int v = 0; v < intrinsics.height_px; ++v) {
    y_norm_[v] = static_cast<float>((v - intrinsics.cy_px) / intrinsics.fy_px);
  }
}

void RayCaster::Render(const StaticScene& scene, const std::vector<CylinderPrimitive>& dynamic,
                       const Pose3& T_world_camera, IdealImage* out) const {
  const cv::Size size(intrinsics_.width_px, intrinsics_.height_px);
  out->bgr.create(size, CV_8UC3);
  out->depth_m.create(size, CV_32FC1);
  out->mask.create(size, CV_8UC1);
  out->mask.setTo(0);
  View view;
  view.R = T_world_camera.linear().cast<float>();
  view.o = T_world_camera.translation().cast<float>();
  view.inv_fx = static_cast<float>(1.0 / intrinsics_.fx_px);
  RenderRoom(scene.room, view, out);
  for (const BoxPrimitive& box : scene.boxes) RenderBox(box, view, out);
  // Front to back, so that occluded pedestrians fail the z-test before any texturing.
  std::vector<std::pair<float, const CylinderPrimitive*>> order;
  order.reserve(dynamic.size());
  for (const CylinderPrimitive& cyl : dynamic) {
    const float dx = cyl.x_m - view.o.x(), dy = cyl.y_m - view.o.y();
    order.emplace_back(dx * dx + dy * dy, &cyl);
  }
  std::sort(order.begin(), order.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& entry : order) RenderCylinder(*entry.second, view, out);
}

void RayCaster::RenderRoom(const Room& room, const View& view, IdealImage* out) const {
  const Eigen::Vector3f size(room.width_m, room.length_m, room.height_m);
  const Eigen::Vector3f& o = view.o;
  // Shading per face: floor, ceiling, south, east, north, west.
  constexpr float kShade[6] = {0.95f, 0.8f, 0.8f, 0.9f, 0.75f, 0.85f};
  for (int v = 0; v < out->bgr.rows; ++v) {
    const Eigen::Vector3f row = view.R.col(1) * y_norm_[v] + view.R.col(2);
    uint8_t* bgr = out->bgr.ptr<uint8_t>(v);
    float* depth = out->depth_m.ptr<float>(v);
    for (int u = 0; u < out->bgr.cols; ++u) {
      const Eigen::Vector3f d = row + view.R.col(0) * x_norm_[u];
      float t_best = kInf;
      int axis = 0;
      for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0f) continue;
        const float t = ((d[a] > 0.0f ? size[a] : 0.0f) - o[a]) / d[a];
        if (t < t_best) {
          t_best = t;
          axis = a;
        }
      }
      const Eigen::Vector3f p = o + t_best * d;
      const float d2 = d.squaredNorm();
      const float fp = Footprint(t_best, d2, std::abs(d[axis]), view.inv_fx);
      uint8_t* dst = bgr + 3 * u;
      if (axis == 2) {
        const bool floor = d.z() < 0.0f;
        PutShaded(floor ? *room.floor : *room.ceiling, p.x(), p.y(), fp, kShade[floor ? 0 : 1],
                  dst);
      } else {
        // Wall index and u coordinate running left to right as seen from inside the room.
        int wall;
        float wu;
        if (axis == 1) {
          wall = d.y() < 0.0f ? 0 : 2;
          wu = wall == 0 ? room.width_m - p.x() : p.x();
        } else {
          wall = d.x() > 0.0f ? 1 : 3;
          wu = wall == 1 ? room.length_m - p.y() : p.y();
        }
        PutShaded(*room.walls[wall], wu, room.height_m - p.z(), fp, kShade[2 + wall], dst);
      }
      depth[u] = t_best;
    }
  }
}

cv::Rect RayCaster::ScreenRect(const View& view, const Eigen::Vector3f& lo,
                               const Eigen::Vector3f& hi) const {
  // Bound the projection of the box clipped by the near plane: its vertices are the corners in
  // front of the camera plus the points where edges cross the near plane.
  const Eigen::Matrix3f Rt = view.R.transpose();
  Eigen::Vector3f pc[8];
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3f corner((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                                 (i & 4) ? hi.z() : lo.z());
    pc[i] = Rt * (corner - view.o);
  }
  float u0 = kInf, v0 = kInf, u1 = -kInf, v1 = -kInf;
  const auto add = [&](const Eigen::Vector3f& p) {
    const float u = static_cast<float>(intrinsics_.fx_px) * p.x() / p.z() + intrinsics_.cx_px;
    const float v = static_cast<float>(intrinsics_.fy_px) * p.y() / p.z() + intrinsics_.cy_px;
    u0 = std::min(u0, u);
    u1 = std::max(u1, u);
    v0 = std::min(v0, v);
    v1 = std::max(v1, v);
  };
  int in_front = 0;
  for (int i = 0; i < 8; ++i) {
    if (pc[i].z() > kNearM) {
      add(pc[i]);
      ++in_front;
    }
  }
  if (in_front == 0) return {};
  if (in_front < 8) {
    for (int i = 0; i < 8; ++i) {
      for (int bit = 1; bit < 8; bit <<= 1) {
        const int j = i | bit;
        if (j == i) continue;
        const Eigen::Vector3f& a = pc[i];
        const Eigen::Vector3f& b = pc[j];
        if ((a.z() > kNearM) == (b.z() > kNearM)) continue;
        const float s = (kNearM - a.z()) / (b.z() - a.z());
        Eigen::Vector3f p = a + s * (b - a);
        p.z() = kNearM;
        add(p);
      }
    }
  }
  const cv::Rect full(0, 0, intrinsics_.width_px, intrinsics_.height_px);
  // Clamp before converting: near-plane points can project very far outside the image.
  const auto clamp_u = [&](float u) { return std::clamp(u, -1.0f, full.width + 1.0f); };
  const auto clamp_v = [&](float v) { return std::clamp(v, -1.0f, full.height + 1.0f); };
  const cv::Rect r(cv::Point(static_cast<int>(std::floor(clamp_u(u0))) - 1,
                             static_cast<int>(std::floor(clamp_v(v0))) - 1),
                   cv::Point(static_cast<int>(std::ceil(clamp_u(u1))) + 2,
                             static_cast<int>(std::ceil(clamp_v(v1))) + 2));
  return r & full;
}

void RayCaster::RenderBox(const BoxPrimitive& box, const View& view, IdealImage* out) const {
  const cv::Rect rect = ScreenRect(view, box.min_m, box.max_m);
  if (rect.empty()) return;
  const Eigen::Vector3f& o = view.o;
  if ((o.array() > box.min_m.array()).all() && (o.array() < box.max_m.array()).all()) return;
  constexpr float kSideShade[2][2] = {{0.8f, 0.7f}, {0.9f, 0.75f}};  // [axis][positive face]
  for (int v = rect.y; v < rect.y + rect.height; ++v) {
    const Eigen::Vector3f row = view.R.col(1) * y_norm_[v] + view.R.col(2);
    uint8_t* bgr = out->bgr.ptr<uint8_t>(v);
    float* depth = out->depth_m.ptr<float>(v);
    for (int u = rect.x; u < rect.x + rect.width; ++u) {
      const Eigen::Vector3f d = row + view.R.col(0) * x_norm_[u];
      float t_near = -kInf, t_far = kInf;
      int axis = 0;
      for (int a = 0; a < 3; ++a) {
        const float inv = 1.0f / d[a];  // +-inf for d[a] == 0 keeps the slab test valid
        float t0 = (box.min_m[a] - o[a]) * inv, t1 = (box.max_m[a] - o[a]) * inv;
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > t_near) {
          t_near = t0;
          axis = a;
        }
        t_far = std::min(t_far, t1);
      }
      if (!(t_near <= t_far) || t_near <= kNearM || t_near >= depth[u]) continue;
      const Eigen::Vector3f p = o + t_near * d;
      const float fp = Footprint(t_near, d.squaredNorm(), std::abs(d[axis]), view.inv_fx);
      uint8_t* dst = bgr + 3 * u;
      if (axis == 2) {
        PutShaded(*box.top, p.x() - box.min_m.x(), p.y() - box.min_m.y(), fp, 1.0f, dst);
      } else {
        // Face normal points against the ray; u runs left to right as seen from outside.
        const bool positive_face = d[axis] < 0.0f;
        float fu;
        if (axis == 0) {
          fu = positive_face ? p.y() - box.min_m.y() : box.max_m.y() - p.y();
        } else {
          fu = positive_face ? box.max_m.x() - p.x() : p.x() - box.min_m.x();
        }
        // Offset per face so that opposite faces show different parts of the texture.
        fu += (2 * axis + positive_face) * 0.37f * static_cast<float>(box.side->width_m());
        PutShaded(*box.side, fu, box.max_m.z() - p.z(), fp, kSideShade[axis][positive_face], dst);
      }
      depth[u] = t_near;
    }
  }
}

void RayCaster::RenderCylinder(const CylinderPrimitive& cyl, const View& view,
                               IdealImage* out) const {
  const Eigen::Vector3f lo(cyl.x_m - cyl.radius_m, cyl.y_m - cyl.radius_m, cyl.z_min_m);
  const Eigen::Vector3f hi(cyl.x_m + cyl.radius_m, cyl.y_m + cyl.radius_m, cyl.z_max_m);
  const cv::Rect rect = ScreenRect(view, lo, hi);
  if (rect.empty()) return;
  const float px = view.o.x() - cyl.x_m, py = view.o.y() - cyl.y_m, oz = view.o.z();
  const float c = px * px + py * py - cyl.radius_m * cyl.radius_m;
  if (c <= 0.0f) return;  // camera inside the cylinder's footprint: not rendered
  const float light_x = 0.6f, light_y = 0.8f;
  const uint8_t mask_value = cyl.dynamic ? 255 : 0;
  for (int v = rect.y; v < rect.y + rect.height; ++v) {
    const Eigen::Vector3f row = view.R.col(1) * y_norm_[v] + view.R.col(2);
    uint8_t* bgr = out->bgr.ptr<uint8_t>(v);
    float* depth = out->depth_m.ptr<float>(v);
    uint8_t* mask = out->mask.ptr<uint8_t>(v);
    for (int u = rect.x; u < rect.x + rect.width; ++u) {
      const Eigen::Vector3f d = row + view.R.col(0) * x_norm_[u];
      const float a = d.x() * d.x() + d.y() * d.y();
      const float b = px * d.x() + py * d.y();  // half of the quadratic's linear term
      const float disc = b * b - a * c;
      float t = kInf;
      float nx = 0.0f, ny = 0.0f;
      bool top = false;
      if (disc >= 0.0f && a > 0.0f) {
        const float ts = (-b - std::sqrt(disc)) / a;
        const float z = oz + ts * d.z();
        if (ts > kNearM && z >= cyl.z_min_m && z <= cyl.z_max_m) {
          t = ts;
          nx = (px + ts * d.x()) / cyl.radius_m;
          ny = (py + ts * d.y()) / cyl.radius_m;
        }
      }
      if (t == kInf && oz > cyl.z_max_m && d.z() < 0.0f) {  // top cap seen from above
        const float tc = (cyl.z_max_m - oz) / d.z();
        const float qx = px + tc * d.x(), qy = py + tc * d.y();
        if (qx * qx + qy * qy <= cyl.radius_m * cyl.radius_m) {
          t = tc;
          top = true;
        }
      }
      if (t == kInf || t >= depth[u]) continue;
      const float d2 = d.squaredNorm();
      uint8_t* dst = bgr + 3 * u;
      if (top) {
        PutShaded(*cyl.texture, 0.0f, 0.0f, Footprint(t, d2, std::abs(d.z()), view.inv_fx), 1.0f,
                  dst);
      } else {
        const float angle = FastAtan2(ny, nx) - cyl.heading_rad;
        const float fu = angle * cyl.radius_m;
        const float shade = 0.6f + 0.4f * std::max(0.0f, nx * light_x + ny * light_y);
        const float d_normal = std::abs(nx * d.x() + ny * d.y());
        PutShaded(*cyl.texture, fu, cyl.z_max_m - (oz + t * d.z()),
                  Footprint(t, d2, d_normal, view.inv_fx), shade, dst);
      }
      depth[u] = t;
      mask[u] = mask_value;
    }
  }
}

}  // namespace icgm::sim
