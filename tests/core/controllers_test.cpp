#include "core/controllers.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

void expectDerivativesConsistent(const Reference& reference) {
  Eigen::VectorXd q, dq, ddq, qp, dqp, ddqp, qm, dqm, ddqm;
  const double t = 1.3, h = 1e-5;
  evaluateReference(reference, t, q, dq, ddq);
  evaluateReference(reference, t + h, qp, dqp, ddqp);
  evaluateReference(reference, t - h, qm, dqm, ddqm);
  // Central differences, truncation O(h^2 q''') ~ 1e-10 for rad-scale motions.
  EXPECT_LT(((qp - qm) / (2 * h) - dq).norm(), 1e-8);
  EXPECT_LT(((dqp - dqm) / (2 * h) - ddq).norm(), 1e-8);
}

TEST(Controllers, SinusoidalReferenceIsConsistent) {
  SinusoidalReference r;
  r.q0 = Eigen::Vector3d(0.1, -0.2, 0.3);
  r.amplitude = Eigen::Vector3d(0.5, 0.4, 0.3);
  r.frequency = Eigen::Vector3d(0.2, 0.35, 0.5);
  r.phase = Eigen::Vector3d(0.0, 1.0, -0.5);
  Eigen::VectorXd q, dq, ddq;
  evaluateReference(r, 0.0, q, dq, ddq);
  EXPECT_NEAR(q[1], -0.2 + 0.4 * std::sin(1.0), 1e-15);
  expectDerivativesConsistent(r);
  r.phase = Eigen::Vector2d::Zero();  // wrong size
  EXPECT_THROW(evaluateReference(r, 0.0, q, dq, ddq), InputError);
}

TEST(Controllers, FourierSeriesIsConsistent) {
  FourierSeries r;
  r.offset = Eigen::Vector2d(0.1, 0.2);
  r.period = 10.0;
  r.a = Eigen::Matrix<double, 2, 3>::Random();
  r.b = Eigen::Matrix<double, 2, 3>::Random();
  expectDerivativesConsistent(r);
}

