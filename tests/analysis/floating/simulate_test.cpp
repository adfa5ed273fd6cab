// Simulated floating robots identified per sensor set (the acceptance): the example
// quadruped and humanoid (examples/floating/) recover every determined combination from
// noise-free data to 1e-9, and with noise their generalized least-squares intervals are
// calibrated (z RMS within 0.9-1.1).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/identify.hpp"
#include "analysis/floating/simulate.hpp"
#include "core/errors.hpp"
#include "tests/common/floating_datasets.hpp"
#include "tests/common/floating_models.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

using test::FloatingExample;
using Robot = FloatingExample;
const Robot& kAnymal = test::kAnymalExample;
const Robot& kRomeo = test::kRomeoExample;

FloatingModel load(const Robot& robot) {
  FloatingModel model = test::loadExample(robot);
  model.setDriveTerms(DriveTerms::of({DriveTerm::kViscous, DriveTerm::kCoulomb}));
  // Friction the data can see: Fv 0.5 N m s/rad, Fc 1 N m on every joint.
  Eigen::VectorXd theta = model.standardParameters();
  const ParameterLayout layout = model.limbs().parameterLayout();
  for (int i = 0; i < model.numJoints(); ++i) {
    theta[FloatingModel::limbColumn(layout.driveIndex(i, DriveTerm::kViscous))] = 0.5;
    theta[FloatingModel::limbColumn(layout.driveIndex(i, DriveTerm::kCoulomb))] = 1.0;
  }
  model.setStandardParameters(theta);
  return model;
}

std::vector<SensorSetBase> structural(const FloatingModel& model, const Robot& robot,
                                      FloatingMotion motion) {
  FloatingIdentifiabilityRequest request;
  request.contacts = robot.contacts;
  request.motion = motion;
  return floatingIdentifiabilityRun(model, request).sets;
}

/// Every set's base parameters from noise-free measurements of the robot in the motion (the
/// contacts' forces within cones of mu `friction_cone` when it is not 0) to 1e-9.
void expectRecovery(const Robot& robot, FloatingMotion motion, double friction_cone) {
  const FloatingModel model = load(robot);
  FloatingSimulationOptions options;
  options.samples = &robot == &kAnymal ? 150 : 100;
  options.seed = 11;
  options.motion = motion;
  options.contacts = contactsOf(model, robot.contacts);
  options.friction_cone = friction_cone;
  const FloatingSimulation sim = simulateFloating(model, options);
  const Eigen::VectorXd theta = model.standardParameters();
  for (const SensorSetBase& s : structural(model, robot, motion)) {
    SCOPED_TRACE(std::string(robot.path) + " " + sensorSetName(s.set));
    const FloatingFit fit =
        fitFloating(s.base, s.set, sim.samples, {.generalized = false, .torque_variance = {}});
    // Each combination's error in the units of its effect on the measurements: |error_j| times
    // its base regressor column's norm, relative to the measurements' norm (the rank rule's
    // unit-norm columns; a finger's inertia moves the torques a millionth of what the trunk's
    // mass does and is known to that share of them): the 1e-9.
    Eigen::MatrixXd W(0, s.base.numBase());
    Eigen::VectorXd y(0);
    for (const FloatingMeasurement& m : sim.samples) {
      const Eigen::MatrixXd rows = s.base.baseRegressor(sensorRows(s.set, m.Y, m.J));
      const Eigen::VectorXd measured = sensorMeasurements(s.set, m.tau, m.J, m.forces);
      W.conservativeResize(W.rows() + rows.rows(), Eigen::NoChange);
      W.bottomRows(rows.rows()) = rows;
      y.conservativeResize(y.size() + measured.size());
      y.tail(measured.size()) = measured;
    }
    const Eigen::VectorXd effect =
        (fit.beta - s.base.project(theta)).cwiseAbs().cwiseProduct(W.colwise().norm().transpose()) /
        y.norm();
    EXPECT_LT(effect.maxCoeff(), 1e-9);
    // And the whole vector, relative to its norm.
    EXPECT_LT((fit.beta - s.base.project(theta)).norm() / s.base.project(theta).norm(), 1e-9);
  }
}

