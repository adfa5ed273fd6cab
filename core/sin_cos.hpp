// Sine and cosine of a block of doubles at once (CRBA's joint angles), in the widest SIMD registers
// the CPU has: lanes_detail::sinCosKernel (core/lanes.hpp), compiled for SSE2, AVX2 and AVX-512
// and chosen at run time.
#pragma once

namespace dynid {

/// The widest instruction set, of kBuildIsa, kAvx2Isa and kAvx512Isa (core/lanes.hpp), that this
/// build can run code for and the CPU has: kAvx512Isa needs AVX-512 F and VL. Only a GCC build for
/// any x86-64 (the default) compiles code for wider sets than its own; a build that targets AVX
/// itself (-DDYNID_NATIVE=ON) and clang's (the sanitizer and fuzzing builds) return kBuildIsa.
int cpuLaneIsa();

/// The sines and cosines of up to kSize arguments, written by sinCosBlock as whole registers (the
/// caller reads them at once: a store of part of a register is not forwarded to a load).
struct SinCosBlock {
  static constexpr int kSize = 8;
  alignas(64) double s[kSize];
  alignas(64) double c[kSize];
};

/// out.s[i] = sin x[i] and out.c[i] = cos x[i] for i < n, 0 <= n <= SinCosBlock::kSize (else
/// InputError); the entries from n on are unspecified, and x[n] on are not read. Within 1 ulp of
/// the exact values (lanes_detail::sinCosKernel, its series by Estrin's scheme: a short chain of
/// dependent operations, since the caller waits on the results), and the same bits on every CPU and
/// instruction set: IEEE +, -, * alone, no fused multiply-add. An argument beyond kSinCosRange
/// (1e5 rad), infinite or NaN takes the C library's sincos instead. On the widest instruction set
/// cpuLaneIsa() gives.
void sinCosBlock(const double* x, int n, SinCosBlock& out);

/// The same on instruction set `isa`, kBuildIsa up to cpuLaneIsa() (tests compare them); throws
/// InputError on another.
void sinCosBlock(const double* x, int n, SinCosBlock& out, int isa);

}  // namespace dynid
