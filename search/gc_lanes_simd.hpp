// The GC rollout compiled for wider instruction sets than the build's, chosen at run time: a build
// for any x86-64 (the default: SSE2, 2 lanes in one register) rolls 4 lanes in AVX registers where
// the CPU has AVX-512 (F and VL: 32 registers) or AVX2 (16).
//
// search/gc_lanes_avx512.cpp and gc_lanes_avx2.cpp include this header first, as the build
// targets it: it reads every header that defines types and small helpers (Eigen's configuration,
// its packet size and its allocator's alignment, are then fixed for the whole program). They then
// read the dynamics' declarations and template bodies (core/integrators.hpp, core/aba.hpp, their
// -inl files) and the rollout under `#pragma GCC target(...)`: GCC gives a function the target in
// force at its first declaration. Those templates are instantiated there for Lanes<4, kAvx2Isa>
// or Lanes<4, kAvx512Isa> alone (core/lanes.hpp), types no other file uses: every function
// compiled for the wider set is a symbol of its own, which the linker can never pick in place of
// the build's copy (tests/search/gc_lanes_simd_symbols.sh checks both objects). No FMA
// (fp-contract off): each lane does the scalar path's IEEE operations, as in the build's lanes,
// so the results are the same bit for bit whatever the width or the CPU, and sin and cos come
// from the same kernel (core/lanes.hpp). Internal to the search module.
#pragma once

#include <array>

#include <Eigen/Core>

#include "core/checks.hpp"
#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/friction.hpp"
#include "core/lanes.hpp"
#include "core/model.hpp"
#include "core/spatial.hpp"
#include "core/trajectory.hpp"

// Where the build compiles for wider instruction sets than its own (core/lanes.hpp).
#define DYNID_GC_SIMD DYNID_LANES_SIMD

namespace dynid {
struct GcProblem;
}

namespace dynid::gc_detail {

#if DYNID_GC_SIMD
/// rollOutSegments<4> (search/gc_rollout.hpp) compiled for Isa: call it only where gcLaneIsa()
/// (search/gc_error.hpp) is at least Isa. Results: rollOutSegments<4>'s bit for bit (above).
template <int Isa>
void rollOutSegmentsSimd(const ModelTpl<Lanes<4, Isa>>& model, DataTpl<Lanes<4, Isa>>& data,
                         const GcProblem& problem, const std::array<int, 4>& segments,
                         VectorX<Lanes<4, Isa>>& q, VectorX<Lanes<4, Isa>>& dq,
                         VectorX<Lanes<4, Isa>>& tau);
#endif

}  // namespace dynid::gc_detail
