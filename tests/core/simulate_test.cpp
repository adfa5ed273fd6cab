#include "core/simulate.hpp"

#include <gtest/gtest.h>

#include "core/aba.hpp"
#include "core/errors.hpp"
#include "core/friction.hpp"
#include "core/kinematics.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TrackingController sinusoidalController(const Model& model) {
  return test::pumaSinusoidController(model, 0.4, 0.2, 0.6);
}

TEST(Simulate, RecordsExactAccelerationsAndReplaysFromRecordedTorques) {
  const Model model = makePuma560(true);
  TrackingController controller = sinusoidalController(model);
  SimulationOptions options;
  options.duration = 0.5;
  options.step = 5e-4;
  options.record_rate = 200.0;
  const Trajectory tr = simulate(model, controller, options);
  ASSERT_EQ(tr.numSamples(), 101);
  EXPECT_DOUBLE_EQ(tr.time[100], 0.5);
  Data data(model);
  for (int k = 0; k + 1 < tr.numSamples(); k += 10) {
    EXPECT_EQ(aba(model, data, tr.q.col(k), tr.dq.col(k), tr.tau.col(k)), tr.ddq.col(k));
    // Rolling out from sample k with its held torque, the same integrator and step reproduces
    // sample k + 1 bit for bit: the property the GC error relies on.
    Eigen::VectorXd q = tr.q.col(k), dq = tr.dq.col(k);
    for (int s = 0; s < 10; ++s) rk4Step(model, data, q, dq, tr.tau.col(k), 5e-4);
    EXPECT_EQ(q, tr.q.col(k + 1));
    EXPECT_EQ(dq, tr.dq.col(k + 1));
  }
}

// A wrench's joint torques do the same virtual work as the wrench: tau . dq = F . v + M . w, with
// the link origin's velocity v and the link's angular velocity w by central differences.
TEST(Simulate, AWrenchsJointTorquesDoItsVirtualWork) {
  const Model model = test::randomTree(3);
  Data data(model);
  std::mt19937_64 rng(3);
  const int n = model.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.0), dq = test::randomVector(rng, n, 1.0);
  const Eigen::Vector3d force(3.0, -2.0, 5.0), moment(0.5, 1.5, -1.0);
  for (int link = 0; link < n; ++link) {
    const Eigen::VectorXd tau = wrenchJointTorques(model, data, q, link, force, moment);
    const double h = 1e-6;
    forwardKinematics(model, data, Eigen::VectorXd(q + h * dq));
    const Pose<double> plus = data.oMi[link];
    forwardKinematics(model, data, Eigen::VectorXd(q - h * dq));
    const Pose<double> minus = data.oMi[link];
    const Eigen::Vector3d v = (plus.translation - minus.translation) / (2 * h);
    const Eigen::Matrix3d dR = (plus.rotation - minus.rotation) / (2 * h);
    const Eigen::Matrix3d skew = dR * minus.rotation.transpose();  // ~ [w]x
    const Eigen::Vector3d w(skew(2, 1), skew(0, 2), skew(1, 0));
    // Central differences of smooth kinematics: O(h^2) truncation, ~1e-10 cancellation per unit.
    EXPECT_NEAR(tau.dot(dq), force.dot(v) + moment.dot(w), 1e-6) << "link " << link;
  }
  EXPECT_THROW(wrenchJointTorques(model, data, q, n, force, moment), InputError);
}

