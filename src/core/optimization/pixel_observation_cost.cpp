// Compiled with Ceres only (ICGM_HAVE_CERES), like the bundle adjustment that uses it.
#ifdef ICGM_HAVE_CERES
#include "core/optimization/pixel_observation_cost.h"

#include <cstdint>
#include <tuple>

namespace icgm {

namespace {

// Derivative slots: t 0-2, q 3-6 (x, y, z, w), X 7-9. A dual number whose slots outside the
// compile-time mask M are zero; each operation computes ceres::Jet's formula for the slots of
// its result's mask, an operand's slot outside its own mask counting as 0.0 (so a product or
// sum equals Jet's whenever it is nonzero; only the sign of an exact zero could differ).
template <uint32_t M>
struct Dual {
  double a = 0.0;
  double v[10];
  double at(int s) const { return (M >> s) & 1u ? v[s] : 0.0; }
};

constexpr bool In(uint32_t m, int s) { return (m >> s) & 1u; }

template <uint32_t A, uint32_t B>
inline Dual<A | B> operator+(const Dual<A>& f, const Dual<B>& g) {
  Dual<A | B> r;
  r.a = f.a + g.a;
  for (int s = 0; s < 10; ++s) {
    if (In(A | B, s)) r.v[s] = f.at(s) + g.at(s);
  }
  return r;
}

template <uint32_t A, uint32_t B>
inline Dual<A | B> operator-(const Dual<A>& f, const Dual<B>& g) {
  Dual<A | B> r;
  r.a = f.a - g.a;
  for (int s = 0; s < 10; ++s) {
    if (In(A | B, s)) r.v[s] = f.at(s) - g.at(s);
  }
  return r;
}

template <uint32_t A>
inline Dual<A> operator-(const Dual<A>& f) {
  Dual<A> r;
  r.a = -f.a;
  for (int s = 0; s < 10; ++s) {
    if (In(A, s)) r.v[s] = -f.v[s];
  }
  return r;
}

// Jet: (f.a * g.a, f.a * g.v + f.v * g.a).
template <uint32_t A, uint32_t B>
inline Dual<A | B> operator*(const Dual<A>& f, const Dual<B>& g) {
  Dual<A | B> r;
  r.a = f.a * g.a;
  for (int s = 0; s < 10; ++s) {
    if (In(A | B, s)) r.v[s] = f.a * g.at(s) + f.at(s) * g.a;
  }
  return r;
}

// Jet: 1/g.a, f.a/g.a by that inverse, (f.v - (f.a/g.a) * g.v) * inverse.
template <uint32_t A, uint32_t B>
inline Dual<A | B> operator/(const Dual<A>& f, const Dual<B>& g) {
  const double g_a_inverse = 1.0 / g.a;
  const double f_a_by_g_a = f.a * g_a_inverse;
  Dual<A | B> r;
  r.a = f_a_by_g_a;
  for (int s = 0; s < 10; ++s) {
    if (In(A | B, s)) r.v[s] = (f.at(s) - f_a_by_g_a * g.at(s)) * g_a_inverse;
  }
  return r;
}

// A constant (Jet(double): zero derivative).
inline Dual<0> Constant(double c) {
  Dual<0> r;
  r.a = c;
  return r;
}

template <int kSlot>
inline Dual<(1u << kSlot)> Variable(double value) {
  Dual<(1u << kSlot)> r;
  r.a = value;
  r.v[kSlot] = 1.0;
  return r;
}

// Eigen's MatrixBase::cross for 3-vectors (coefficient formula, conj the identity).
template <typename L0, typename L1, typename L2, typename R0, typename R1, typename R2>
inline auto Cross(const L0& l0, const L1& l1, const L2& l2, const R0& r0, const R1& r1,
                  const R2& r2) {
  return std::make_tuple(l1 * r2 - l2 * r1, l2 * r0 - l0 * r2, l0 * r1 - l1 * r0);
}

}  // namespace

bool PixelObservationCost::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  if (!jacobians) return functor_(parameters[0], parameters[1], parameters[2], residuals);
  const double* t = parameters[0];
  const double* q = parameters[1];
  const double* x = parameters[2];
  // d = X - t.
  const auto d0 = Variable<7>(x[0]) - Variable<0>(t[0]);
  const auto d1 = Variable<8>(x[1]) - Variable<1>(t[1]);
  const auto d2 = Variable<9>(x[2]) - Variable<2>(t[2]);
  // Conjugate quaternion (w, -x, -y, -z).
  const auto qw = Variable<6>(q[3]);
  const auto cx = -Variable<3>(q[0]);
  const auto cy = -Variable<4>(q[1]);
  const auto cz = -Variable<5>(q[2]);
  // Eigen's _transformVector: uv = vec x d; uv += uv; d + w * uv + vec x uv.
  auto [u0, u1, u2] = Cross(cx, cy, cz, d0, d1, d2);
  const auto uu0 = u0 + u0;
  const auto uu1 = u1 + u1;
  const auto uu2 = u2 + u2;
  const auto [c0, c1, c2] = Cross(cx, cy, cz, uu0, uu1, uu2);
  const auto pcx = (d0 + qw * uu0) + c0;
  const auto pcy = (d1 + qw * uu1) + c1;
  const auto pcz = (d2 + qw * uu2) + c2;
  if (pcz.a < 1e-3) return false;  // as the functor: behind the camera
  const RgbdObservationError& f = functor_;
  const auto r0 = ((Constant(f.fx_) * pcx / pcz + Constant(f.cx_)) - Constant(f.pixel_.x())) *
                  Constant(f.inv_sigma_px_);
  const auto r1 = ((Constant(f.fy_) * pcy / pcz + Constant(f.cy_)) - Constant(f.pixel_.y())) *
                  Constant(f.inv_sigma_px_);
  const auto r2 = (pcz - Constant(f.depth_m_)) * Constant(f.inv_depth_sigma_);
  residuals[0] = r0.a;
  residuals[1] = r1.a;
  residuals[2] = r2.a;
  const auto put = [&](int block, int first, int size) {
    if (!jacobians[block]) return;
    for (int j = 0; j < size; ++j) {
      jacobians[block][0 * size + j] = r0.at(first + j);
      jacobians[block][1 * size + j] = r1.at(first + j);
      jacobians[block][2 * size + j] = r2.at(first + j);
    }
  };
  put(0, 0, 3);
  put(1, 3, 4);
  put(2, 7, 3);
  return true;
}

}  // namespace icgm
#endif  // ICGM_HAVE_CERES