class NoiseFree : public ::testing::TestWithParam<std::tuple<int, FloatingMotion>> {};

TEST_P(NoiseFree, EverySetRecoversItsCombinations) {
  const auto [which, motion] = GetParam();
  expectRecovery(which == 0 ? kAnymal : kRomeo, motion, 0.0);
}

INSTANTIATE_TEST_SUITE_P(
    Robots, NoiseFree,
    ::testing::Combine(::testing::Values(0, 1),
                       ::testing::Values(FloatingMotion::kHolding, FloatingMotion::kSuspended,
                                         FloatingMotion::kFree, FloatingMotion::kCarried)));

/// On the ground, friction cones of mu 0.6: each holding foot of ANYmal pushes within its cone in
/// the world's axes, the cones bind (the least-norm forces would leave them), states the cones
/// cannot hold are drawn again, and every set still recovers its combinations.
TEST(FrictionCones, EveryFootPushesWithinItsConeAndTheSetsStillRecover) {
  const double mu = 0.6;
  const FloatingModel model = load(kAnymal);
  FloatingSimulationOptions options;
  options.samples = 150;
  options.seed = 11;
  options.contacts = contactsOf(model, kAnymal.contacts);
  options.friction_cone = mu;
  int drawn = 0;
  const FloatingDataset data = simulateFloatingDataset(model, options, &drawn);
  EXPECT_GT(drawn, options.samples);  // random holding states: some need a pull or a slide
  FloatingData work(model);
  const Eigen::Vector3d up = -model.gravity().normalized();
  int binding = 0, holding = 0;
  for (int k = 0; k < options.samples; ++k) {
    const Eigen::Vector4d q = data.orientation.col(k);
    const Eigen::Matrix3d base = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    double scale = 0.0;  // the sample's total contact force, the tolerances' unit
    for (const FloatingDataset::Wrench& w : data.wrenches) scale += w.values.col(k).norm();
    for (std::size_t c = 0; c < options.contacts.size(); ++c) {
      if (!data.flags[c].holding[static_cast<std::size_t>(k)]) {
        EXPECT_EQ(data.wrenches[c].values.col(k).norm(), 0.0);
        continue;
      }
      ++holding;
      const Eigen::Matrix3d axes =
          base * contactPose(model, work, options.contacts[c], data.q.col(k)).rotation;
      const Eigen::Vector3d f = axes * data.wrenches[c].values.col(k);
      const double normal = up.dot(f), tangent = (f - normal * up).norm();
      // The solver's tolerance: 1e-9 of the wrench it carries.
      EXPECT_GE(normal, -1e-9 * scale);
      EXPECT_LE(tangent, mu * normal + 1e-9 * scale);
      if (tangent > mu * normal - 1e-6 * scale) ++binding;
    }
  }
  EXPECT_GT(binding, holding / 20) << binding << " of " << holding << " at the cone's edge";
  expectRecovery(kAnymal, FloatingMotion::kHolding, mu);
  expectRecovery(kRomeo, FloatingMotion::kHolding, mu);
}