TEST(Simulate, ADisturbanceMovesTheArmAndIsRecordedAsTheTruth) {
  const Model model = makePuma560();
  SimulationOptions options;
  options.duration = 1.0;
  TrackingController calm = sinusoidalController(model), pushed = sinusoidalController(model);
  const Trajectory clean = simulate(model, calm, options);
  Disturbance push;
  push.start = 0.4, push.duration = 0.1, push.joint = 2, push.torque = 20.0;
  Disturbance wrench;
  wrench.start = 0.7, wrench.duration = 0.05, wrench.link = 5, wrench.force = {0, 0, -30};
  Eigen::MatrixXd applied;
  const Trajectory tr = simulate(model, pushed, options, {push, wrench}, &applied);
  ASSERT_EQ(applied.cols(), tr.numSamples());
  Data data(model);
  for (int k = 0; k < tr.numSamples(); ++k) {
    const double t = tr.time[k];
    const bool pushing = t >= 0.4 && t < 0.5 - 1e-12, twisting = t >= 0.7 && t < 0.75 - 1e-12;
    if (k < 400) {
      // Before the first push the runs are the same, bit for bit.
      EXPECT_EQ(tr.q.col(k), clean.q.col(k)) << t;
      EXPECT_EQ(applied.col(k).norm(), 0.0) << t;
    }
    if (pushing) {
      EXPECT_EQ(applied(2, k), 20.0) << t;
    }
    if (!pushing && !twisting) {
      EXPECT_EQ(applied.col(k).norm(), 0.0) << t;
    }
    if (twisting) {
      const Eigen::VectorXd expected =
          wrenchJointTorques(model, data, tr.q.col(k), 5, Eigen::Vector3d(0, 0, -30), {0, 0, 0});
      EXPECT_LT((applied.col(k) - expected).norm(), 1e-12) << t;
    }
    // The recorded acceleration is the true one, under the controller's torque and the push.
    const Eigen::VectorXd total = tr.tau.col(k) + applied.col(k);
    EXPECT_LT((aba(model, data, tr.q.col(k), tr.dq.col(k), total) - tr.ddq.col(k)).norm(), 1e-12);
  }
  // The push moved joint 3 off the clean run.
  EXPECT_GT((tr.q.row(2) - clean.q.row(2)).cwiseAbs().maxCoeff(), 1e-3);
  Disturbance bad = push;
  bad.joint = 6;
  EXPECT_THROW(simulate(model, pushed, options, {bad}), InputError);
  bad = push;
  bad.link = 1;  // both a joint and a link
  EXPECT_THROW(simulate(model, pushed, options, {bad}), InputError);
  bad = push;
  bad.duration = 0.0;
  EXPECT_THROW(simulate(model, pushed, options, {bad}), InputError);
}

TEST(Simulate, TracksTheReference) {
  const Model model = makePuma560();
  TrackingController controller = sinusoidalController(model);
  SimulationOptions options;
  options.duration = 3.0;
  const Trajectory tr = simulate(model, controller, options);
  Eigen::VectorXd q, dq, ddq;
  double worst = 0.0;
  for (int k = 0; k < tr.numSamples(); ++k) {
    evaluateReference(controller.reference(), tr.time[k], q, dq, ddq);
    worst = std::max(worst, (tr.q.col(k) - q).cwiseAbs().maxCoeff());
  }
  // PD at 5 Hz bandwidth with exact gravity feed-forward tracking 0.2-0.6 Hz sines of 0.4 rad:
  // the lag leaves errors of a few hundredths of a radian.
  EXPECT_LT(worst, 0.1);
}

TEST(Simulate, NoiseIsSeeded) {
  const Model model = makePuma560();
  SimulationOptions options;
  options.duration = 2.0;
  options.noise_q = 1e-3;
  TrackingController c1 = sinusoidalController(model), c2 = sinusoidalController(model),
                     c3 = sinusoidalController(model), c0 = sinusoidalController(model);
  const Trajectory a = simulate(model, c1, options), b = simulate(model, c2, options);
  EXPECT_EQ(a.q, b.q);
  options.seed = 2;
  const Trajectory c = simulate(model, c3, options);
  EXPECT_NE(a.q, c.q);
  options.noise_q = 0.0;
  const Trajectory clean = simulate(model, c0, options);
  const Eigen::ArrayXXd noise = (a.q - clean.q).array();
  const double sigma = std::sqrt(noise.square().mean());
  // 12006 samples: the estimated sigma is within a few percent of 1e-3.
  EXPECT_NEAR(sigma, 1e-3, 0.05e-3);
  EXPECT_EQ(a.tau, clean.tau);  // noise only on the recorded q
}

