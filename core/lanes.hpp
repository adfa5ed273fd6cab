// Lanes<W>: W doubles that move through the Scalar-templated algorithms together, one SIMD lane
// each, the way ceres::Jet moves a value and its derivatives. The GC error rolls W segments at once
// in them (search/gc_error.hpp). Each lane does the operations a double does (IEEE +, -, *, /;
// exp and sqrt from the C library lane by lane; sin and cos of all lanes at once, within 1 ulp:
// sinCos below), so a lane's result is the scalar path's up to round-off: the order in which Eigen
// sums short dot products (it splits double sums into SIMD packets, which it cannot do for a user
// type) and sin and cos rounded differently from the C library's in the last bit, bounded in
// search/gc_error.hpp. A lane's result depends on nothing but its own inputs: the same bits in any
// lane of any width, whatever instruction set the lanes are compiled for (no fused multiply-add).
//
// Built on GCC's vector extensions, so the compiler emits the widest instructions the code is
// compiled for: with the default flags (any x86-64: SSE2) a Lanes<2> is one 2-wide register; with
// -DDYNID_NATIVE=ON on an AVX machine a Lanes<4> is one 4-wide one (kLanes picks). The default
// build also has the GC rollout compiled for AVX2 and AVX-512 on types of their own (the Isa
// parameter), chosen at run time (search/gc_lanes_simd.hpp).
// A branch on a value becomes a select (comparisons return a per-lane Mask) or a test that every
// lane agrees (allLanes); signum (Coulomb friction) is such a select.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "core/spatial.hpp"

namespace dynid {

/// The lane count the GC rollouts use: one SSE2 register (the default build) or one AVX register
/// (-DDYNID_NATIVE=ON on an AVX machine), the fastest in bench_search's BM_GcErrorLanes on both
/// (docs/PERFORMANCE.md; 8 lanes on AVX-512 were slower than 4: more register spills).
#if defined(__AVX__)
inline constexpr int kLanes = 4;
#else
inline constexpr int kLanes = 2;
#endif

namespace lanes_detail {
// GCC's vector types, spelt per width: a vector_size that depends on a template parameter is not
// taken as a vector inside the template. Aligned to at most Eigen's static alignment: Eigen aligns
// a fixed-size array to at most that, and a type that asks for more is refused (clang: "requested
// alignment is less than minimum alignment"; GCC ignores it silently). Only the widths wider than
// the build's registers lose alignment (unaligned loads), never kLanes.
#define DYNID_LANES_ALIGN(bytes)          \
  ((bytes) < EIGEN_MAX_STATIC_ALIGN_BYTES \
       ? (bytes)                          \
       : (EIGEN_MAX_STATIC_ALIGN_BYTES > 8 ? EIGEN_MAX_STATIC_ALIGN_BYTES : 8))
template <int W>
struct VectorOf;
template <>
struct VectorOf<2> {
  typedef double Vector __attribute__((vector_size(16), aligned(DYNID_LANES_ALIGN(16))));
  typedef long Mask __attribute__((vector_size(16), aligned(DYNID_LANES_ALIGN(16))));
};
template <>
struct VectorOf<4> {
  typedef double Vector __attribute__((vector_size(32), aligned(DYNID_LANES_ALIGN(32))));
  typedef long Mask __attribute__((vector_size(32), aligned(DYNID_LANES_ALIGN(32))));
};
template <>
struct VectorOf<8> {
  typedef double Vector __attribute__((vector_size(64), aligned(DYNID_LANES_ALIGN(64))));
  typedef long Mask __attribute__((vector_size(64), aligned(DYNID_LANES_ALIGN(64))));
};
#undef DYNID_LANES_ALIGN
}  // namespace lanes_detail

/// The instruction set a Lanes type's code is compiled for: the build's (kBuildIsa), AVX2
/// (kAvx2Isa) or AVX-512 (kAvx512Isa: F and VL, 4 lanes in 32 AVX registers). Lanes<4, kAvx2Isa>
/// and Lanes<4, kAvx512Isa> exist only in the GC rollouts search/gc_lanes_avx2.cpp and
/// gc_lanes_avx512.cpp compile for those instruction sets, run where the CPU has them (runtime
/// dispatch, search/gc_lanes_simd.hpp). Separate types, so that every function instantiated for
/// them is a symbol of its own: their code can never stand in for the build's.
inline constexpr int kBuildIsa = 0, kAvx2Isa = 1, kAvx512Isa = 2;

/// 1 where the build compiles code for wider instruction sets than its own and picks it at run time
/// (core/sin_cos.hpp, search/gc_lanes_simd.hpp): a GCC build for any x86-64, the default. A build
/// that targets AVX itself rolls 4 lanes in its own registers (kLanes), and clang (the sanitizer
/// and fuzzing builds) has no `#pragma GCC target`.
#if defined(__x86_64__) && !defined(__AVX__) && defined(__GNUC__) && !defined(__clang__)
#define DYNID_LANES_SIMD 1
#else
#define DYNID_LANES_SIMD 0
#endif

template <int W, int Isa = kBuildIsa>
struct Lanes {
  using Vector = typename lanes_detail::VectorOf<W>::Vector;
  using Mask = typename lanes_detail::VectorOf<W>::Mask;  // all bits set where true