/// Expects every holding sole of `data` to push, its tangential force within the cone of mu and
/// its centre of pressure in the convex polygon `corners` (counter-clockwise); returns how many
/// centres of pressure lie at the polygon's edge, and counts the holding soles in `holding`.
int expectWithinSoles(const FloatingDataset& data, const FloatingSimulationOptions& options,
                      const std::vector<Eigen::Vector2d>& corners, int& holding) {
  int at_edge = 0;
  holding = 0;
  for (int k = 0; k < data.numSamples(); ++k) {
    double scale = 0.0;  // the sample's total contact wrench, the tolerances' unit
    for (const FloatingDataset::Wrench& w : data.wrenches) scale += w.values.col(k).norm();
    for (std::size_t c = 0; c < options.contacts.size(); ++c) {
      if (!data.flags[c].holding[static_cast<std::size_t>(k)]) continue;
      ++holding;
      const Eigen::VectorXd w = data.wrenches[c].values.col(k);  // (n, f) in the sole's axes
      const double fz = w[5];
      EXPECT_GE(fz, -1e-9 * scale);
      EXPECT_LE(w.segment<2>(3).norm(), options.friction_cone * fz + 1e-9 * scale);
      // The centre of pressure p = (-n_y, n_x) / f_z, written without the division: on the inner
      // side of every edge a -> b, (b - a) x (p - a) >= 0, times f_z.
      const Eigen::Vector2d pf(-w[1], w[0]);
      double closest = std::numeric_limits<double>::infinity();
      for (std::size_t e = 0; e < corners.size(); ++e) {
        const Eigen::Vector2d a = corners[e], b = corners[(e + 1) % corners.size()];
        const Eigen::Vector2d d = pf - fz * a, edge = b - a;
        const double inside = (edge.x() * d.y() - edge.y() * d.x()) / edge.norm();
        EXPECT_GE(inside, -1e-9 * scale) << "sample " << k << ", edge " << e;
        closest = std::min(closest, inside);
      }
      if (closest < 1e-6 * scale) ++at_edge;
    }
  }
  return at_edge;
}

/// The data are the model's own in `set`: every sample's rows times the model's parameters give
/// what was measured, to round-off (1e-9 of the measurements).
void expectTheModelsOwn(const FloatingModel& model, const FloatingDataset& data,
                        const std::vector<Contact>& contacts, SensorSet set) {
  SCOPED_TRACE(sensorSetName(set));
  const Eigen::VectorXd theta = model.standardParameters();
  FloatingData workspace(model);
  for (int k = 0; k < data.numSamples(); ++k) {
    const FloatingMeasurement m = floatingMeasurement(model, workspace, data, contacts, set, k);
    const Eigen::VectorXd measured = sensorMeasurements(set, m.tau, m.J, m.forces);
    const Eigen::VectorXd rows = sensorRows(set, m.Y, m.J) * theta;
    EXPECT_LT((rows - measured).norm(), 1e-9 * measured.norm()) << "sample " << k;
  }
}

/// Romeo standing on soles of 0.2 x 0.1 m (mu 0.8): every holding sole's wrench, in its own axes,
/// is that of forces at its corners within their cones about its normal, so its normal force
/// pushes, its centre of pressure lies in the rectangle and its tangential force within the cone;
/// some centres of pressure reach the rectangle's edge (the free moment would leave it), and the
/// soles carry exactly the wrench the motion needs: every set's rows hold with the model's own
/// parameters to round-off. (No estimate: the states soles can carry are mostly double support, a
/// closed chain through both legs, which excites too little for every combination.)
TEST(FrictionCones, ASolesCentreOfPressureStaysInIt) {
  const FloatingModel model = load(kRomeo);
  FloatingSimulationOptions options;
  options.samples = 45;  // 3 % of random states stand on such soles: about 1500 draws
  options.seed = 5;
  options.contacts = contactsOf(model, kRomeo.contacts);
  options.friction_cone = 0.8;
  options.sole = rectangularSole(0.2, 0.1);
  int drawn = 0, holding = 0;
  const FloatingDataset data = simulateFloatingDataset(model, options, &drawn);
  const int at_edge = expectWithinSoles(data, options, options.sole, holding);
  EXPECT_GT(at_edge, 0) << "of " << holding << " holding soles";
  EXPECT_GE(drawn, options.samples);
  // Double support excites little: 45 states on soles determine 201 of the wrenches' 227
  // combinations and 287 of torques_contacts' 289 (measured), so the model's own parameters check
  // the data, in every set.
  for (SensorSet set : kSensorSets) expectTheModelsOwn(model, data, options.contacts, set);
}