TEST(Simulate, RejectsBadSettings) {
  const Model model = makePuma560();
  TrackingController controller = sinusoidalController(model);
  SimulationOptions options;
  options.step = 3e-4;  // 1 ms is not a whole number of 0.3 ms steps
  try {
    simulate(model, controller, options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a whole multiple"), std::string::npos);
  }
  options.step = 1e-3;
  options.duration = -1.0;
  EXPECT_THROW(simulate(model, controller, options), InputError);
  options.duration = 1.0;
  options.noise_dq = std::nan("");
  EXPECT_THROW(simulate(model, controller, options), InputError);
  options.noise_dq = 0.0;
  options.step = 1e-12;  // would never finish
  EXPECT_THROW(simulate(model, controller, options), InputError);
}

TEST(Simulate, ReportsDivergence) {
  const Model model = makePuma560();
  SinusoidalReference r;
  r.q0 = Eigen::VectorXd::Zero(6);
  r.amplitude = r.frequency = r.phase = Eigen::VectorXd::Zero(6);
  // Absurd gains with a coarse step make the discrete loop unstable.
  TrackingController controller(
      model, r, {Eigen::VectorXd::Constant(6, 1e9), Eigen::VectorXd::Constant(6, 1e7)},
      Eigen::VectorXd::Constant(6, 1e300));
  SimulationOptions options;
  options.duration = 5.0;
  options.step = 1e-2;
  options.record_rate = 100.0;
  r.q0[0] = 0.1;
  try {
    simulate(model, controller, options);
    FAIL();
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("diverged at t ="), std::string::npos);
    // The cause: kd/M's rate is about 1e7/s against a period of 0.01 s.
    EXPECT_NE(std::string(e.what()).find("the controller's damping is too high"), std::string::npos)
        << e.what();
  }
}

// The PUMA's drive friction without its rotor inertias: Fv6 = 0.216 N m s on link 6's 4e-5 kg m^2
// decays in about 0.2 ms, and RK4 at 1 ms diverges. The message names the joint, the missing rotor
// inertia and a step that divides the recording period; with that step the simulation is stable.
TEST(Simulate, NamesTheFrictionThatOutrunsTheStepAndAStepThatHolds) {
  Model model = makePuma560(true);
  model.setDriveTerms(DriveTerms::of({DriveTerm::kViscous}));
  SimulationOptions options;
  options.duration = 0.5;
  std::string message;
  try {
    TrackingController controller = sinusoidalController(model);
    simulate(model, controller, options);
  } catch (const NumericalError& e) {
    message = e.what();
  }
  ASSERT_NE(message.find("diverged at t ="), std::string::npos) << message;
  EXPECT_NE(message.find("mostly joint 6 (Fv6 = 0.216 N m s)"), std::string::npos) << message;
  EXPECT_NE(message.find("(Ia6 = 0.194 kg m^2) are not among its drive terms"), std::string::npos)
      << message;
  const std::string marker = "a step of ";
  const std::size_t at = message.find(marker);
  ASSERT_NE(at, std::string::npos) << message;
  const double step = std::stod(message.substr(at + marker.size()));
  const long substeps = std::lround(1e-3 / step);
  EXPECT_GT(substeps, 1);
  EXPECT_NEAR(1e-3 / step, static_cast<double>(substeps), 1e-6);  // divides the period
  options.step = 1e-3 / static_cast<double>(substeps);
  TrackingController controller = sinusoidalController(model);
  const Trajectory tr = simulate(model, controller, options);
  EXPECT_TRUE(tr.q.allFinite() && tr.dq.allFinite());
}

