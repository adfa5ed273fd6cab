// ceres::Jet flows through every templated algorithm: the values equal the double ones and the
// derivatives equal central finite differences.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "core/aba-inl.hpp"
#include "core/crba-inl.hpp"
#include "core/integrators-inl.hpp"
#include "core/kinematics-inl.hpp"
#include "core/model-inl.hpp"
#include "core/rnea-inl.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

constexpr int kN = 6;
using Jet = ceres::Jet<double, kN>;
using VectorJ = VectorX<Jet>;

/// A Jet vector with value x and derivative seeds e_{offset+i} on its entries (when seed).
VectorJ toJet(const Eigen::VectorXd& x, bool seed, int offset = 0) {
  VectorJ out(x.size());
  for (int i = 0; i < x.size(); ++i)
    out[i] = seed && i + offset < kN ? Jet(x[i], i + offset) : Jet(x[i]);
  return out;
}

Eigen::VectorXd values(const VectorJ& x) {
  Eigen::VectorXd out(x.size());
  for (int i = 0; i < x.size(); ++i) out[i] = x[i].a;
  return out;
}

class JetOnModels : public ::testing::TestWithParam<int> {
 protected:
  Model model() const {
    return GetParam() == 0 ? makePuma560(true)
                           : test::randomTree(GetParam(), {.num_bodies = 6, .drives = true});
  }
};

TEST_P(JetOnModels, RneaValuesAndPositionDerivatives) {
  const Model m = model();
  const ModelTpl<Jet> mj = m.cast<Jet>();
  Data data(m);
  DataTpl<Jet> data_j(mj);
  std::mt19937_64 rng(GetParam());
  const int n = m.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.5), dq = test::randomVector(rng, n, 1.5),
                        ddq = test::randomVector(rng, n, 1.5);
  const VectorJ tau_j = rnea(mj, data_j, toJet(q, true), toJet(dq, false), toJet(ddq, false));
  const Eigen::VectorXd tau = rnea(m, data, q, dq, ddq);
  // Same operations in another scalar type: equal to round-off.
  EXPECT_LT((values(tau_j) - tau).norm(), 1e-12 * (1 + tau.norm()));
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd qp = q, qm = q;
    qp[k] += h, qm[k] -= h;
    // rnea returns a reference into data: copy each result before the next call.
    const Eigen::VectorXd tau_plus = rnea(m, data, qp, dq, ddq);
    const Eigen::VectorXd tau_minus = rnea(m, data, qm, dq, ddq);
    const Eigen::VectorXd fd = (tau_plus - tau_minus) / (2 * h);
    for (int i = 0; i < n; ++i)
      // Central difference: O(h^2) truncation plus 1e-16 * |tau| / h cancellation ~ 1e-8.
      EXPECT_NEAR(tau_j[i].v[k], fd[i], 1e-6 * (1 + std::abs(fd[i]))) << "dtau" << i << "/dq" << k;
  }
}

