#include "core/mono/pnp_pose.h"

#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "core/mono/ransac_order.h"
#include "core/mono/triangulation.h"

namespace icgm {

namespace {
void PoseToRvecTvec(const Pose3& world_camera, cv::Mat* rvec, cv::Mat* tvec) {
  const Pose3 camera_world = world_camera.inverse();
  cv::Mat r;
  cv::eigen2cv(Eigen::Matrix3d(camera_world.rotation()), r);
  cv::Rodrigues(r, *rvec);
  cv::eigen2cv(Eigen::Vector3d(camera_world.translation()), *tvec);
}

Pose3 RvecTvecToPose(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  Eigen::Matrix3d re;
  Eigen::Vector3d te;
  cv::cv2eigen(r, re);
  cv::cv2eigen(tvec, te);
  Pose3 camera_world = Pose3::Identity();
  camera_world.linear() = re;
  camera_world.translation() = te;
  return camera_world.inverse();
}
}  // namespace

PnpResult EstimatePnpPose(const std::vector<Eigen::Vector3d>& points_world,
                          const std::vector<Eigen::Vector2d>& pixels,
                          const CameraIntrinsics& intrinsics, const PnpOptions& options,
                          const std::optional<Pose3>& predicted_world_camera) {
  PnpResult out;
  const size_t n = points_world.size();
  out.inliers.assign(n, 0);
  const size_t needed = std::max<size_t>(4, static_cast<size_t>(options.min_inliers));
  if (pixels.size() != n || n < needed) {
    out.status =
        Status::Error(std::to_string(n) + " 2D-3D correspondences < " + std::to_string(needed));
    return out;
  }
  std::vector<cv::Point3d> object(n);
  std::vector<cv::Point2d> image(n);
  for (size_t k = 0; k < n; ++k) {
    object[k] = cv::Point3d(points_world[k].x(), points_world[k].y(), points_world[k].z());
    image[k] = cv::Point2d(pixels[k].x(), pixels[k].y());
  }
  const cv::Matx33d k(intrinsics.fx_px, 0, intrinsics.cx_px, 0, intrinsics.fy_px, intrinsics.cy_px,
                      0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  bool ok = false;
  const bool seeded = predicted_world_camera && predicted_world_camera->matrix().allFinite();
  // Without RANSAC (a known pose refined) the seed's inliers below start the refinement.
  if (options.ransac || !seeded) {
    try {
      const std::vector<size_t> order = RansacOrder(n, options.ransac_order_seed);
      std::vector<cv::Point3d> object_drawn(n);
      std::vector<cv::Point2d> image_drawn(n);
      for (size_t i = 0; i < n; ++i) {
        object_drawn[i] = object[order[i]];
        image_drawn[i] = image[order[i]];
      }
      ok = cv::solvePnPRansac(object_drawn, image_drawn, k, cv::noArray(), rvec, tvec, false,
                              options.iterations, static_cast<float>(options.reprojection_px),
                              options.confidence, inliers, cv::SOLVEPNP_EPNP);
      for (int& i : inliers) i = static_cast<int>(order[static_cast<size_t>(i)]);
    } catch (const cv::Exception& ex) {
      out.status = Status::Error(std::string("PnP failed: ") + ex.what());
      return out;
    }
  }
  // The prediction, when it explains more correspondences than the RANSAC model, seeds the
  // refinement instead.
  if (seeded) {
    size_t predicted_inliers = 0;
    for (size_t i = 0; i < n; ++i) {
      predicted_inliers += ReprojectionErrorPx(intrinsics, *predicted_world_camera, points_world[i],
                                               pixels[i]) <= options.reprojection_px;
    }
    if (predicted_inliers > inliers.size()) {
      PoseToRvecTvec(*predicted_world_camera, &rvec, &tvec);
      ok = true;
      inliers.clear();
      for (size_t i = 0; i < n; ++i) {
        if (ReprojectionErrorPx(intrinsics, *predicted_world_camera, points_world[i], pixels[i]) <=
            options.reprojection_px) {
          inliers.push_back(static_cast<int>(i));
        }
      }
    }
  }
  if (!ok || inliers.size() < needed) {
    out.status = Status::Error("PnP: " + std::to_string(inliers.size()) + " inliers < " +
                               std::to_string(needed));
    return out;
  }
  const auto count_inliers = [&](const Pose3& pose, std::vector<uint8_t>* flags) {
    flags->assign(n, 0);
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
      const double e = ReprojectionErrorPx(intrinsics, pose, points_world[i], pixels[i]);
      if (e <= options.reprojection_px) {
        (*flags)[i] = 1;
        ++count;
      }
    }
    return count;
  };
  const Pose3 ransac_pose = RvecTvecToPose(rvec, tvec);
  out.world_camera = ransac_pose;
  out.num_inliers = count_inliers(ransac_pose, &out.inliers);
  // Levenberg-Marquardt on the inliers; kept when it explains at least as many points.
  std::vector<cv::Point3d> in_object;
  std::vector<cv::Point2d> in_image;
  for (size_t i = 0; i < n; ++i) {
    if (!out.inliers[i]) continue;
    in_object.push_back(object[i]);
    in_image.push_back(image[i]);
  }
  if (in_object.size() >= 6) {
    cv::Mat r = rvec.clone(), t = tvec.clone();
    try {
      if (cv::solvePnP(in_object, in_image, k, cv::noArray(), r, t, true, cv::SOLVEPNP_ITERATIVE)) {
        const Pose3 refined = RvecTvecToPose(r, t);
        std::vector<uint8_t> flags;
        const size_t count = refined.matrix().allFinite() ? count_inliers(refined, &flags) : 0;
        if (count >= out.num_inliers) {
          out.world_camera = refined;
          out.inliers = flags;
          out.num_inliers = count;
        }
      }
    } catch (const cv::Exception&) {
      // Keep the RANSAC pose.
    }
  }
  if (!out.world_camera.matrix().allFinite()) {
    out.status = Status::Error("PnP gave a non-finite pose");
    return out;
  }
  if (out.num_inliers < needed) {
    out.status = Status::Error("PnP: " + std::to_string(out.num_inliers) +
                               " inliers after refinement < " + std::to_string(needed));
  }
  return out;
}

}  // namespace icgm
