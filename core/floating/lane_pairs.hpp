// Two 3-vectors side by side, one in each lane of a 2-wide array per component: a body's velocity
// and acceleration halves in the floating-base forward pass, its moment and force in the backward
// pass. A rotation, a cross product or a sum then costs one SIMD instruction for both (SSE2's
// two doubles), where the 3-vector code issues two scalar ones; each lane's arithmetic is the
// 3-vector code's, term for term and in the same order.
#pragma once

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/spatial.hpp"

namespace dynid {

namespace lane_detail {
template <typename Scalar>
using Lanes = Eigen::Array<Scalar, 2, 1>;

/// (a, b).
template <typename Scalar>
DYNID_INLINE Lanes<Scalar> make(const Scalar& a, const Scalar& b) {
  return Lanes<Scalar>(a, b);
}
/// (x's first, y's first).
template <typename Scalar>
DYNID_INLINE Lanes<Scalar> lows(const Lanes<Scalar>& x, const Lanes<Scalar>& y) {
  return Lanes<Scalar>(x(0), y(0));
}
/// (x's second, y's second).
template <typename Scalar>
DYNID_INLINE Lanes<Scalar> highs(const Lanes<Scalar>& x, const Lanes<Scalar>& y) {
  return Lanes<Scalar>(x(1), y(1));
}

#if defined(__SSE2__)
// GCC builds an Array2d of two scalars in memory, two 8-byte stores that the 16-byte load after
// them cannot be forwarded from (a stall each time, which made the paired code slower than the
// scalar one despite fewer instructions); the shuffles keep both lanes in registers.
DYNID_INLINE Eigen::Array2d fromPacket(__m128d p) {
  Eigen::Array2d out;
  _mm_storeu_pd(out.data(), p);
  return out;
}
DYNID_INLINE __m128d packet(const Eigen::Array2d& x) { return _mm_loadu_pd(x.data()); }
DYNID_INLINE Eigen::Array2d make(const double& a, const double& b) {
  return fromPacket(_mm_set_pd(b, a));
}
DYNID_INLINE Eigen::Array2d lows(const Eigen::Array2d& x, const Eigen::Array2d& y) {
  return fromPacket(_mm_unpacklo_pd(packet(x), packet(y)));
}
DYNID_INLINE Eigen::Array2d highs(const Eigen::Array2d& x, const Eigen::Array2d& y) {
  return fromPacket(_mm_unpackhi_pd(packet(x), packet(y)));
}
#endif
}  // namespace lane_detail

template <typename Scalar>
struct Pair3 {
  using Lanes = lane_detail::Lanes<Scalar>;
  /// c[k] = (first's k-th component, second's k-th component).
  Lanes c[3];

  static DYNID_INLINE Pair3 join(const Vector3<Scalar>& first, const Vector3<Scalar>& second) {
    using lane_detail::make;
    return {
        {make(first.x(), second.x()), make(first.y(), second.y()), make(first.z(), second.z())}};
  }
  /// (a's first lane, b's first lane) and (a's second lane, b's second lane).
  static DYNID_INLINE Pair3 lows(const Pair3& a, const Pair3& b) {
    using lane_detail::lows;
    return {{lows(a.c[0], b.c[0]), lows(a.c[1], b.c[1]), lows(a.c[2], b.c[2])}};
  }
  static DYNID_INLINE Pair3 highs(const Pair3& a, const Pair3& b) {
    using lane_detail::highs;
    return {{highs(a.c[0], b.c[0]), highs(a.c[1], b.c[1]), highs(a.c[2], b.c[2])}};
  }
  static DYNID_INLINE Pair3 zero() { return {{Lanes::Zero(), Lanes::Zero(), Lanes::Zero()}}; }
  /// The first (0) or second (1) 3-vector.
  DYNID_INLINE Vector3<Scalar> lane(int k) const {
    return Vector3<Scalar>(c[0](k), c[1](k), c[2](k));
  }
  DYNID_INLINE Pair3& operator+=(const Pair3& o) {
    c[0] += o.c[0], c[1] += o.c[1], c[2] += o.c[2];
    return *this;
  }
  friend DYNID_INLINE Pair3 operator+(const Pair3& a, const Pair3& b) {
    return {{a.c[0] + b.c[0], a.c[1] + b.c[1], a.c[2] + b.c[2]}};
  }
  friend DYNID_INLINE Pair3 operator-(const Pair3& a, const Pair3& b) {
    return {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}};
  }
  friend DYNID_INLINE Pair3 operator*(const Pair3& a, const Scalar& s) {
    return {{a.c[0] * s, a.c[1] * s, a.c[2] * s}};
  }
};