  Vector v;  // uninitialised, as a double is

  Lanes() = default;
  /// Every lane x, its sign bit included: x - 0 is x for every x (-0 - +0 = -0), where 0 + x would
  /// turn -0 into +0.
  explicit DYNID_INLINE Lanes(double x) : v(x - Vector{}) {}
  DYNID_INLINE static Lanes fromVector(Vector x) {
    Lanes out;
    out.v = x;
    return out;
  }

  DYNID_INLINE double operator[](int lane) const { return v[lane]; }
  DYNID_INLINE void set(int lane, double x) { v[lane] = x; }

  DYNID_INLINE Lanes& operator+=(const Lanes& b) { return v += b.v, *this; }
  DYNID_INLINE Lanes& operator-=(const Lanes& b) { return v -= b.v, *this; }
  DYNID_INLINE Lanes& operator*=(const Lanes& b) { return v *= b.v, *this; }
  DYNID_INLINE Lanes& operator/=(const Lanes& b) { return v /= b.v, *this; }
};

template <int W, int I>
DYNID_INLINE Lanes<W, I> operator+(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return Lanes<W, I>::fromVector(a.v + b.v);
}
template <int W, int I>
DYNID_INLINE Lanes<W, I> operator-(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return Lanes<W, I>::fromVector(a.v - b.v);
}
template <int W, int I>
DYNID_INLINE Lanes<W, I> operator*(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return Lanes<W, I>::fromVector(a.v * b.v);
}
template <int W, int I>
DYNID_INLINE Lanes<W, I> operator/(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return Lanes<W, I>::fromVector(a.v / b.v);
}
template <int W, int I>
DYNID_INLINE Lanes<W, I> operator-(const Lanes<W, I>& a) {
  return Lanes<W, I>::fromVector(-a.v);
}
template <int W, int I>
DYNID_INLINE Lanes<W, I> operator+(const Lanes<W, I>& a) {
  return a;
}

// Comparisons give a mask per lane; a NaN lane compares false, as a double does.
template <int W, int I>
DYNID_INLINE typename Lanes<W, I>::Mask operator<(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return a.v < b.v;
}
template <int W, int I>
DYNID_INLINE typename Lanes<W, I>::Mask operator>(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return a.v > b.v;
}
template <int W, int I>
DYNID_INLINE typename Lanes<W, I>::Mask operator<=(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return a.v <= b.v;
}
template <int W, int I>
DYNID_INLINE typename Lanes<W, I>::Mask operator>=(const Lanes<W, I>& a, const Lanes<W, I>& b) {
  return a.v >= b.v;
}

/// Per lane: mask ? a : b.
template <int W, int I>
DYNID_INLINE Lanes<W, I> select(typename Lanes<W, I>::Mask mask, const Lanes<W, I>& a,
                                const Lanes<W, I>& b) {
  return Lanes<W, I>::fromVector(mask ? a.v : b.v);
}

/// True when the condition holds in every lane (for a plain bool, the bool): a branch that the
/// lanes take together or not at all.
DYNID_INLINE bool allLanes(bool condition) { return condition; }
template <typename Mask>
DYNID_INLINE auto allLanes(Mask mask) -> decltype(mask[0] != 0) {
  constexpr int w = sizeof(Mask) / sizeof(mask[0]);
  bool all = true;
  for (int l = 0; l < w; ++l) all = all && mask[l] != 0;
  return all;
}

template <int W, int I>
DYNID_INLINE Lanes<W, I> abs(const Lanes<W, I>& a) {
  return Lanes<W, I>::fromVector(a.v < 0 ? -a.v : a.v);
}

/// sign(x) in {-1, 0, 1} per lane; a NaN lane gives 0, as drive_terms.hpp's signum does.
template <int W, int I>
DYNID_INLINE Lanes<W, I> signum(const Lanes<W, I>& x) {
  using Vector = typename Lanes<W, I>::Vector;
  const Vector one = Vector{} + 1.0;
  const Vector zero{};
  return Lanes<W, I>::fromVector(x.v > 0 ? one : (x.v < 0 ? -one : zero));
}

/// sign(x) outside [-rest, rest] and 0 inside it, per lane (drive_terms.hpp's signOutside).
template <int W, int I>
DYNID_INLINE Lanes<W, I> signOutside(const Lanes<W, I>& x, double rest) {
  using Vector = typename Lanes<W, I>::Vector;
  const Vector one = Vector{} + 1.0;
  const Vector zero{};
  return Lanes<W, I>::fromVector(x.v > rest ? one : (x.v < -rest ? -one : zero));
}

/// f applied to every lane: the transcendental functions lane by lane with the C library's, so each
/// lane rounds as a double does.
template <int W, int I, typename F>
DYNID_INLINE Lanes<W, I> eachLane(const Lanes<W, I>& a, F f) {
  Lanes<W, I> out;
  for (int l = 0; l < W; ++l) out.v[l] = f(a.v[l]);
  return out;
}
namespace lanes_detail {

/// The range sinCosKernel reduces exactly enough: |x| <= 1e5 rad (k < 2^16 quarter turns, so that
/// k times each of the first two 33-bit parts of pi/2 below is exact).
inline constexpr double kSinCosRange = 1e5;

/// sin and cos of every lane of x, |x| <= kSinCosRange (else any value), within 1 ulp of the
/// exact values (faithfully rounded; tests/core/lanes_test.cpp measures it against long double
/// sinl/cosl: 0.77 ulp at most, the C library's 0.56), from IEEE +, -, * alone, so the same bits
/// in every lane, width and instruction set. How:
/// - x = k pi/2 + r, |r| <= pi/4: k the nearest integer to x 2/pi; r = x - k P1 - k P2 - k P3
///   with pi/2 = P1 + P2 + P3 (+ 1e-37): P1 and P2 of 33 significant bits, so k P1 and k P2 are
///   exact and x - k P1 too (Sterbenz); r as a double-double (r, r_lo), the rounding of the
///   subtractions caught by an exact two-sum, so that r keeps its relative accuracy near a
///   multiple of pi/2 (cos(pi/2) = 6.1e-17 to the last bit).
/// - sin r and cos r from their Taylor series to r^17 and r^16 (truncation below 1e-18 relative
///   for |r| <= pi/4, far under an ulp: the error is the arithmetic's), r_lo added to first order;
///   cos r as w + ((1 - w) - r^2/2 + ...) with w = 1 - r^2/2, which recovers w's rounding.
/// - the quadrant k mod 4 (the low bits of x 2/pi + 1.5 2^52) swaps sin and cos and sets signs.
/// sin(+-0) = +-0. The constants are pi/2 split and 1/n! rounded to the nearest double
/// (mpmath, 400 bits).
/// kShortChain shortens the chain of dependent operations, for a caller that waits on the result
/// (CRBA: core/sin_cos.hpp), where false (the rollouts, in which many calls overlap) takes the
/// fewest operations: r is rounded from hi - k P3 at once and the roundings go to r_lo beside the
/// series (two subtractions before z = r^2 instead of seven), and the series are summed by Estrin's
/// scheme (pairs, then pairs of pairs in z^2 and z^4: three multiply-adds deep instead of seven)
/// instead of Horner's rule. The two round differently in the last bit; each is within 1 ulp
/// (tests/core/lanes_test.cpp, sin_cos_test.cpp).
/// (Templated on the width, not on the vector type: a vector typedef passed as a template argument
/// loses its reduced alignment, and a 32-byte vector aligned to 16 is then loaded as if aligned
/// to 32.)
template <int W>
DYNID_INLINE typename VectorOf<W>::Vector all(double a) {
  return a - typename VectorOf<W>::Vector{};  // a's sign bit kept, as Lanes(a) keeps it
}
template <int W, bool kShortChain = false>
DYNID_INLINE void sinCosKernel(const typename VectorOf<W>::Vector& x,
                               typename VectorOf<W>::Vector& s, typename VectorOf<W>::Vector& c) {
  using V = typename VectorOf<W>::Vector;
  using M = typename VectorOf<W>::Mask;
  const V magic = all<W>(0x1.8p52);  // x 2/pi + magic rounds to an integer, k in the low bits
  const V km = x * all<W>(0x1.45f306dc9c883p-1) + magic;
  const V k = km - magic;
  const V r1 = x - k * all<W>(0x1.921fb54400000p+0);  // exact
  const V t2 = k * all<W>(0x1.0b4611a600000p-34);     // exact
  const V p3 = k * all<W>(0x1.3198a2e037073p-69);
  const V hi = r1 - t2;
  const V bb = hi - r1;
  const V err = (r1 - (hi - bb)) - (t2 + bb);  // r1 - t2 = hi + err exactly
  V r, r_lo;
  if constexpr (kShortChain) {
    // r rounded from hi - p3 at once, so that z waits on two subtractions after r1, not seven;
    // the roundings of r1 - t2 (err) and of hi - p3 (an exact two-sum) go to r_lo meanwhile.
    r = hi - p3;
    const V rb = r - hi;
    r_lo = ((hi - (r - rb)) - (p3 + rb)) + err;
  } else {
    const V lo = err - p3;
    r = hi + lo;
    r_lo = lo - (r - hi);
  }
  const V z = r * r;
  // sin r = r + r z (-1/3! + z/5! - ...), cos r = 1 - z/2 + z^2 (1/4! - z/6! + ...).
  const V s3 = all<W>(-0x1.5555555555555p-3), s5 = all<W>(0x1.1111111111111p-7),
          s7 = all<W>(-0x1.a01a01a01a01ap-13), s9 = all<W>(0x1.71de3a556c734p-19),
          s11 = all<W>(-0x1.ae64567f544e4p-26), s13 = all<W>(0x1.6124613a86d09p-33),
          s15 = all<W>(-0x1.ae7f3e733b81fp-41), s17 = all<W>(0x1.952c77030ad4ap-49);
  const V c4 = all<W>(0x1.5555555555555p-5), c6 = all<W>(-0x1.6c16c16c16c17p-10),
          c8 = all<W>(0x1.a01a01a01a01ap-16), c10 = all<W>(-0x1.27e4fb7789f5cp-22),
          c12 = all<W>(0x1.1eed8eff8d898p-29), c14 = all<W>(-0x1.93974a8c07c9dp-37),
          c16 = all<W>(0x1.ae7f3e733b81fp-45);
  V ps, pc;
  if constexpr (kShortChain) {
    const V z2 = z * z, z4 = z2 * z2;
    ps = ((s3 + s5 * z) + (s7 + s9 * z) * z2) + ((s11 + s13 * z) + (s15 + s17 * z) * z2) * z4;
    pc = ((c4 + c6 * z) + (c8 + c10 * z) * z2) + ((c12 + c14 * z) + c16 * z2) * z4;
    ps = ps * z;
    pc = pc * z2;
  } else {
    ps = s17;
    for (const V& term : {s15, s13, s11, s9, s7, s5, s3}) ps = ps * z + term;
    pc = c16;
    for (const V& term : {c14, c12, c10, c8, c6, c4}) pc = pc * z + term;
    ps = ps * z;
    pc = pc * (z * z);
  }
  const V one = all<W>(1.0), half = all<W>(0.5);
  const V sin_r = r + (r * ps + r_lo * (one - half * z));
  const V hz = half * z;  // exact
  const V w = one - hz;
  const V cos_r = w + (((one - w) - hz) + (pc - r * r_lo));
  // Quadrant: odd k swaps sin and cos; sin is negated for k mod 4 in {2, 3}, cos for {1, 2}.
  const M kb = reinterpret_cast<M>(km);
  const M swap = -(kb & 1);
  const M sb = reinterpret_cast<M>(sin_r), cb = reinterpret_cast<M>(cos_r);
  const M so = ((cb & swap) | (sb & ~swap)) ^ ((kb & 2) << 62);
  const M co = ((sb & swap) | (cb & ~swap)) ^ (((kb + 1) & 2) << 62);
  const M zero = x == V{};  // keeps sin(-0) = -0
  s = zero ? x : reinterpret_cast<V>(so);
  c = reinterpret_cast<V>(co);
}

}  // namespace lanes_detail

/// sin and cos of every lane (lanes_detail::sinCosKernel: within 1 ulp); a lane beyond
/// kSinCosRange, infinite or NaN takes the C library's sincos instead. Each lane's result depends
/// on its own x alone.
template <int W, int I>
DYNID_INLINE void sinCos(const Lanes<W, I>& x, Lanes<W, I>& s, Lanes<W, I>& c) {
  using Vector = typename Lanes<W, I>::Vector;
  using Mask = typename Lanes<W, I>::Mask;
  const Vector xv = x.v;  // s or c may be x
  const Mask in_range = (xv < 0 ? -xv : xv) <= Vector{} + lanes_detail::kSinCosRange;
  lanes_detail::sinCosKernel<W>(xv, s.v, c.v);
  if (!allLanes(in_range))
    for (int l = 0; l < W; ++l)
      if (!in_range[l]) {
        double sl, cl;
        ::sincos(xv[l], &sl, &cl);
        s.v[l] = sl, c.v[l] = cl;
      }
}
template <int W, int I>
inline Lanes<W, I> sin(const Lanes<W, I>& a) {
  Lanes<W, I> s, c;
  sinCos(a, s, c);
  return s;
}
template <int W, int I>
inline Lanes<W, I> cos(const Lanes<W, I>& a) {
  Lanes<W, I> s, c;
  sinCos(a, s, c);
  return c;
}
template <int W, int I>
inline Lanes<W, I> exp(const Lanes<W, I>& a) {
  return eachLane(a, [](double x) { return std::exp(x); });
}
template <int W, int I>
inline Lanes<W, I> sqrt(const Lanes<W, I>& a) {
  return eachLane(a, [](double x) { return std::sqrt(x); });
}

}  // namespace dynid

namespace Eigen {

/// What Eigen needs of a scalar type; Lanes is never compared, printed or decomposed by Eigen.
template <int W, int I>
struct NumTraits<dynid::Lanes<W, I>> : GenericNumTraits<double> {
  using Real = dynid::Lanes<W, I>;
  using NonInteger = dynid::Lanes<W, I>;
  using Nested = dynid::Lanes<W, I>;
  using Literal = dynid::Lanes<W, I>;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1,
    AddCost = 1,
    MulCost = 1,
  };
  static dynid::Lanes<W, I> epsilon() {
    return dynid::Lanes<W, I>(std::numeric_limits<double>::epsilon());
  }
  static dynid::Lanes<W, I> dummy_precision() { return dynid::Lanes<W, I>(1e-12); }
};

}  // namespace Eigen
