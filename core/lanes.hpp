// Lanes<W>: W doubles that move through the Scalar-templated algorithms together, one SIMD lane
// each, the way ceres::Jet moves a value and its derivatives. The GC error rolls W segments at once
// in them (search/gc_error.hpp). Each lane does the operations a double does (IEEE +, -, *, /;
// sin, cos, exp, sqrt from the C library lane by lane; in an AVX2 build, sin and cos of 4 lanes
// from glibc's vector library, within 4 ulps), so a lane's result is the scalar path's up to the
// order in which Eigen sums short dot products (it splits double sums into SIMD packets, which it
// cannot do for a user type): round-off, bounded in search/gc_error.hpp.
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

// glibc's vector sin and cos (libmvec, linked by core/CMakeLists.txt) where the build targets AVX2.
#if defined(__AVX2__) && defined(__x86_64__) && defined(__GLIBC__) && defined(DYNID_HAVE_LIBMVEC)
#include <immintrin.h>
extern "C" __m256d _ZGVdN4v_sin(__m256d);
extern "C" __m256d _ZGVdN4v_cos(__m256d);
#define DYNID_LANES_LIBMVEC 1
#else
#define DYNID_LANES_LIBMVEC 0
#endif

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

template <int W, int Isa = kBuildIsa>
struct Lanes {
  using Vector = typename lanes_detail::VectorOf<W>::Vector;
  using Mask = typename lanes_detail::VectorOf<W>::Mask;  // all bits set where true

  Vector v;  // uninitialised, as a double is

  Lanes() = default;
  /// Every lane x.
  explicit DYNID_INLINE Lanes(double x) : v(Vector{} + x) {}
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

/// f applied to every lane: the transcendental functions lane by lane with the C library's, so each
/// lane rounds as a double does.
template <int W, int I, typename F>
DYNID_INLINE Lanes<W, I> eachLane(const Lanes<W, I>& a, F f) {
  Lanes<W, I> out;
  for (int l = 0; l < W; ++l) out.v[l] = f(a.v[l]);
  return out;
}
template <int W, int I>
inline Lanes<W, I> sin(const Lanes<W, I>& a) {
  return eachLane(a, [](double x) { return std::sin(x); });
}
template <int W, int I>
inline Lanes<W, I> cos(const Lanes<W, I>& a) {
  return eachLane(a, [](double x) { return std::cos(x); });
}

/// sin and cos of every lane: glibc's vector functions (libmvec) for 4 lanes where the build
/// targets AVX2 (at most 4 ulps from the correctly rounded value, glibc's bound; the scalar sincos
/// is within 1), else sincos lane by lane (one range reduction for both).
template <int W, int I>
inline void sinCos(const Lanes<W, I>& x, Lanes<W, I>& s, Lanes<W, I>& c) {
#if DYNID_LANES_LIBMVEC
  if constexpr (W == 4) {
    s.v = reinterpret_cast<typename Lanes<W, I>::Vector>(
        _ZGVdN4v_sin(reinterpret_cast<__m256d>(x.v)));
    c.v = reinterpret_cast<typename Lanes<W, I>::Vector>(
        _ZGVdN4v_cos(reinterpret_cast<__m256d>(x.v)));
    return;
  }
#endif
  for (int l = 0; l < W; ++l) {
    double sl, cl;
    ::sincos(x.v[l], &sl, &cl);
    s.v[l] = sl, c.v[l] = cl;
  }
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
