// The GC rollout in 4 lanes compiled for AVX-512 (F and VL), run where the CPU has it
// (search/gc_lanes_simd.hpp says how, and why it cannot leak into the rest of the program).
#include "search/gc_lanes_simd.hpp"

#if DYNID_GC_SIMD

#pragma GCC push_options
#pragma GCC target("avx2,avx512f,avx512vl")
#pragma GCC optimize("fp-contract=off")
#include "core/aba.hpp"
#include "core/integrators-inl.hpp"
#include "core/integrators.hpp"
#include "search/gc_problem.hpp"
#include "search/gc_rollout.hpp"

namespace dynid::gc_detail {

template <>
__attribute__((flatten)) void rollOutSegmentsSimd<kAvx512Isa>(
    const ModelTpl<Lanes<4, kAvx512Isa>>& model, DataTpl<Lanes<4, kAvx512Isa>>& data,
    const GcProblem& problem, const std::array<int, 4>& segments, VectorX<Lanes<4, kAvx512Isa>>& q,
    VectorX<Lanes<4, kAvx512Isa>>& dq, VectorX<Lanes<4, kAvx512Isa>>& tau) {
  rollOutSegments<4, kAvx512Isa>(model, data, problem, segments, q, dq, tau);
}

}  // namespace dynid::gc_detail

#pragma GCC pop_options

#endif
