// Software depth registration against ground truth rendered by the simulator's ray caster: the
// scene of a simulated scenario seen by a depth camera with its own intrinsics, displaced and
// rotated from the colour camera as a Kinect's IR camera is, registered to the colour camera,
// must equal the depth the colour camera itself sees (to rounding, away from occlusion edges).
// The calibration is read from the `depth_camera` section of a camera YAML.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/camera_options.h"
#include "core/sensor/depth_registration.h"
#include "core/sim/ray_caster.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

cv::Mat ToMillimetres(const cv::Mat& depth_m) {
  cv::Mat m = depth_m.clone();
  cv::patchNaNs(m, 0.0);
  cv::Mat mm;
  m.convertTo(mm, CV_16UC1, 1000.0);
  return mm;
}

struct Errors {
  double coverage = 0.0;  // registered pixels / colour pixels
  double median_mm = 0.0;
  // Fraction of registered pixels within 1% of the true depth. (A pixel of the far floor, seen at
  // a grazing angle, spans several centimetres of depth: a depth sample landing a fraction of a
  // pixel from a colour pixel's centre differs from the truth there by that much.)
  double within_1pct = 0.0;
};

Errors Compare(const cv::Mat& registered_mm, const cv::Mat& truth_mm) {
  std::vector<double> e;
  size_t within = 0;
  for (int v = 0; v < truth_mm.rows; ++v) {
    for (int u = 0; u < truth_mm.cols; ++u) {
      const uint16_t r = registered_mm.at<uint16_t>(v, u);
      const uint16_t t = truth_mm.at<uint16_t>(v, u);
      if (r != 0 && t != 0) {
        e.push_back(std::abs(static_cast<double>(r) - t));
        within += e.back() <= 0.01 * t;
      }
    }
  }
  Errors out;
  out.coverage = static_cast<double>(e.size()) / truth_mm.total();
  if (e.empty()) return out;
  std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
  out.median_mm = e[e.size() / 2];
  out.within_1pct = static_cast<double>(within) / e.size();
  return out;
}

// The registration as its contract states it, one depth pixel at a time in float arithmetic
// with the standard library's rounding (the fast version must give the same image).
cv::Mat ReferenceRegister(const DepthCameraCalibration& c, const CameraIntrinsics& color,
                          const cv::Mat& depth_mm) {
  const CameraIntrinsics& k = c.depth;
  const Eigen::Matrix3d R = c.T_color_depth.linear();
  // Ray of the corner (u - 1/2, v - 1/2) in the colour frame: column(u) + row(v).
  const auto column = [&](int u) {
    return Eigen::Vector3f(((u - 0.5 - k.cx_px) / k.fx_px * R.col(0)).cast<float>());
  };
  const auto row = [&](int v) {
    return Eigen::Vector3f(((v - 0.5 - k.cy_px) / k.fy_px * R.col(1) + R.col(2)).cast<float>());
  };
  const Eigen::Vector3f t = c.T_color_depth.translation().cast<float>();
  cv::Mat out(color.height_px, color.width_px, CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < depth_mm.rows; ++v) {
    for (int u = 0; u < depth_mm.cols; ++u) {
      const uint16_t d = depth_mm.at<uint16_t>(v, u);
      if (d == 0) continue;
      const float z = d * 1e-3f;
      float pu[2], pv[2], pz[2];
      bool ok = true;
      for (int corner = 0; corner < 2; ++corner) {
        const Eigen::Vector3f ray = column(u + corner) + row(v + corner);
        const float x = z * ray.x() + t.x(), y = z * ray.y() + t.y();
        pz[corner] = z * ray.z() + t.z();
        if (pz[corner] <= 1e-6f) {
          ok = false;
          break;
        }
        const float inv_z = 1.0f / pz[corner];
        pu[corner] = static_cast<float>(color.fx_px) * x * inv_z + static_cast<float>(color.cx_px);
        pv[corner] = static_cast<float>(color.fy_px) * y * inv_z + static_cast<float>(color.cy_px);
        ok = ok && std::abs(pu[corner]) < 1e6f && std::abs(pv[corner]) < 1e6f;
      }
      if (!ok) continue;
      const float mm = std::round(500.0f * (pz[0] + pz[1]));
      if (mm < 1.0f || mm > std::numeric_limits<uint16_t>::max()) continue;
      int ua = static_cast<int>(std::ceil(std::min(pu[0], pu[1])));
      int ub = static_cast<int>(std::floor(std::max(pu[0], pu[1])));
      int va = static_cast<int>(std::ceil(std::min(pv[0], pv[1])));
      int vb = static_cast<int>(std::floor(std::max(pv[0], pv[1])));
      if (ub < ua) ua = ub = static_cast<int>(std::lround(0.5f * (pu[0] + pu[1])));
      if (vb < va) va = vb = static_cast<int>(std::lround(0.5f * (pv[0] + pv[1])));
      for (int y = std::max(va, 0); y <= std::min(vb, out.rows - 1); ++y) {
        for (int x = std::max(ua, 0); x <= std::min(ub, out.cols - 1); ++x) {
          uint16_t& dst = out.at<uint16_t>(y, x);
          if (dst == 0 || mm < dst) dst = static_cast<uint16_t>(mm);
        }
      }
    }
  }
  return out;
}

