#include "core/registration/dense_refinement.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, DenseRefinementOptions* options) {
  reader.Read("grid_step_px", &options->grid_step_px, 1, 64);
  reader.Read("iterations", &options->iterations, 1, 100);
  reader.Read("min_points", &options->min_points, 6, 1000000);
  reader.Read("normal_offset_px", &options->normal_offset_px, 1, 32);
  reader.Read("depth_sigma_m", &options->depth_sigma_m, 1e-5, 1.0);
  reader.Read("depth_sigma_per_m2", &options->depth_sigma_per_m2, 0.0, 1.0);
  reader.Read("gate_sigmas", &options->gate_sigmas, 0.1, 100.0);
  reader.Read("huber_sigmas", &options->huber_sigmas, 0.1, 100.0);
  reader.Read("min_agreement_ratio", &options->min_agreement_ratio, 0.0, 10.0);
  reader.Read("max_correction_m", &options->max_correction_m, 0.0, 10.0);
  reader.Read("max_correction_deg", &options->max_correction_deg, 0.0, 180.0);
  reader.Read("grey_sigma", &options->grey_sigma, 0.0, 255.0);
}

namespace {

using Vec6d = Eigen::Matrix<double, 6, 1>;
using Row6d = Eigen::Matrix<double, 1, 6>;

double DepthSigma(double z, const DenseRefinementOptions& o) {
  return o.depth_sigma_m + o.depth_sigma_per_m2 * z * z;
}


// Unit normal of the reference surface at pixel (u, v), facing the camera; false at depth
// discontinuities, missing depth or the image border.
bool ReferenceNormal(const cv::Mat& depth, int u, int v, int offset, const CameraIntrinsics& k,
                     const DepthConsistencyOptions& o, Eigen::Vector3d* normal) {
  if (u - offset < 0 || v - offset < 0 || u + offset >= depth.cols || v + offset >= depth.rows) {
    return false;
  }
  const float z = depth.at<float>(v, u);
  const auto lift = [&](int du, int dv, Eigen::Vector3d* p) {
    const float zn = depth.at<float>(v + dv, u + du);
    if (!o.Usable(zn) || std::abs(zn - z) > o.Tolerance(z)) return false;
    *p = k.BackProject(u + du, v + dv, zn);
    return true;
  };
  Eigen::Vector3d l, r, up, down;
  if (!lift(-offset, 0, &l) || !lift(offset, 0, &r) || !lift(0, -offset, &up) ||
      !lift(0, offset, &down)) {
    return false;
  }
  Eigen::Vector3d n = (r - l).cross(down - up);
  const double norm = n.norm();
  if (!(norm > 1e-12)) return false;
  n /= norm;
  if (n.dot(k.BackProject(u, v, z)) > 0) n = -n;
  *normal = n;
  return true;
}

// Current grid pixels whose residual under `ref_cur` lies within gate_sigmas noise sigmas (the tight static test the refinement's result is judged by).
size_t CountWithinNoise(const cv::Mat& depth_ref_m, const cv::Mat& depth_cur_m,
                        const Pose3& ref_cur, const CameraIntrinsics& k,
                        const DenseRefinementOptions& o, const DepthConsistencyOptions& c) {
  size_t count = 0;
  const int step = std::max(1, o.grid_step_px);
  for (int v = 0; v < depth_cur_m.rows; v += step) {
    for (int u = 0; u < depth_cur_m.cols; u += step) {
      const float z = depth_cur_m.at<float>(v, u);
      if (!c.Usable(z)) continue;
      const Eigen::Vector3d q = ref_cur * k.BackProject(u, v, z);
      if (q.z() <= 1e-3) continue;
      const Eigen::Vector2d uv = k.Project(q);
      const int ur = static_cast<int>(std::lround(uv.x()));
      const int vr = static_cast<int>(std::lround(uv.y()));
      if (ur < 0 || vr < 0 || ur >= depth_ref_m.cols || vr >= depth_ref_m.rows) continue;
      const float zr = depth_ref_m.at<float>(vr, ur);
      if (!c.Usable(zr)) continue;
      // The distance to the reference surface (along its normal where it has one): a depth
      // difference alone grows on slanted surfaces from the pixel grid.
      double residual = double(zr) - q.z();
      Eigen::Vector3d n;
      if (ReferenceNormal(depth_ref_m, ur, vr, o.normal_offset_px, k, c, &n)) {
        residual = n.dot(q - k.BackProject(ur, vr, zr));
      }
      if (std::abs(residual) <= o.gate_sigmas * DepthSigma(q.z(), o)) ++count;
    }
  }
  return count;
}

// Bilinear grey value and gradient of `grey` at (x, y); false near the border.
bool SampleGrey(const cv::Mat& grey, double x, double y, double* value, Eigen::Vector2d* gradient) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 1 || y0 < 1 || x0 + 2 >= grey.cols || y0 + 2 >= grey.rows) return false;
  const double ax = x - x0, ay = y - y0;
  const auto at = [&](int xx, int yy) { return double(grey.at<uint8_t>(yy, xx)); };
  const auto bilinear = [&](double xx0, double yy0, int dx, int dy) {
    const int xi = static_cast<int>(xx0) + dx, yi = static_cast<int>(yy0) + dy;
    return (1 - ax) * (1 - ay) * at(xi, yi) + ax * (1 - ay) * at(xi + 1, yi) +
           (1 - ax) * ay * at(xi, yi + 1) + ax * ay * at(xi + 1, yi + 1);
  };
  *value = bilinear(x0, y0, 0, 0);
  gradient->x() = 0.5 * (bilinear(x0, y0, 1, 0) - bilinear(x0, y0, -1, 0));
  gradient->y() = 0.5 * (bilinear(x0, y0, 0, 1) - bilinear(x0, y0, 0, -1));
  return true;
}