/// A sole that is not a rectangle centred at its frame: a foot's outline, five corners, the ankle
/// frame 5 cm from its heel (counter-clockwise). Every holding sole's centre of pressure stays in
/// that pentagon, some at its edge, none beyond it (behind the ankle by more than the heel's 5 cm,
/// in particular), and the data fit to round-off.
TEST(FrictionCones, ASolePolygonOffTheFrameHoldsItsCentreOfPressure) {
  const FloatingModel model = load(kRomeo);
  FloatingSimulationOptions options;
  options.samples = 12;  // 3 % of random states stand: about 400 draws
  options.seed = 3;
  options.contacts = contactsOf(model, kRomeo.contacts);
  options.friction_cone = 0.8;
  options.sole = {{-0.05, -0.05}, {0.15, -0.05}, {0.19, 0.0}, {0.15, 0.05}, {-0.05, 0.05}};
  int holding = 0;
  const FloatingDataset data = simulateFloatingDataset(model, options);
  EXPECT_GT(expectWithinSoles(data, options, options.sole, holding), 0)
      << "of " << holding << " holding soles";
  // 12 states in double support determine 284 of the 289 combinations (the rank rule refuses
  // identify: measured), so the model's own parameters check the data instead.
  expectTheModelsOwn(model, data, options.contacts, SensorSet::kTorquesAndWrenches);
}

/// Runs the simulation and expects an InputError whose message holds every fragment.
void expectRefused(const FloatingModel& model, const FloatingSimulationOptions& options,
                   std::initializer_list<const char*> fragments) {
  try {
    simulateFloating(model, options);
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    for (const char* fragment : fragments)
      EXPECT_TRUE(test::contains(e.what(), fragment)) << e.what();
  }
}

TEST(FrictionCones, AreRefusedWhereNoContactStandsOnTheGround) {
  const FloatingModel model = load(kAnymal);
  FloatingSimulationOptions options;
  options.contacts = contactsOf(model, kAnymal.contacts);
  options.friction_cone = -0.1;
  EXPECT_THROW(simulateFloating(model, options), InputError);
  options.friction_cone = 0.5;
  options.motion = FloatingMotion::kSuspended;
  expectRefused(model, options, {"`friction_cone`", "suspended"});
  // So narrow a cone that no random state of a quadruped is held.
  options.motion = FloatingMotion::kHolding;
  options.friction_cone = 1e-6;
  expectRefused(model, options, {"`friction_cone`", "200 random states"});
}

TEST(FrictionCones, ASoleIsRefusedWhereItCannotStand) {
  const FloatingModel model = load(kRomeo);
  FloatingSimulationOptions options;
  options.contacts = contactsOf(model, kRomeo.contacts);
  options.sole = rectangularSole(0.2, 0.1);
  expectRefused(model, options, {"`sole`", "`friction_cone`"});
  options.friction_cone = 0.8;
  for (const auto& [length, width] : {std::pair{0.2, 0.0}, {0.2, -0.1}, {NAN, 0.1}}) {
    try {
      rectangularSole(length, width);
      ADD_FAILURE() << length << " x " << width << " not refused";
    } catch (const InputError& e) {
      EXPECT_TRUE(test::contains(e.what(), "`sole`")) << e.what();
      EXPECT_TRUE(test::contains(e.what(), "both positive")) << e.what();
    }
  }
  options.sole = {{0.0, 0.0}, {0.1, 0.0}};
  expectRefused(model, options, {"`sole`", "three or more corners", "not 2"});
  options.sole = {{0.0, 0.0}, {0.1, 0.05}, {0.2, 0.1}, {-0.1, -0.05}};
  expectRefused(model, options, {"`sole`", "not all on one line", "on a line"});
  options.sole.assign(33, Eigen::Vector2d(0.1, 0.0));
  for (int k = 0; k < 33; ++k)
    options.sole[static_cast<std::size_t>(k)] =
        0.1 * Eigen::Vector2d(std::cos(0.19 * k), std::sin(0.19 * k));
  expectRefused(model, options, {"`sole`", "33 corners, more than 32"});
  options.sole = {{0.0, 0.0}, {0.1, 0.0}, {0.0, INFINITY}};
  expectRefused(model, options, {"`sole`", "corner 3 is not finite"});
  const FloatingModel anymal = load(kAnymal);  // point feet
  options.contacts = contactsOf(anymal, kAnymal.contacts);
  options.sole = rectangularSole(0.2, 0.1);
  expectRefused(anymal, options, {"`sole`", "no frame contact"});
}

