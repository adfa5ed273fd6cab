#include "search/gc_lanes.hpp"

#include <algorithm>
#include <array>

#include "core/integrators-inl.hpp"
#include "core/lanes.hpp"
#include "search/gc_rollout.hpp"

namespace dynid::gc_detail {

namespace {

template <int W>
struct Buffers final : GcWorkspace::LaneBuffers {
  explicit Buffers(const Model& candidate)
      : model(candidate.cast<Lanes<W>>()),
        data(model),
        q(candidate.numJoints()),
        dq(candidate.numJoints()),
        tau(candidate.numJoints()) {}
  ModelTpl<Lanes<W>> model;  // the candidate in every lane
  long evaluation = -1;      // the evaluation `model` was cast for
  DataTpl<Lanes<W>> data;
  VectorX<Lanes<W>> q, dq, tau;
  Eigen::VectorXd q_lane, dq_lane;  // one lane's end state, for segmentError
};

template <int W>
void rollOut(const Model& candidate, long evaluation, const GcProblem& problem, int first,
             std::unique_ptr<GcWorkspace::LaneBuffers>& slot, Eigen::VectorXd& errors) {
  auto* own = dynamic_cast<Buffers<W>*>(slot.get());
  if (!own) {
    slot = std::make_unique<Buffers<W>>(candidate);
    own = static_cast<Buffers<W>*>(slot.get());
    own->evaluation = evaluation;
  } else if (own->evaluation != evaluation) {
    own->model = candidate.cast<Lanes<W>>();
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

void rollOutGroup(int width, const Model& candidate, long evaluation, const GcProblem& problem,
                  int first, std::unique_ptr<GcWorkspace::LaneBuffers>& buffers,
                  Eigen::VectorXd& errors) {
  switch (width) {
    case 2:
      return rollOut<2>(candidate, evaluation, problem, first, buffers, errors);
    case 4:
      return rollOut<4>(candidate, evaluation, problem, first, buffers, errors);
    default:
      return rollOut<8>(candidate, evaluation, problem, first, buffers, errors);
  }
}

}  // namespace dynid::gc_detail