TEST(DepthRegistration, RegistersRenderedDepthToTheColourCamera) {
  const sim::Simulator simulator(
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml"));
  const CameraIntrinsics color = simulator.intrinsics();
  DepthCameraCalibration calibration;
  calibration.depth.fx_px = 580.0;
  calibration.depth.fy_px = 578.0;
  calibration.depth.cx_px = 314.5;
  calibration.depth.cy_px = 243.5;
  calibration.depth.width_px = 640;
  calibration.depth.height_px = 480;
  calibration.T_color_depth.linear() =
      (Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(-0.008, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  calibration.T_color_depth.translation() = Eigen::Vector3d(-0.025, 0.003, 0.002);

  const DepthRegistration registration(calibration, color);
  for (size_t i : {size_t{0}, simulator.size() / 2}) {
    const Pose3 T_world_color = simulator.T_world_camera(i);
    sim::IdealImage seen_by_color, seen_by_depth;
    sim::RayCaster(color).Render(simulator.scene(), {}, T_world_color, &seen_by_color);
    sim::RayCaster(calibration.depth)
        .Render(simulator.scene(), {}, T_world_color * calibration.T_color_depth, &seen_by_depth);
    const cv::Mat truth_mm = ToMillimetres(seen_by_color.depth_m);
    const cv::Mat depth_mm = ToMillimetres(seen_by_depth.depth_m);

    const cv::Mat registered = registration.Register(depth_mm);
    ASSERT_EQ(registered.type(), CV_16UC1);
    ASSERT_EQ(registered.size(), truth_mm.size());
    EXPECT_EQ(cv::countNonZero(registered != ReferenceRegister(calibration, color, depth_mm)), 0)
        << "frame " << i << ": differs from the per-pixel reference";
    const Errors e = Compare(registered, truth_mm);
    // The depth camera's narrower view ((525 / 580)^2 = 82% of the colour image's area) is
    // covered without cracks.
    EXPECT_GT(e.coverage, 0.78) << "frame " << i;
    EXPECT_LE(e.median_mm, 2.0) << "frame " << i;
    EXPECT_GT(e.within_1pct, 0.97) << "frame " << i;

    // The same depth taken as registered (what a driver without registration publishes) is off.
    const Errors raw = Compare(depth_mm, truth_mm);
    EXPECT_LT(raw.within_1pct, 0.7) << "frame " << i << ": the test scene shows no parallax";
    std::printf("frame %zu: registered %.1f%% covered, median %.1f mm, %.1f%% within 1%%; "
                "unregistered %.1f%% within 1%%\n",
                i, 100 * e.coverage, e.median_mm, 100 * e.within_1pct, 100 * raw.within_1pct);
  }
}

// Random depth (holes, near and far values, depth edges) seen by a rotated, displaced, magnifying
// and shrinking depth camera: the fast registration equals the reference pixel for pixel.
TEST(DepthRegistration, EqualsThePerPixelReference) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 4; ++trial) {
    DepthCameraCalibration c;
    c.depth.fx_px = trial % 2 == 0 ? 575.8 : 400.0;
    c.depth.fy_px = c.depth.fx_px + trial;
    c.depth.cx_px = 319.5 + trial;
    c.depth.cy_px = 239.5 - trial;
    c.depth.width_px = 640;
    c.depth.height_px = 480;
    c.T_color_depth.linear() = (Eigen::AngleAxisd(0.02 * trial, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(-0.01 * trial, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
    c.T_color_depth.translation() = Eigen::Vector3d(-0.025, 0.004 * trial, -0.01 * trial);
    CameraIntrinsics color;
    color.fx_px = color.fy_px = trial < 2 ? 525.0 : 700.0;
    color.cx_px = 319.5;
    color.cy_px = 239.5;
    cv::Mat depth(480, 640, CV_16UC1);
    for (int v = 0; v < depth.rows; ++v) {
      for (int u = 0; u < depth.cols; ++u) {
        const unsigned r = rng() % 100;
        // Blocks at different depths (edges), 10% holes, a few very near or very far pixels.
        uint16_t mm = static_cast<uint16_t>(600 + 900 * ((u / 37 + v / 29) % 4) + (rng() % 13));
        if (r < 10) mm = 0;
        if (r == 10) mm = 1 + rng() % 50;
        if (r == 11) mm = 60000 + rng() % 5000;
        depth.at<uint16_t>(v, u) = mm;
      }
    }
    const cv::Mat fast = DepthRegistration(c, color).Register(depth);
    const cv::Mat reference = ReferenceRegister(c, color, depth);
    EXPECT_GT(cv::countNonZero(reference), 100000) << "trial " << trial;
    EXPECT_EQ(cv::countNonZero(fast != reference), 0) << "trial " << trial;
  }
}

TEST(DepthRegistration, WrongImageSizeGivesNothing) {
  DepthCameraCalibration calibration;
  const DepthRegistration registration(calibration, CameraIntrinsics());
  EXPECT_TRUE(registration.Register(cv::Mat(240, 320, CV_16UC1, cv::Scalar(1000))).empty());
  EXPECT_TRUE(registration.Register(cv::Mat(480, 640, CV_32FC1, cv::Scalar(1.0))).empty());
}

TEST(DepthRegistration, ReadsTheDepthCameraSectionStrictly) {
  DepthCameraCalibration c;
  ReadOptions(OptionReader::FromString("{fx_px: 580, fy_px: 581, cx_px: 320, cy_px: 240, "
                                       "width_px: 640, height_px: 480, x_m: -0.025, yaw_deg: 90}"),
              &c);
  EXPECT_EQ(c.depth.fy_px, 581.0);
  EXPECT_NEAR(c.T_color_depth.translation().x(), -0.025, 1e-12);
  EXPECT_NEAR((c.T_color_depth.linear() * Eigen::Vector3d::UnitX()).y(), 1.0, 1e-12);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{fx_px: 580, fy_px: 581, cx_px: 320, "
                                                    "cy_px: 240, width_px: 640}"),
                           &c),
               LoadError);  // height_px missing
  EXPECT_THROW(ReadOptions(OptionReader::FromString("{fx_px: 580, fy_px: 581, cx_px: 320, "
                                                    "cy_px: 240, width_px: 640, height_px: 480, "
                                                    "x_mm: 3}"),
                           &c),
               LoadError);  // unknown key

  // Shipped camera files: the Kinect defaults carry a depth camera, the TUM calibration none
  // (its depth is registered).
  const std::string dir = std::string(ICGM_SOURCE_DIR) + "/config/camera/";
  DepthCameraCalibration kinect;
  EXPECT_TRUE(LoadDepthCameraCalibration(dir + "kinect_default.yaml", &kinect));
  EXPECT_NEAR(kinect.T_color_depth.translation().norm(), 0.025, 1e-9);
  EXPECT_NO_THROW(LoadCameraIntrinsics(dir + "kinect_default.yaml"));
  EXPECT_FALSE(LoadDepthCameraCalibration(dir + "tum_fr1.yaml", &kinect));
}

}  // namespace
}  // namespace icgm