TEST(Controllers, FeedForwardUsesTheControllersOwnModel) {
  const Model truth = makePuma560();
  Model controller_model = truth;
  RigidInertia<double> heavier = controller_model.inertias()[1];
  heavier.mass *= 1.2;
  controller_model.setLinkInertia(1, heavier);
  SinusoidalReference r;
  r.q0 = puma560Pose("qn");
  r.amplitude = r.frequency = r.phase = Eigen::VectorXd::Zero(6);
  TrackingController controller(controller_model, r, defaultGains(controller_model, r.q0),
                                Eigen::VectorXd::Constant(6, 1e9));
  // On the reference, tau is the controller model's gravity torque, not the truth's.
  Eigen::VectorXd tau(6);
  controller.compute(0.0, r.q0, Eigen::VectorXd::Zero(6), tau);
  Data data(controller_model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  EXPECT_LT((tau - rnea(controller_model, data, r.q0, zero, zero)).norm(), 1e-12);
  Data truth_data(truth);
  EXPECT_GT((tau - rnea(truth, truth_data, r.q0, zero, zero)).norm(), 0.1);
}

TEST(Controllers, SaturatesAndTracksWithPdGains) {
  const Model model = makePuma560();
  SinusoidalReference r;
  r.q0 = Eigen::VectorXd::Zero(6);
  r.amplitude = r.frequency = r.phase = Eigen::VectorXd::Zero(6);
  TrackingGains gains{Eigen::VectorXd::Constant(6, 100.0), Eigen::VectorXd::Constant(6, 10.0)};
  TrackingController controller(model, r, gains, Eigen::VectorXd::Constant(6, 2.0));
  Eigen::VectorXd tau(6);
  controller.compute(0.0, Eigen::VectorXd::Constant(6, 0.5), Eigen::VectorXd::Zero(6), tau);
  // Kp e = -50 on every joint, clamped to the +-2 N m limit.
  EXPECT_TRUE((tau.array() == -2.0).all()) << tau.transpose();
  EXPECT_THROW(TrackingController(model, r, gains, Eigen::VectorXd::Constant(6, -1.0)), InputError);
  const TrackingGains g = defaultGains(model, r.q0, 5.0, 1.0);
  EXPECT_GT(g.kp.minCoeff(), 0.0);
  EXPECT_NEAR(g.kd[0] / g.kp[0], 2.0 / (2 * M_PI * 5.0), 1e-12);
}

TEST(Controllers, EffectiveInertiaGainsBoundEveryClosedLoopModeWhereTheDiagonalsDoNot) {
  // The Panda at simulate's default centre: strongly coupled axes, so the mass-matrix diagonal's
  // gains put a closed-loop mode above 3 times the bandwidth (the chatter of a 1 kHz loop); the
  // effective inertias' gains keep every mode within sqrt(n) times it (max eig <= trace).
  const Model panda = makePanda(true);
  const Eigen::VectorXd rest = defaultCentre(panda);
  const double bandwidth = 5.0;
  EXPECT_GT(closedLoopFrequency(panda, rest, defaultGains(panda, rest, bandwidth).kp),
            3.0 * bandwidth);
  const TrackingGains effective = effectiveInertiaGains(panda, rest, bandwidth);
  const double highest = closedLoopFrequency(panda, rest, effective.kp);
  EXPECT_LE(highest, std::sqrt(7.0) * bandwidth * (1.0 + 1e-12));  // the trace bound, round-off
  EXPECT_GE(highest, bandwidth * (1.0 - 1e-12));  // the largest eigenvalue is at least the mean
  // The PUMA keeps the paper's diagonal gains: their modes stay within 3 times the bandwidth.
  const Model puma = makePuma560(true);
  const Eigen::VectorXd q0 = defaultCentre(puma);
  EXPECT_LE(closedLoopFrequency(puma, q0, defaultGains(puma, q0, bandwidth).kp), 3.0 * bandwidth);
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

TEST(Controllers, PausesStopTheReferenceSmoothlyAndHoldIt) {
  const Model model = makePuma560();
  const int n = model.numJoints();
  SinusoidalReference r;
  r.q0 = Eigen::VectorXd::Zero(n);
  r.amplitude = Eigen::VectorXd::Constant(n, 0.5);
  r.frequency = defaultFrequencies(n);
  r.phase = Eigen::VectorXd::Constant(n, 0.3);
  TrackingController controller(model, r, defaultGains(model, r.q0),
                                Eigen::VectorXd::Constant(n, 1e3));
  Pauses p;
  p.move = 3.0, p.hold = 1.5, p.ramp = 0.4;
  controller.setPauses(p);
  Eigen::VectorXd q, dq, ddq, qp, dqp, ddqp, qm, dqm, ddqm;
  // Central differences of the warped reference at every phase of a cycle: the ramps, full
  // speed, the hold and the second cycle (truncation O(h^2) ~ 1e-10 at rad-scale motions).
  const double h = 1e-5;
  for (double t : {0.1, 0.35, 1.7, 2.75, 2.95, 3.8, 4.6, 6.0, 7.3}) {
    controller.desired(t, q, dq, ddq);
    controller.desired(t + h, qp, dqp, ddqp);
    controller.desired(t - h, qm, dqm, ddqm);
    EXPECT_LT(((qp - qm) / (2 * h) - dq).norm(), 1e-8) << t;
    EXPECT_LT(((dqp - dqm) / (2 * h) - ddq).norm(), 1e-7) << t;
  }
  // At rest from t = 0 and through the hold, at the pose where the motion stopped.
  controller.desired(0.0, q, dq, ddq);
  EXPECT_EQ(dq.norm(), 0.0);
  controller.desired(3.2, q, dq, ddq);
  EXPECT_EQ(dq.norm() + ddq.norm(), 0.0);
  controller.desired(4.4, qp, dqp, ddqp);
  EXPECT_EQ((q - qp).norm(), 0.0);
  // The reference's own time advanced by move - ramp per cycle: the second hold's pose is the
  // unpaused reference's at 2 (move - ramp).
  controller.desired(8.0, q, dq, ddq);
  evaluateReference(r, 2 * (p.move - p.ramp), qp, dqp, ddqp);
  EXPECT_LT((q - qp).norm(), 1e-12);
  p.ramp = 2.0;  // move must exceed two ramps
  EXPECT_THROW(controller.setPauses(p), InputError);
}

}  // namespace
}  // namespace dynid