TEST_P(JetOnModels, ParameterDerivativesThroughRneaAndAba) {
  const Model m = model();
  ModelTpl<Jet> mj = m.cast<Jet>();
  std::mt19937_64 rng(10 + GetParam());
  const int n = m.numJoints();
  const Eigen::VectorXd theta = m.standardParameters();
  // Seed 6 parameters spread over the vector: masses, first moments, inertias and drives.
  const std::vector<int> seeded = {0, 11, 19, 25, 33, static_cast<int>(theta.size()) - 3};
  VectorJ theta_j = toJet(theta, false);
  for (int k = 0; k < kN; ++k) theta_j[seeded[k]].v[k] = 1.0;
  mj.setStandardParameters(theta_j);
  DataTpl<Jet> data_j(mj);
  Data data(m);
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.5), dq = test::randomVector(rng, n, 1.5),
                        ddq = test::randomVector(rng, n, 1.5), tau = test::randomVector(rng, n, 5);
  const VectorJ tau_j = rnea(mj, data_j, toJet(q, false), toJet(dq, false), toJet(ddq, false));
  const VectorJ ddq_j = aba(mj, data_j, toJet(q, false), toJet(dq, false), toJet(tau, false));
  const double h = 1e-6;
  for (int k = 0; k < kN; ++k) {
    auto with = [&](double delta) {
      Model copy = m;
      Eigen::VectorXd t = theta;
      t[seeded[k]] += delta;
      copy.setStandardParameters(t);
      return copy;
    };
    const Model plus = with(h), minus = with(-h);
    Data dp(plus), dm(minus);
    // tau is linear in theta: the difference quotient is exact up to cancellation (~1e-9).
    const Eigen::VectorXd fd_tau =
        (rnea(plus, dp, q, dq, ddq) - rnea(minus, dm, q, dq, ddq)) / (2 * h);
    const Eigen::VectorXd fd_ddq =
        (aba(plus, dp, q, dq, tau) - aba(minus, dm, q, dq, tau)) / (2 * h);
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(tau_j[i].v[k], fd_tau[i], 1e-6 * (1 + std::abs(fd_tau[i])));
      EXPECT_NEAR(ddq_j[i].v[k], fd_ddq[i], 1e-5 * (1 + std::abs(fd_ddq[i])));
    }
  }
}

TEST_P(JetOnModels, Rk4RolloutAndMassMatrix) {
  const Model m = model();
  const ModelTpl<Jet> mj = m.cast<Jet>();
  std::mt19937_64 rng(20 + GetParam());
  const int n = m.numJoints();
  const Eigen::VectorXd q0 = test::randomVector(rng, n, 1.0), dq0 = test::randomVector(rng, n, 1.0),
                        tau = test::randomVector(rng, n, 2.0);
  // d(final state)/d(initial q) through 20 RK4 steps.
  auto rollout = [&](const Eigen::VectorXd& q_start) {
    Data data(m);
    Eigen::VectorXd q = q_start, dq = dq0;
    for (int s = 0; s < 20; ++s) rk4Step(m, data, q, dq, tau, 1e-3);
    return q;
  };
  DataTpl<Jet> data_j(mj);
  VectorJ q = toJet(q0, true), dq = toJet(dq0, false);
  const VectorJ tau_j = toJet(tau, false);
  for (int s = 0; s < 20; ++s) rk4Step(mj, data_j, q, dq, tau_j, Jet(1e-3));
  EXPECT_LT((values(q) - rollout(q0)).norm(), 1e-12);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd qp = q0, qm = q0;
    qp[k] += h, qm[k] -= h;
    const Eigen::VectorXd fd = (rollout(qp) - rollout(qm)) / (2 * h);
    for (int i = 0; i < n; ++i) EXPECT_NEAR(q[i].v[k], fd[i], 1e-7) << i << "/" << k;
  }
  Data data(m);
  const MatrixX<Jet> M_j = crba(mj, data_j, toJet(q0, true));
  const Eigen::MatrixXd M = crba(m, data, q0);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) EXPECT_NEAR(M_j(r, c).a, M(r, c), 1e-13);
}

INSTANTIATE_TEST_SUITE_P(Models, JetOnModels, ::testing::Values(0, 3, 4));

TEST(Jet, PlacementWithADerivativeTakesTheGeneralAbaPath) {
  // ABA's permuted path treats a signed-permutation placement as constant; an exact 0 whose
  // derivative is not 0 (a kinematic parameter being differentiated) must not be taken for one.
  ModelTpl<Jet> mj = makePuma560(false).cast<Jet>();
  mj.finalize();
  EXPECT_EQ(mj.placement_permutation()[2], 0);
  Pose<Jet> placement = mj.body_placements()[1];
  placement.rotation(0, 1) = Jet(0.0, 0);
  mj.setBodyPlacement(1, placement);
  EXPECT_EQ(mj.placement_permutation()[2], -1);
}

}  // namespace
}  // namespace dynid
