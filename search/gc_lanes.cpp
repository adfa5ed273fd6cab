#include "search/gc_lanes.hpp"

#include <algorithm>
#include <array>

#include "core/integrators-inl.hpp"
#include "core/lanes.hpp"
#include "core/sin_cos.hpp"
#include "search/gc_rollout.hpp"

namespace dynid::gc_detail {

namespace {

template <int W, int Isa>
struct Buffers final : GcWorkspace::LaneBuffers {
  using L = Lanes<W, Isa>;
  explicit Buffers(const Model& candidate)
      : model(candidate.cast<L>()),
        data(model),
        q(candidate.numJoints()),
        dq(candidate.numJoints()),
        tau(candidate.numJoints()) {}
  ModelTpl<L> model;     // the candidate in every lane
  long evaluation = -1;  // the evaluation `model` was cast for
  DataTpl<L> data;
  VectorX<L> q, dq, tau;
  Eigen::VectorXd q_lane, dq_lane;  // one lane's end state, for segmentError
};

template <int W, int Isa>
void rollOut(const Model& candidate, long evaluation, const GcProblem& problem, int first,
             std::unique_ptr<GcWorkspace::LaneBuffers>& slot, Eigen::VectorXd& errors) {
  using Own = Buffers<W, Isa>;
  auto* own = dynamic_cast<Own*>(slot.get());
  if (!own) {
    slot = std::make_unique<Own>(candidate);
    own = static_cast<Own*>(slot.get());
    own->evaluation = evaluation;
  } else if (own->evaluation != evaluation) {
    own->model = candidate.cast<typename Own::L>();
    own->evaluation = evaluation;
  }
  // Lane l rolls segment first + l; past the last segment the lanes repeat it (results dropped).
  const int count = std::min(W, problem.numSegments() - first);
  std::array<int, W> segments;
  for (int l = 0; l < W; ++l) segments[l] = first + std::min(l, count - 1);
  const int n = candidate.numJoints();
  for (int j = 0; j < n; ++j)
    for (int l = 0; l < W; ++l) {
      own->q[j].set(l, problem.data.q(j, problem.starts[segments[l]]));
      own->dq[j].set(l, problem.data.dq(j, problem.starts[segments[l]]));
    }
#if DYNID_GC_SIMD
  if constexpr (Isa != kBuildIsa)
    rollOutSegmentsSimd<Isa>(own->model, own->data, problem, segments, own->q, own->dq, own->tau);
  else
#endif
    rollOutSegments<W>(own->model, own->data, problem, segments, own->q, own->dq, own->tau);
  own->q_lane.resize(n);
  own->dq_lane.resize(n);
  for (int l = 0; l < count; ++l) {
    for (int j = 0; j < n; ++j) own->q_lane[j] = own->q[j][l], own->dq_lane[j] = own->dq[j][l];
    errors[segments[l]] = segmentError(own->q_lane, own->dq_lane, problem,
                                       problem.starts[segments[l]] + problem.samples_per_segment);
  }
}

}  // namespace

}  // namespace dynid::gc_detail

namespace dynid {

int gcLaneIsa() { return cpuLaneIsa(); }

}  // namespace dynid

namespace dynid::gc_detail {

void rollOutGroup(int width, [[maybe_unused]] int isa, const Model& candidate, long evaluation,
                  const GcProblem& problem, int first,
                  std::unique_ptr<GcWorkspace::LaneBuffers>& buffers, Eigen::VectorXd& errors) {
  switch (width) {
    case 2:
      return rollOut<2, kBuildIsa>(candidate, evaluation, problem, first, buffers, errors);
    case 4:
#if DYNID_GC_SIMD
      if (isa == kAvx512Isa)
        return rollOut<4, kAvx512Isa>(candidate, evaluation, problem, first, buffers, errors);
      if (isa == kAvx2Isa)
        return rollOut<4, kAvx2Isa>(candidate, evaluation, problem, first, buffers, errors);
#endif
      return rollOut<4, kBuildIsa>(candidate, evaluation, problem, first, buffers, errors);
    default:
      return rollOut<8, kBuildIsa>(candidate, evaluation, problem, first, buffers, errors);
  }
}

}  // namespace dynid::gc_detail

namespace dynid {

int defaultGcLanes() { return gcLaneIsa() == kBuildIsa ? kLanes : 4; }

}  // namespace dynid
