#include "search/gc_rollout.hpp"

#include <gtest/gtest.h>

#include <ceres/jet.h>

#include "core/integrators-inl.hpp"
#include "core/model-inl.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "search/gc_error.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

// The one rollout: gcError (double) and the refinement's Jet residuals both come from it. Its
// double and Jet instantiations agree, and summed they give gcError.
TEST(GcRollout, DoubleAndJetRolloutsAgreeAndSumToTheGcError) {
  using Jet = ceres::Jet<double, 3>;
  const Model model = perturbedModel(makePuma560(false), 0.2, 4);
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(1.0), {.num_segments = 8});
  const ModelTpl<Jet> model_j = model.cast<Jet>();
  Data data(model);
  DataTpl<Jet> data_j(model_j);
  const int n = model.numJoints();
  double total = 0.0;
  for (int s = 0; s < problem.numSegments(); ++s) {
    const int start = problem.starts[s], end = start + problem.samples_per_segment;
    Eigen::VectorXd q = problem.data.q.col(start), dq = problem.data.dq.col(start), tau(n);
    VectorX<Jet> q_j = q.cast<Jet>(), dq_j = dq.cast<Jet>(), tau_j(n);
    rollOutSegment(model, data, problem, s, q, dq, tau);
    rollOutSegment(model_j, data_j, problem, s, q_j, dq_j, tau_j);
    // Round-off only: the double instantiation may evaluate the same formulas in another order
    // (merged sincos, RK4's stage series), 50 RK4 steps from a state of order 1.
    for (int j = 0; j < n; ++j) {
      EXPECT_NEAR(q_j[j].a, q[j], 1e-12) << s;
      EXPECT_NEAR(dq_j[j].a, dq[j], 1e-11) << s;
    }
    total +=
        (q - problem.data.q.col(end)).squaredNorm() + (dq - problem.data.dq.col(end)).squaredNorm();
  }
  ThreadPool pool(1);
  GcWorkspace workspace(1, 1);  // the scalar path: the same code as the loop above, bit for bit
  EXPECT_EQ(gcError(model, problem, workspace, pool), total);
}

}  // namespace
}  // namespace dynid