/// R x in both lanes, each entry's three terms summed left to right (Eigen's product may sum
/// its last row in another order: the last bit can differ from R * x).
template <typename Scalar>
DYNID_INLINE Pair3<Scalar> times(const Matrix3<Scalar>& r, const Pair3<Scalar>& x) {
  return {{r(0, 0) * x.c[0] + r(0, 1) * x.c[1] + r(0, 2) * x.c[2],
           r(1, 0) * x.c[0] + r(1, 1) * x.c[1] + r(1, 2) * x.c[2],
           r(2, 0) * x.c[0] + r(2, 1) * x.c[1] + r(2, 2) * x.c[2]}};
}

/// R^T x in both lanes (transposeTimes').
template <typename Scalar>
DYNID_INLINE Pair3<Scalar> transposeTimes(const Matrix3<Scalar>& r, const Pair3<Scalar>& x) {
  return {{r(0, 0) * x.c[0] + r(1, 0) * x.c[1] + r(2, 0) * x.c[2],
           r(0, 1) * x.c[0] + r(1, 1) * x.c[1] + r(2, 1) * x.c[2],
           r(0, 2) * x.c[0] + r(1, 2) * x.c[1] + r(2, 2) * x.c[2]}};
}

/// a x b for one 3-vector a and each lane's b.
template <typename Scalar>
DYNID_INLINE Pair3<Scalar> cross(const Vector3<Scalar>& a, const Pair3<Scalar>& b) {
  return {{a.y() * b.c[2] - a.z() * b.c[1], a.z() * b.c[0] - a.x() * b.c[2],
           a.x() * b.c[1] - a.y() * b.c[0]}};
}

/// to's second lane += from's first x (x e_k), two entries, for a rate x about e_k:
/// (w, dw) += (0, w x e_k x) with from = to the angular pair, (v, dv) += (0, v x e_k x) the
/// linear one, and (v, dv) += (0, w x e_k x) for a prismatic joint (from the angular pair).
template <typename Scalar>
DYNID_INLINE void addRateCross(const Pair3<Scalar>& from, Pair3<Scalar>& to, int k,
                               const Scalar& x) {
  using lane_detail::lows;
  const typename Pair3<Scalar>::Lanes zero = Pair3<Scalar>::Lanes::Zero();
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  const typename Pair3<Scalar>::Lanes xa = from.c[a] * x, xb = from.c[b] * x;
  to.c[a] += lows(zero, xb);
  to.c[b] -= lows(zero, xa);
}

/// A body's motion in the forward pass: angular = (w, dw), linear = (v, dv).
template <typename Scalar>
struct MotionPair {
  Pair3<Scalar> angular, linear;

  static DYNID_INLINE MotionPair of(const Vector6<Scalar>& v, const Vector6<Scalar>& a) {
    return {Pair3<Scalar>::join(v.template head<3>(), a.template head<3>()),
            Pair3<Scalar>::join(v.template tail<3>(), a.template tail<3>())};
  }
  DYNID_INLINE Vector6<Scalar> velocity() const {
    Vector6<Scalar> out;
    out << angular.lane(0), linear.lane(0);
    return out;
  }
  DYNID_INLINE Vector6<Scalar> acceleration() const {
    Vector6<Scalar> out;
    out << angular.lane(1), linear.lane(1);
    return out;
  }
};

}  // namespace dynid