// Derivative of p' = T * Exp(eps) * p with respect to eps = (v, w): [R, -R [p]x].
Eigen::Matrix<double, 3, 6> PointJacobian(const Eigen::Matrix3d& r, const Eigen::Vector3d& p) {
  Eigen::Matrix3d skew;
  skew << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
  Eigen::Matrix<double, 3, 6> j;
  j.leftCols<3>() = r;
  j.rightCols<3>() = -r * skew;
  return j;
}

}  // namespace

DenseRefinementResult RefineDense(const cv::Mat& depth_ref_m, const cv::Mat& depth_cur_m,
                                  const cv::Mat& grey_ref, const cv::Mat& grey_cur,
                                  const Pose3& ref_cur, const CameraIntrinsics& k,
                                  const DenseRefinementOptions& o,
                                  const DepthConsistencyOptions& c,
                                  const DynamicMask& cur_dynamic, const DynamicMask& ref_dynamic) {
  DenseRefinementResult out;
  out.ref_cur = ref_cur;
  if (depth_ref_m.empty() || depth_cur_m.empty() || depth_ref_m.type() != CV_32FC1 ||
      depth_cur_m.type() != CV_32FC1) {
    out.status = Status::Error("no usable depth images");
    return out;
  }
  const bool photometric = o.grey_sigma > 0.0 && !grey_ref.empty() && !grey_cur.empty() &&
                           grey_ref.type() == CV_8UC1 && grey_cur.type() == CV_8UC1 &&
                           grey_cur.size() == depth_cur_m.size();
  const int step = std::max(1, o.grid_step_px);
  Pose3 t = ref_cur;
  for (int iteration = 0; iteration < o.iterations; ++iteration) {
    Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
    Vec6d b = Vec6d::Zero();
    size_t points = 0, edges = 0;
    const Eigen::Matrix3d r = t.linear();
    const auto accumulate = [&](const Row6d& j, double residual, double sigma) {
      const double scaled = std::abs(residual) / sigma;
      const double huber = scaled <= o.huber_sigmas ? 1.0 : o.huber_sigmas / scaled;
      const double w = huber / (sigma * sigma);
      h += w * j.transpose() * j;
      b += w * j.transpose() * residual;
    };
    for (int v = step; v + step < depth_cur_m.rows; v += step) {
      const float* zrow = depth_cur_m.ptr<float>(v);
      for (int u = step; u + step < depth_cur_m.cols; u += step) {
        const float z = zrow[u];
        if (!c.Usable(z)) continue;
        const cv::Point2f px(static_cast<float>(u), static_cast<float>(v));
        if (cur_dynamic.Contains(px)) continue;
        const Eigen::Vector3d p = k.BackProject(u, v, z);
        const Eigen::Vector3d q = t * p;
        if (q.z() <= 1e-3) continue;
        const Eigen::Vector2d uv = k.Project(q);
        const int ur = static_cast<int>(std::lround(uv.x()));
        const int vr = static_cast<int>(std::lround(uv.y()));
        if (ur < 0 || vr < 0 || ur >= depth_ref_m.cols || vr >= depth_ref_m.rows) continue;
        if (ref_dynamic.Contains(cv::Point2f(static_cast<float>(ur), static_cast<float>(vr)))) {
          continue;
        }
        const float zr = depth_ref_m.at<float>(vr, ur);
        if (!c.Usable(zr)) continue;
        // Verified static under the current estimate: within gate_sigmas depth noise sigmas.
        const double sigma = DepthSigma(q.z(), o);
        if (std::abs(double(zr) - q.z()) > o.gate_sigmas * sigma) continue;
        Eigen::Vector3d n;
        if (!ReferenceNormal(depth_ref_m, ur, vr, o.normal_offset_px, k, c, &n)) continue;
        const Eigen::Matrix<double, 3, 6> jp = PointJacobian(r, p);
        const Eigen::Vector3d surface = k.BackProject(ur, vr, zr);
        accumulate(n.transpose() * jp, n.dot(q - surface), sigma);
        ++points;
        if (!photometric) continue;
        const uint8_t* g = grey_cur.ptr<uint8_t>(v);
        const double gx = double(g[u + 1]) - double(g[u - 1]);
        const double gy = double(grey_cur.at<uint8_t>(v + 1, u)) -
                          double(grey_cur.at<uint8_t>(v - 1, u));
        if (std::abs(gx) + std::abs(gy) < c.min_gradient) continue;
        double value = 0.0;
        Eigen::Vector2d gradient;
        if (!SampleGrey(grey_ref, uv.x(), uv.y(), &value, &gradient)) continue;
        Eigen::Matrix<double, 2, 3> projection;
        projection << k.fx_px / q.z(), 0, -k.fx_px * q.x() / (q.z() * q.z()), 0,
            k.fy_px / q.z(), -k.fy_px * q.y() / (q.z() * q.z());
        accumulate(gradient.transpose() * projection * jp, value - double(g[u]), o.grey_sigma);
        ++edges;
      }
    }
    out.points = points;
    out.edge_points = edges;
    if (static_cast<int>(points) < o.min_points) {
      out.status = Status::Error("too few verified-static pixels (" + std::to_string(points) + ")");
      return out;
    }
    const Vec6d delta = h.ldlt().solve(-b);
    if (!delta.allFinite()) {
      out.status = Status::Error("degenerate dense alignment");
      return out;
    }
    t = Orthonormalized(t * ExpSE3(delta));
    if (delta.head<3>().norm() < 1e-5 && delta.tail<3>().norm() < 1e-5) break;
  }
  const Pose3 correction = Between(ref_cur, t);
  if (TranslationNorm(correction) > o.max_correction_m ||
      RotationAngleRad(correction) * 180.0 / M_PI > o.max_correction_deg) {
    out.status = Status::Error("dense correction beyond max_correction_m/_deg");
    return out;
  }
  out.agreeing_before = CountWithinNoise(depth_ref_m, depth_cur_m, ref_cur, k, o, c);
  out.agreeing_after = CountWithinNoise(depth_ref_m, depth_cur_m, t, k, o, c);
  if (static_cast<double>(out.agreeing_after) <
      o.min_agreement_ratio * static_cast<double>(out.agreeing_before)) {
    out.status = Status::Error("dense alignment explains fewer pixels than the start");
    return out;
  }
  out.ref_cur = t;
  return out;
}

}  // namespace icgm