/// A given motion (another dataset's time, base and joints, its flags saying what holds):
/// noise-free, the torques, wrenches and flags of the dataset it came from; within cones too
/// narrow for some of its states, those keep their least-norm forces and are named.
TEST(GivenMotion, ReproducesTheDatasetItCameFrom) {
  const FloatingModel model = load(kAnymal);
  FloatingSimulationOptions options;
  options.samples = 40;
  options.seed = 3;
  options.contacts = contactsOf(model, kAnymal.contacts);
  const FloatingDataset original = simulateFloatingDataset(model, options);
  FloatingSimulationOptions along;  // its contacts: the dataset's flagged frames
  along.motion_from = std::make_shared<const FloatingDataset>(original);
  std::vector<int> outside, unsupported;
  const FloatingDataset again =
      simulateFloatingDataset(model, along, nullptr, &outside, &unsupported);
  EXPECT_TRUE(outside.empty());
  EXPECT_TRUE(unsupported.empty());
  ASSERT_EQ(again.numSamples(), original.numSamples());
  EXPECT_EQ(again.time, original.time);
  EXPECT_LT((again.tau - original.tau).norm(), 1e-9 * original.tau.norm());
  ASSERT_EQ(again.wrenches.size(), original.wrenches.size());
  for (std::size_t c = 0; c < again.wrenches.size(); ++c) {
    EXPECT_EQ(again.wrenches[c].frame, original.wrenches[c].frame);
    const Eigen::MatrixXd& w = original.wrenches[c].values;
    EXPECT_LE((again.wrenches[c].values - w).norm(), 1e-9 * w.norm());
    EXPECT_EQ(again.flags[c].holding, original.flags[c].holding);
  }
  // Random states need a pull or a slide at mu 0.3 now and then: kept, with the least-norm forces.
  along.friction_cone = 0.3;
  const FloatingDataset coned =
      simulateFloatingDataset(model, along, nullptr, &outside, &unsupported);
  EXPECT_FALSE(outside.empty());
  EXPECT_LT(outside.size(), 40u);
  EXPECT_TRUE(unsupported.empty());
  for (int k : outside)
    for (std::size_t c = 0; c < coned.wrenches.size(); ++c)
      EXPECT_LE((coned.wrenches[c].values.col(k) - original.wrenches[c].values.col(k)).norm(),
                1e-9 * original.wrenches[c].values.col(k).norm() + 1e-12);
  std::vector<std::string> said = givenMotionWarnings(coned, outside, unsupported);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_TRUE(test::contains(
      said[0], std::to_string(outside.size()) + " of the motion's samples (from t = "))
      << said[0];
  // One point foot cannot carry a moment about itself: where it alone holds, the wrench is
  // not carried, and every such sample is named.
  FloatingDataset one_foot = original;
  for (std::size_t c = 1; c < one_foot.flags.size(); ++c)
    std::fill(one_foot.flags[c].holding.begin(), one_foot.flags[c].holding.end(), 0);
  std::fill(one_foot.flags[0].holding.begin(), one_foot.flags[0].holding.end(), 1);
  along.friction_cone = 0.0;
  along.motion_from = std::make_shared<const FloatingDataset>(one_foot);
  const FloatingDataset lone =
      simulateFloatingDataset(model, along, nullptr, &outside, &unsupported);
  EXPECT_TRUE(outside.empty());
  EXPECT_EQ(unsupported.size(), 40u);
  said = givenMotionWarnings(lone, outside, unsupported);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_TRUE(test::contains(said[0], "40 of the motion's samples (from t = 0 s) need a wrench"))
      << said[0];
}

