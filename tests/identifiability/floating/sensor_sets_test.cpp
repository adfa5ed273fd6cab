// What each sensor set of a floating robot determines: counts against an independent computation
// (the virtual chain's fixed-base regressor, tests/common/floating_models, with its own contact
// Jacobians in world axes and an SVD rank), and noise-free recovery of the determined
// combinations.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include "core/aba.hpp"
#include "core/floating/floating_regressor.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/kinematics.hpp"
#include "core/regressor.hpp"
#include "data/urdf.hpp"
#include "identifiability/floating/sensor_sets.hpp"
#include "tests/common/floating_models.hpp"

namespace dynid {
namespace {

/// Point contacts at a point of each of the tree's leaves (bodies no other body hangs from).
std::vector<Contact> leafContacts(const FloatingModel& model) {
  const Model& limbs = model.limbs();
  std::vector<Contact> out;
  for (int i = 0; i < limbs.numJoints(); ++i) {
    if (std::find(limbs.parents().begin(), limbs.parents().end(), i) != limbs.parents().end())
      continue;
    Contact c;
    c.name = "foot" + std::to_string(i);
    c.body = i;
    c.placement.translation << 0.05, -0.02, 0.15;
    out.push_back(c);
  }
  return out;
}

/// The numerical rank of W with unit-norm columns (zero columns dropped), by SVD: singular values
/// above 1e-8 of the largest (the rank rule's threshold, docs/IDENTIFIABILITY.md).
int svdRank(Eigen::MatrixXd W) {
  for (Eigen::Index c = 0; c < W.cols(); ++c)
    if (W.col(c).norm() > 0) W.col(c).normalize();
  // A tall W's singular values are those of R in W = QR (Q's columns orthonormal): the SVD of the
  // square factor, half the work of bidiagonalising W itself.
  if (W.rows() > W.cols()) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
    W = qr.matrixQR().topRows(W.cols()).triangularView<Eigen::Upper>();
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(W);
  const Eigen::VectorXd s = svd.singularValues();
  return static_cast<int>((s.array() > 1e-8 * s[0]).count());
}

/// The chain's contact Jacobian (world axes, the chain's velocities): per active contact a point's
/// linear velocity (3 rows) or a frame's angular and linear (6 rows).
Eigen::MatrixXd chainJacobian(const Model& chain, Data& data,
                              const std::vector<const Contact*>& active, const Eigen::VectorXd& q) {
  forwardKinematics(chain, data, q);
  int rows = 0;
  for (const Contact* c : active) rows += c->dimension();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, chain.numJoints());
  rows = 0;
  for (const Contact* c : active) {
    const int body = c->body + 6;  // the chain's body of the floating body
    const Eigen::Vector3d r = (data.oMi[body] * c->placement).translation;
    for (int j = body; j >= 0; j = chain.parents()[j]) {
      const Vector6<double> s = data.oMj[j].actMotion(jointMotionAt(chain, j, 1.0));
      const Eigen::Vector3d linear = s.tail<3>() + s.head<3>().cross(r);
      if (c->kind == Contact::Kind::kPoint) {
        J.block<3, 1>(rows, j) = linear;
      } else {
        J.block<3, 1>(rows, j) = s.head<3>();
        J.block<3, 1>(rows + 3, j) = linear;
      }
    }
    rows += c->dimension();
  }
  return J;
}

/// The sensor set's rank through the virtual chain: its regressor's rows (the six virtual joints'
/// torques are the base wrench in another basis) over the base body's and limbs' columns, in
/// states of the motion's class: holding (velocities in the null space of the chain's own contact
/// Jacobian, accelerations that keep the points still), free, suspended (the virtual joints
/// still) or carried (the virtual joints moving as drawn, their torques the support's wrench); for
/// contact flags the rows orthogonal to what holds.
int chainRank(const FloatingModel& model, SensorSet set, const std::vector<Contact>& contacts,
              FloatingMotion motion, std::uint64_t seed) {
  const Model chain = test::virtualChain(model);
  Data data(chain);
  const int n = model.numJoints(), nv = 6 + n, p = 10 * (n + 1);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int samples = 150;
  Eigen::MatrixXd W(samples * nv, p);  // at most nv rows a sample
  Eigen::Index filled = 0;
  for (int sample = 0; sample < samples; ++sample) {
    const Eigen::VectorXd q = test::randomVector(rng, nv, 1.2);
    Eigen::VectorXd dq = test::randomVector(rng, nv, 1.5);
    Eigen::VectorXd ddq = test::randomVector(rng, nv, 3.0);
    Eigen::MatrixXd J(0, nv);
    if (motion == FloatingMotion::kFree) {
      // In flight: the virtual joints carry no torque (no wrench on the base), the limbs' drawn.
      Eigen::VectorXd tau = test::randomVector(rng, nv, 10.0);
      tau.head<6>().setZero();
      ddq = aba(chain, data, q, dq, tau);
    } else if (motion == FloatingMotion::kSuspended) {
      dq.head<6>().setZero(), ddq.head<6>().setZero();
      J = Eigen::MatrixXd::Identity(6, nv);  // the virtual joints held
    } else if (motion == FloatingMotion::kCarried) {
      J = Eigen::MatrixXd::Identity(6, nv);  // the virtual joints driven by the support
    } else if (motion == FloatingMotion::kHolding) {
      std::vector<const Contact*> active;
      for (const Contact& c : contacts)
        if (unit(rng) < 0.5) active.push_back(&c);
      J = chainJacobian(chain, data, active, q);
      if (J.rows() == 0 || Eigen::FullPivLU<Eigen::MatrixXd>(J.leftCols<6>()).rank() < 6) {
        --sample;
        continue;
      }
      const Eigen::MatrixXd N = Eigen::FullPivLU<Eigen::MatrixXd>(J).kernel();
      dq = N * test::randomVector(rng, static_cast<int>(N.cols()), 1.5);
      const double h = 1e-6;
      const Eigen::VectorXd bias = (chainJacobian(chain, data, active, q + h * dq) -
                                    chainJacobian(chain, data, active, q - h * dq)) *
                                   dq / (2 * h);
      ddq = N * test::randomVector(rng, static_cast<int>(N.cols()), 3.0) -
            J.completeOrthogonalDecomposition().solve(bias);
    }
    const Eigen::MatrixXd Y = jointTorqueRegressor(chain, data, q, dq, ddq).rightCols(p);
    Eigen::MatrixXd rows = set == SensorSet::kWrenches ? Eigen::MatrixXd(Y.topRows(6)) : Y;
    if (set == SensorSet::kTorquesAndContactFlags && J.rows() > 0)  // a basis: any will do
      rows = Eigen::MatrixXd(Eigen::FullPivLU<Eigen::MatrixXd>(J).kernel()).transpose() * Y;
    W.middleRows(filled, rows.rows()) = rows;
    filled += rows.rows();
  }
  return svdRank(W.topRows(filled));
}

class SensorSetsOnTrees : public ::testing::TestWithParam<std::tuple<int, FloatingMotion>> {};

TEST_P(SensorSetsOnTrees, CountsEqualTheVirtualChains) {
  const auto [seed, motion] = GetParam();
  const FloatingModel model = test::randomFloating(seed, {.num_bodies = 7});
  FloatingStructuralOptions options;
  options.contacts = leafContacts(model);
  options.motion = motion;
  // In flight nothing carries a wrench: that set is refused, the others analysed.
  const bool flight = motion == FloatingMotion::kFree;
  if (flight) {
    EXPECT_THROW(floatingStructuralBase(model, {SensorSet::kWrenches}, options), InputError);
  }
  std::vector<SensorSet> requested(std::begin(kSensorSets) + (flight ? 1 : 0),
                                   std::end(kSensorSets));
  const std::vector<SensorSetBase> sets = floatingStructuralBase(model, requested, options);
  for (const SensorSetBase& s : sets) {
    SCOPED_TRACE(sensorSetName(s.set));
    EXPECT_EQ(s.base.numBase(), chainRank(model, s.set, options.contacts, motion, seed + 100));
    EXPECT_GT(s.base.rankGap(), 1e4);  // a clear rank decision
  }
  // The wrenches' rows and the flags' projected rows lie in the full rows of the same states.
  const SensorSetBase& full = sets[flight ? 0 : 1];
  for (const SensorSetBase& s : sets) EXPECT_LE(s.base.numBase(), full.base.numBase());
}

INSTANTIATE_TEST_SUITE_P(
    Seeds, SensorSetsOnTrees,
    ::testing::Combine(::testing::Values(1, 2, 3),
                       ::testing::Values(FloatingMotion::kHolding, FloatingMotion::kFree,
                                         FloatingMotion::kSuspended, FloatingMotion::kCarried)));

/// The example robots (examples/floating/): ANYmal C on its four point feet, Romeo on its two flat
/// soles; each set's count against the virtual chain's.
TEST(SensorSets, ExampleRobotsCountsEqualTheVirtualChains) {
  struct Robot {
    const char* path;
    std::vector<std::pair<const char*, Contact::Kind>> feet;
  };
  for (const Robot& robot :
       {Robot{"examples/floating/anymal_c/anymal.urdf",
              {{"LF_FOOT", Contact::Kind::kPoint},
               {"RF_FOOT", Contact::Kind::kPoint},
               {"LH_FOOT", Contact::Kind::kPoint},
               {"RH_FOOT", Contact::Kind::kPoint}}},
        Robot{"examples/floating/romeo/romeo_small.urdf",
              {{"l_sole", Contact::Kind::kFrame}, {"r_sole", Contact::Kind::kFrame}}}}) {
    SCOPED_TRACE(robot.path);
    const FloatingModel model = loadFloatingUrdf(std::string(DYNID_SOURCE_DIR) + "/" + robot.path);
    FloatingStructuralOptions options;
    for (const auto& [name, kind] : robot.feet) {
      const BodyFrame* frame = model.findFrame(name);
      ASSERT_NE(frame, nullptr);
      options.contacts.push_back({name, frame->body, frame->placement, kind});
    }
    const std::vector<SensorSetBase> sets =
        floatingStructuralBase(model, {std::begin(kSensorSets), std::end(kSensorSets)}, options);
    for (const SensorSetBase& s : sets) {
      SCOPED_TRACE(sensorSetName(s.set));
      EXPECT_EQ(s.base.numBase(),
                chainRank(model, s.set, options.contacts, FloatingMotion::kHolding, 7));
    }
  }
}

TEST(SensorSets, DrivesNeedJointTorques) {
  const FloatingModel model = test::randomFloating(4, {.num_bodies = 5, .drives = true});
  FloatingStructuralOptions options;
  options.contacts = leafContacts(model);
  const std::vector<SensorSetBase> sets =
      floatingStructuralBase(model, {std::begin(kSensorSets), std::end(kSensorSets)}, options);
  const ParameterLayout layout = model.limbs().parameterLayout();
  const int fv = FloatingModel::limbColumn(layout.driveIndex(2, DriveTerm::kViscous));
  const auto has = [](const std::vector<int>& v, int x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  EXPECT_TRUE(has(sets[0].base.zero_columns, fv));  // friction never reaches the base
  EXPECT_TRUE(has(sets[1].determined_alone, fv));   // each joint's torque sees its friction
  EXPECT_TRUE(has(sets[2].determined_alone, fv));
}

/// Noise-free recovery: each set's base parameters from its measurements of a simulated robot in
/// states that hold random subsets of its contacts (FloatingStateSampler::holding), the contact
/// forces the least-norm ones that give the base wrench, the joint torques the rest.
TEST(SensorSets, RecoverTheirCombinationsFromNoiseFreeData) {
  const FloatingModel model = test::randomFloating(5, {.num_bodies = 8, .drives = true});
  FloatingStructuralOptions options;
  options.contacts = leafContacts(model);
  ASSERT_GE(options.contacts.size(), 3u);
  const std::vector<SensorSetBase> sets =
      floatingStructuralBase(model, {std::begin(kSensorSets), std::end(kSensorSets)}, options);
  FloatingData data(model);
  FloatingStructuralOptions data_options = options;
  data_options.structural.seed = 77;  // other states than the analysis drew
  FloatingStateSampler sampler(model, data_options);
  const int n = model.numJoints();
  std::vector<Eigen::MatrixXd> W(3, Eigen::MatrixXd(0, model.numParameters()));
  std::vector<Eigen::VectorXd> y(3);
  for (int sample = 0; sample < 300; ++sample) {
    const FloatingState state = sampler.next();
    const Eigen::VectorXd tau = floatingRnea(model, data, state.base, state.q, state.dq, state.ddq);
    const Eigen::MatrixXd Y = sampler.regressor(state);
    const Eigen::MatrixXd J = sampler.jacobian(state);
    const Eigen::VectorXd lambda =
        J.leftCols<6>().transpose().completeOrthogonalDecomposition().solve(
            Eigen::VectorXd(tau.head<6>()));
    ASSERT_LT((J.leftCols<6>().transpose() * lambda - tau.head<6>()).norm(),
              1e-9 * tau.head<6>().norm());
    const Eigen::VectorXd motor = tau.tail(n) - J.rightCols(n).transpose() * lambda;
    for (std::size_t s = 0; s < 3; ++s) {
      const Eigen::MatrixXd rows = sensorRows(sets[s].set, Y, J);
      const Eigen::VectorXd measured = sensorMeasurements(sets[s].set, motor, J, lambda);
      W[s].conservativeResize(W[s].rows() + rows.rows(), Eigen::NoChange);
      W[s].bottomRows(rows.rows()) = rows;
      y[s].conservativeResize(y[s].size() + measured.size());
      y[s].tail(measured.size()) = measured;
    }
  }
  for (std::size_t s = 0; s < 3; ++s) {
    SCOPED_TRACE(sensorSetName(sets[s].set));
    const Eigen::VectorXd beta = sets[s].base.baseRegressor(W[s]).colPivHouseholderQr().solve(y[s]);
    const Eigen::VectorXd truth = sets[s].base.project(model.standardParameters());
    double worst = 0.0;
    // 1e-9 relative (the bound): the base regressors' condition is ~1e3-1e5 here.
    EXPECT_LT(baseParameterError(beta, truth, &worst), 1e-9);
    EXPECT_LT(worst, 1e-9);
  }
}

TEST(SensorSets, RefuseContactFlagsWithoutContactsAndUnknownNames) {
  const FloatingModel model = test::randomFloating(6, {.num_bodies = 3});
  EXPECT_THROW(floatingStructuralBase(model, {SensorSet::kTorquesAndContactFlags}), InputError);
  FloatingStructuralOptions flight;
  flight.motion = FloatingMotion::kFree;  // in flight nothing holds: no contacts needed
  EXPECT_EQ(floatingStructuralBase(model, {SensorSet::kTorquesAndContactFlags}, flight).size(), 1u);
  EXPECT_THROW(parseFloatingMotion("walking"), InputError);
  EXPECT_EQ(parseSensorSet("torques_contacts"), SensorSet::kTorquesAndContactFlags);
  try {
    parseSensorSet("imu");
    FAIL() << "'imu' was taken for a sensor set";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("`sensors`"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynid
