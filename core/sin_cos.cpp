// Each instruction set's code is compiled here under `#pragma GCC target`, after every header is
// read for the build's own set: the kernel (a template, always inlined) is compiled for AVX2 or
// AVX-512 only inside the functions defined under the pragma, which no other file defines, so the
// linker can never pick wider code in place of the build's (as search/gc_lanes_simd.hpp). No
// contraction into fused multiply-adds, which AVX-512 has: each lane does the SSE2 build's IEEE
// operations and gives its bits. A translation unit of its own (not merged in a unity build).
#include "core/sin_cos.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/errors.hpp"
#include "core/lanes.hpp"

#if DYNID_LANES_SIMD
#include <immintrin.h>
#endif

namespace dynid {
namespace {

/// The arguments sinCosKernel may not take, from the C library.
void outOfRangeFromTheCLibrary(const double* x, int n, SinCosBlock& out) {
  for (int i = 0; i < n; ++i)
    if (!(std::fabs(x[i]) <= lanes_detail::kSinCosRange)) ::sincos(x[i], &out.s[i], &out.c[i]);
}

void checkCount(int n) {
  if (n < 0 || n > SinCosBlock::kSize)
    throw InputError("a block of sines and cosines takes 0 to " +
                     std::to_string(SinCosBlock::kSize) + " arguments, not " + std::to_string(n));
}

/// In the build's own registers, kLanes at a time (a last block's other lanes 0).
void sinCosBuild(const double* x, int n, SinCosBlock& out) {
  using Vector = lanes_detail::VectorOf<kLanes>::Vector;
  for (int i = 0; i < n; i += kLanes) {
    Vector xv{}, sv, cv;
    for (int l = 0; l < std::min(kLanes, n - i); ++l) xv[l] = x[i + l];
    lanes_detail::sinCosKernel<kLanes, true>(xv, sv, cv);
    std::memcpy(out.s + i, &sv, sizeof(Vector));
    std::memcpy(out.c + i, &cv, sizeof(Vector));
  }
  outOfRangeFromTheCLibrary(x, n, out);
}
static_assert(SinCosBlock::kSize % kLanes == 0);

}  // namespace

#if DYNID_LANES_SIMD
namespace {
// Masked loads: an argument past n is neither read nor a fault (0 in its lane).
#pragma GCC push_options
#pragma GCC target("avx2")
#pragma GCC optimize("fp-contract=off")
void sinCosAvx2(const double* x, int n, SinCosBlock& out) {
  using Vector = lanes_detail::VectorOf<4>::Vector;
  for (int i = 0; i < n; i += 4) {
    const __m256i mask =
        _mm256_cmpgt_epi64(_mm256_set1_epi64x(n - i), _mm256_setr_epi64x(0, 1, 2, 3));
    Vector sv, cv;
    lanes_detail::sinCosKernel<4, true>((Vector)_mm256_maskload_pd(x + i, mask), sv, cv);
    _mm256_store_pd(out.s + i, (__m256d)sv);
    _mm256_store_pd(out.c + i, (__m256d)cv);
  }
  outOfRangeFromTheCLibrary(x, n, out);
}
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl")
#pragma GCC optimize("fp-contract=off")
void sinCosAvx512(const double* x, int n, SinCosBlock& out) {
  using Vector = lanes_detail::VectorOf<8>::Vector;
  const auto mask = static_cast<__mmask8>((1u << n) - 1);
  Vector sv, cv;
  lanes_detail::sinCosKernel<8, true>((Vector)_mm512_maskz_loadu_pd(mask, x), sv, cv);
  _mm512_store_pd(out.s, (__m512d)sv);
  _mm512_store_pd(out.c, (__m512d)cv);
  outOfRangeFromTheCLibrary(x, n, out);
}
#pragma GCC pop_options
static_assert(SinCosBlock::kSize == 8);
}  // namespace
#endif

int cpuLaneIsa() {
#if DYNID_LANES_SIMD
  static const int isa = [] {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl")) return kAvx512Isa;
    if (__builtin_cpu_supports("avx2")) return kAvx2Isa;
    return kBuildIsa;
  }();
  return isa;
#else
  return kBuildIsa;
#endif
}

void sinCosBlock(const double* x, int n, SinCosBlock& out, int isa) {
  if (isa < kBuildIsa || isa > cpuLaneIsa())
    throw InputError("instruction set " + std::to_string(isa) +
                     " is not one this build and CPU offer (at most " +
                     std::to_string(cpuLaneIsa()) + ")");
  checkCount(n);
#if DYNID_LANES_SIMD
  if (isa == kAvx512Isa) return sinCosAvx512(x, n, out);
  if (isa == kAvx2Isa) return sinCosAvx2(x, n, out);
#endif
  sinCosBuild(x, n, out);
}

void sinCosBlock(const double* x, int n, SinCosBlock& out) {
  static const auto kernel = [] {
#if DYNID_LANES_SIMD
    if (cpuLaneIsa() == kAvx512Isa) return &sinCosAvx512;
    if (cpuLaneIsa() == kAvx2Isa) return &sinCosAvx2;
#endif
    return &sinCosBuild;
  }();
  checkCount(n);
  kernel(x, n, out);
}

}  // namespace dynid