TEST(GivenMotion, IsRefusedWhereItCannotBeSimulated) {
  const FloatingModel model = load(kAnymal);
  FloatingSimulationOptions options;
  options.samples = 5;
  options.contacts = contactsOf(model, kAnymal.contacts);
  FloatingSimulationOptions along;
  along.motion_from =
      std::make_shared<const FloatingDataset>(simulateFloatingDataset(model, options));
  along.motion = FloatingMotion::kFree;
  expectRefused(model, along, {"`motion_from`", "not free"});
  along.motion = FloatingMotion::kHolding;
  along.contacts = contactsOf(model, {model.baseName() + ":frame"});
  expectRefused(model, along, {"`motion_from`", "no flag for the contact at"});
  along.contacts.clear();
  FloatingDataset unflagged = *along.motion_from;
  unflagged.flags.clear();
  along.motion_from = std::make_shared<const FloatingDataset>(unflagged);
  expectRefused(model, along, {"`motion_from`", "no contact flag"});
  along.trajectory = FourierSeries();
  along.motion = FloatingMotion::kSuspended;
  expectRefused(model, along, {"`motion_from` and `trajectory`"});
}

/// z = (beta_hat - beta) / sd over every base parameter and 8 seeds: its RMS is 1 when the
/// intervals are calibrated; on the ground, and on a base its support carries.
class Noisy : public ::testing::TestWithParam<FloatingMotion> {};

TEST_P(Noisy, GeneralizedLeastSquaresIntervalsAreCalibrated) {
  const FloatingModel model = load(kAnymal);
  const Eigen::VectorXd theta = model.standardParameters();
  const FloatingMotion motion = GetParam();
  const std::vector<SensorSetBase> sets = structural(model, kAnymal, motion);
  for (const SensorSetBase& s : sets) {
    SCOPED_TRACE(sensorSetName(s.set));
    const Eigen::VectorXd truth = s.base.project(theta);
    double sum = 0.0;
    int count = 0;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      FloatingSimulationOptions options;
      options.samples = 300;
      options.seed = seed;
      options.motion = motion;
      options.contacts = contactsOf(model, kAnymal.contacts);
      options.torque_noise = 0.5;  // N m: a current-sensing joint's level
      options.force_noise = 2.0;   // N: a foot force sensor's
      options.moment_noise = 0.5;  // N m: the carried base's support sensor's moments
      const FloatingSimulation sim = simulateFloating(model, options);
      const FloatingFit fit =
          fitFloating(s.base, s.set, sim.samples, {.torque_variance = sim.torque_variance});
      // The whitened residuals' scale is 1 when the noise model is the simulation's.
      EXPECT_NEAR(fit.residual_scale, 1.0, 0.1);
      const Eigen::VectorXd z = (fit.beta - truth).cwiseQuotient(fit.sd);
      sum += z.squaredNorm();
      count += static_cast<int>(z.size());
    }
    const double rms = std::sqrt(sum / count);
    // 8 x ~100 values: the RMS of a standard normal sample that size is within 0.05 of 1 (3 sd).
    EXPECT_GT(rms, 0.9);
    EXPECT_LT(rms, 1.1);
  }
}

INSTANTIATE_TEST_SUITE_P(Motions, Noisy,
                         ::testing::Values(FloatingMotion::kHolding, FloatingMotion::kCarried));

/// A designed motion (a Fourier series, as `dynid excite` makes for the robot with its base
/// fixed) simulated on the suspended robot: the design's states at its times, the base held still
/// in one orientation; its noise-free data give torques_contacts exactly, and the wrench sets all
/// but the whole body's first moment along gravity, which a base that never tilts cannot show.
TEST(DesignedMotion, IsSimulatedOnTheSuspendedRobotAndSaysWhatItCannotShow) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FourierSeries design = test::randomDesign(model, 10.0, 0.4, 3);
  FloatingSimulationOptions options;
  options.samples = 400;
  options.motion = FloatingMotion::kSuspended;
  options.trajectory = design;
  const FloatingDataset data = simulateFloatingDataset(model, options);
  Eigen::VectorXd q, dq, ddq;
  for (int k = 0; k < data.numSamples(); k += 57) {
    EXPECT_DOUBLE_EQ(data.time[k], 10.0 * k / 400.0);
    evaluateReference(design, data.time[k], q, dq, ddq);
    EXPECT_EQ(Eigen::VectorXd(data.q.col(k)), q);
    EXPECT_EQ(Eigen::VectorXd(data.ddq.col(k)), ddq);
    EXPECT_EQ(data.twist.col(k).norm() + data.acceleration.col(k).norm(), 0.0);
    EXPECT_EQ(data.orientation.col(k), Eigen::Vector4d(1, 0, 0, 0));
  }
  FloatingIdentifyRequest request;
  request.method = FloatingMethod::kOls;
  const FloatingIdentifyOutcome out = floatingIdentifyRun(model, request, data);
  ASSERT_EQ(out.sets.size(), 3u);
  EXPECT_TRUE(test::contains(out.sets[0].refused, "determine 79 of the 80")) << out.sets[0].refused;
  ASSERT_TRUE(out.sets[2].refused.empty()) << out.sets[2].refused;
  EXPECT_LT(out.sets[2].model_error_percent, 1e-7);  // 1e-9 relative, in percent
  options.motion = FloatingMotion::kHolding;
  options.contacts = contactsOf(model, test::kAnymalExample.contacts);
  try {
    simulateFloatingDataset(model, options);
    FAIL() << "a design on a standing robot was simulated";
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(),
                               "`trajectory`: a designed motion is simulated on a "
                               "suspended robot"))
        << e.what();
  }
}

