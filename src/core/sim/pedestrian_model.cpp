#include "core/sim/pedestrian_model.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace icgm::sim {
namespace {

constexpr float kLegRadiusM = 0.075f;
constexpr float kArmRadiusM = 0.05f;
constexpr float kHeadRadiusM = 0.1f;

int Texels(double metres, double texel_m) {
  return std::max(8, static_cast<int>(std::lround(metres / texel_m)));
}

TexturePtr Wrapped(const cv::Mat& bgr, double texel_m) {
  return std::make_shared<const Texture>(bgr, texel_m);
}

}  // namespace

PedestrianLook MakePedestrianLook(Rng& rng, double texel_size_m) {
  PedestrianLook look;
  look.height_m = static_cast<float>(std::normal_distribution<double>(1.70, 0.08)(rng));
  look.height_m = std::clamp(look.height_m, 1.5f, 1.95f);
  look.torso_radius_m = static_cast<float>(std::uniform_real_distribution<double>(0.16, 0.22)(rng));
  const double t = texel_size_m;
  const float h = look.height_m;
  // Textures span one circumference (u) by the part's height (v); u = 0 is the front.
  look.legs = Wrapped(
      MakeClothingTexture(rng, Texels(2 * M_PI * kLegRadiusM, t), Texels(0.5 * h, t), true), t);
  const cv::Mat shirt = MakeClothingTexture(rng, Texels(2 * M_PI * look.torso_radius_m, t),
                                            Texels(0.36 * h, t), false);
  look.torso = Wrapped(shirt, t);
  // Sleeves of the shirt's colour with a hand at the bottom.
  cv::Mat arm(Texels(0.35 * h, t), Texels(2 * M_PI * kArmRadiusM, t), CV_8UC3);
  cv::resize(shirt(cv::Rect(0, 0, std::min(shirt.cols, arm.cols), shirt.rows)), arm, arm.size());
  const cv::Mat head =
      MakeHeadTexture(rng, Texels(2 * M_PI * kHeadRadiusM, t), Texels(0.16 * h, t));
  const cv::Vec3b skin = head.at<cv::Vec3b>(head.rows - 2, 1);
  arm.rowRange(arm.rows * 4 / 5, arm.rows).setTo(cv::Scalar(skin[0], skin[1], skin[2]));
  look.arms = Wrapped(arm, t);
  look.head = Wrapped(head, t);
  return look;
}

void AppendBodyParts(const PedestrianLook& look, const PedestrianState& s,
                     std::vector<CylinderPrimitive>* out) {
  const float h = look.height_m;
  const float fx = std::cos(s.heading_rad), fy = std::sin(s.heading_rad);  // forward
  const float lx = -fy, ly = fx;                                           // left
  const float swing = s.swing_m * std::sin(s.gait_phase_rad);
  const auto part = [&](float forward, float left, float radius, float z0, float z1,
                        const TexturePtr& tex) {
    CylinderPrimitive c;
    c.x_m = s.x_m + forward * fx + left * lx;
    c.y_m = s.y_m + forward * fy + left * ly;
    c.radius_m = radius;
    c.z_min_m = z0;
    c.z_max_m = z1;
    c.heading_rad = s.heading_rad;
    c.texture = tex;
    c.dynamic = true;
    out->push_back(std::move(c));
  };
  const float hip = 0.5f * h, shoulder = 0.83f * h;
  part(swing, 0.09f, kLegRadiusM, 0.0f, hip, look.legs);
  part(-swing, -0.09f, kLegRadiusM, 0.0f, hip, look.legs);
  part(0.0f, 0.0f, look.torso_radius_m, hip - 0.02f, shoulder, look.torso);
  const float arm_offset = look.torso_radius_m + kArmRadiusM + 0.01f;
  part(-0.6f * swing, arm_offset, kArmRadiusM, hip - 0.05f, shoulder - 0.02f, look.arms);
  part(0.6f * swing, -arm_offset, kArmRadiusM, hip - 0.05f, shoulder - 0.02f, look.arms);
  part(0.02f, 0.0f, kHeadRadiusM, shoulder + 0.01f, h, look.head);
}

}  // namespace icgm::sim