// A resting joint is held by its static friction: a push inside the band leaves every recorded
// signal as it was, bit for bit, where the law's sign(dq) (stiction off) lets it creep; a push
// beyond the band breaks it away at once.
TEST(Simulate, AJointAtRestSticksWhileItsStaticFrictionCanHoldIt) {
  const Model model = makePuma560(true);  // Coulomb friction and its asymmetry through the gears
  const int j = 1;                        // the shoulder, loaded by gravity
  const auto [lo, hi] = staticFrictionBand(model, j);
  ASSERT_LT(lo, 0.0);
  ASSERT_GT(hi, 0.0);
  const auto run = [&](double push, bool stiction) {
    TrackingController hold = test::pumaSinusoidController(model, 0.0, 0.2, 0.6);
    SimulationOptions options;
    options.duration = 1.0;
    options.stiction = stiction;
    Disturbance d;
    d.joint = j, d.start = 0.3, d.duration = 0.2, d.torque = push;
    return simulate(model, hold, options, {d});
  };
  const Trajectory still = run(0.0, true);
  EXPECT_EQ(still.dq.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(still.ddq.cwiseAbs().maxCoeff(), 0.0);
  for (const double push : {0.9 * hi, 0.9 * lo}) {
    const Trajectory held = run(push, true);
    EXPECT_EQ(held.q, still.q) << push;
    EXPECT_EQ(held.dq, still.dq) << push;
    EXPECT_EQ(held.tau, still.tau) << push;
    // Without stiction the same push moves the joint against the controller (kp ~ 1e3 N m/rad:
    // about 1e-3 rad).
    const Trajectory crept = run(push, false);
    EXPECT_GT((crept.q.row(j) - still.q.row(j)).cwiseAbs().maxCoeff(), 1e-5) << push;
  }
  for (const double push : {1.1 * hi, 1.1 * lo}) {
    const Trajectory broke = run(push, true);
    const int k = 301;  // one sample after the push began
    EXPECT_EQ(broke.dq(j, k - 1), 0.0);
    EXPECT_GT(push * broke.dq(j, k), 0.0) << push;
  }
}

// Every recorded sample obeys the truth's friction: its law where the joint moves, and a value
// within the static band where it rests; a paused motion spends its holds stuck.
TEST(Simulate, TheRecordedSamplesObeyTheFrictionLawMovingAndTheBandAtRest) {
  const Model model = makePuma560(true);
  const int n = model.numJoints();
  Data data(model);
  Pauses pauses;
  pauses.move = 2.0, pauses.hold = 1.5, pauses.ramp = 0.5;
  const auto run = [&](bool stiction) {
    TrackingController controller = test::pumaSinusoidController(model, 0.4, 0.2, 0.6);
    controller.setPauses(pauses);
    SimulationOptions options;
    options.duration = 7.0;
    options.stiction = stiction;
    return simulate(model, controller, options);
  };
  const Trajectory tr = run(true);
  std::vector<int> resting(n, 0);
  for (int k = 0; k < tr.numSamples(); ++k) {
    const Eigen::VectorXd friction =
        tr.tau.col(k) - rnea(model, data, tr.q.col(k), tr.dq.col(k), tr.ddq.col(k));
    for (int i = 0; i < n; ++i) {
      // Inverse dynamics of the recorded state against the forward step's: round-off of a few
      // ulps of the torques (up to ~100 N m).
      const double tol = 1e-9 * (1.0 + std::abs(tr.tau(i, k)));
      if (tr.dq(i, k) != 0.0) {
        EXPECT_NEAR(friction[i], 0.0, tol) << "t = " << tr.time[k] << ", joint " << i + 1;
        continue;
      }
      ++resting[i];
      const auto [lo, hi] = staticFrictionBand(model, i);
      EXPECT_GE(friction[i], lo - tol) << "t = " << tr.time[k] << ", joint " << i + 1;
      EXPECT_LE(friction[i], hi + tol) << "t = " << tr.time[k] << ", joint " << i + 1;
    }
  }
  // Two holds of 1.5 s (3000 samples) and the slow ends of the moves around them.
  for (int i = 0; i < n; ++i) EXPECT_GT(resting[i], 1500) << "joint " << i + 1;
  // The law's sign(dq) lets the resting joints chatter about zero instead.
  const Trajectory chatter = run(false);
  for (int i = 0; i < n; ++i)
    EXPECT_LT((chatter.dq.row(i).array() == 0.0).count(), 10) << "joint " << i + 1;
}

}  // namespace
}  // namespace dynid