/// The same design on a stand tilted between recordings: each orientation's run after the one
/// before it by the period and a 1 s gap, the base held in that orientation; the three
/// orientations show what one cannot, and every set recovers its combinations to 1e-9.
TEST(DesignedMotion, OnATiltingStandDeterminesWhatOneOrientationCannot) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  FloatingSimulationOptions options;
  options.samples = 200;
  options.motion = FloatingMotion::kSuspended;
  options.trajectory = test::randomDesign(model, 10.0, 0.4, 3);
  options.stand_tilts = {{0.0, 0.0}, {0.4, 0.0}, {0.0, 0.4}};
  const FloatingDataset data = simulateFloatingDataset(model, options);
  ASSERT_EQ(data.numSamples(), 600);
  EXPECT_DOUBLE_EQ(data.time[199], 10.0 * 199 / 200.0);
  EXPECT_DOUBLE_EQ(data.time[200], 11.0);  // the second run: the period and 1 s later
  EXPECT_DOUBLE_EQ(data.time[450], 22.0 + 10.0 * 50 / 200.0);
  // The second run's orientation: 0.4 rad of roll, (cos 0.2, sin 0.2, 0, 0); its joints the
  // first run's.
  EXPECT_NEAR(
      (data.orientation.col(300) - Eigen::Vector4d(std::cos(0.2), std::sin(0.2), 0, 0)).norm(), 0.0,
      1e-15);
  EXPECT_EQ(Eigen::VectorXd(data.q.col(300)), Eigen::VectorXd(data.q.col(100)));
  FloatingIdentifyRequest request;
  request.method = FloatingMethod::kOls;
  const FloatingIdentifyOutcome out = floatingIdentifyRun(model, request, data);
  ASSERT_EQ(out.sets.size(), 3u);
  for (const FloatingSetEstimate& s : out.sets) {
    ASSERT_TRUE(s.refused.empty()) << sensorSetName(s.base.set) << ": " << s.refused;
    EXPECT_LT(s.model_error_percent, 1e-7) << sensorSetName(s.base.set);  // 1e-9, in percent
  }
  options.stand_tilts.assign(17, Eigen::Vector2d::Zero());
  EXPECT_THROW(simulateFloatingDataset(model, options), InputError);
  options.stand_tilts.resize(16);  // at most 16 of 1e6 samples each: no int overflows
  options.samples = kMaxFloatingSamples + 1;
  EXPECT_THROW(simulateFloatingDataset(model, options), InputError);
  options.samples = 200;
  options.stand_tilts = {{0.1, std::nan("")}};
  EXPECT_THROW(simulateFloatingDataset(model, options), InputError);
  options.trajectory.reset();
  options.stand_tilts = {{0.1, 0.0}};
  try {
    simulateFloatingDataset(model, options);
    ADD_FAILURE() << "tilts without a design were simulated";
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(), "`stand_tilts`")) << e.what();
  }
}

}  // namespace
}  // namespace dynid
