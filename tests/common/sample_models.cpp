#include "tests/common/sample_models.hpp"

#include <unistd.h>
#include <atomic>
#include <cmath>

#include <Eigen/LU>

#include "core/parameters.hpp"
#include "core/simulate.hpp"
#include "data/io.hpp"
#include "data/puma560.hpp"

namespace dynid::test {

Eigen::VectorXd randomVector(std::mt19937_64& rng, int n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

namespace {
Eigen::Matrix3d randomRotation(std::mt19937_64& rng) {
  const Eigen::VectorXd rpy = randomVector(rng, 3, 3.0);
  return rotationFromRpy(rpy[0], rpy[1], rpy[2]);
}
}  // namespace

Model randomTree(std::uint64_t seed, const RandomTreeOptions& options) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Model model;
  model.name = "random_tree_" + std::to_string(seed);
  model.setGravity(Eigen::Vector3d(0.3, -0.2, -9.81));
  if (options.drives) model.setDriveTerms(DriveTerms{(1u << kDriveTermCount) - 1});  // every term
  for (int i = 0; i < options.num_bodies; ++i) {
    const int parent =
        options.chain ? i - 1 : static_cast<int>(std::floor(unit(rng) * (i + 1))) - 1;
    const double kind = unit(rng);
    const JointType type = options.prismatic && kind < 0.25 ? JointType::kPrismatic
                           : kind < 0.4                     ? JointType::kContinuous
                                                            : JointType::kRevolute;
    Eigen::Vector3d axis = Eigen::Vector3d::Unit(static_cast<int>(unit(rng) * 3) % 3);
    if (options.general_axes && unit(rng) < 0.5) axis = randomVector(rng, 3, 1.0).normalized();
    Pose<double> joint_placement;
    joint_placement.rotation = randomRotation(rng);
    joint_placement.translation = randomVector(rng, 3, 0.5);
    Pose<double> body_placement;
    if (options.body_placements && unit(rng) < 0.5) {
      body_placement.rotation = randomRotation(rng);
      body_placement.translation = randomVector(rng, 3, 0.3);
    }
    // Physically consistent: principal moments with the triangle inequality, rotated.
    Eigen::Matrix<double, 7, 1> paper;
    const double a = 0.02 + 0.2 * unit(rng), b = 0.02 + 0.2 * unit(rng);
    const double c = std::abs(a - b) + (a + b - std::abs(a - b)) * unit(rng);
    paper << 0.5 + 4.5 * unit(rng), randomVector(rng, 3, 0.2), a, b, c;
    RigidInertia<double> inertia = fromStandardVector(paperToStandard(paper));
    const Eigen::Matrix3d rot = randomRotation(rng);
    const Eigen::Matrix3d ic = inertiaAboutCom(inertia);
    inertia.inertia += rot * ic * rot.transpose() - ic;
    DriveParameters<double> drive;
    if (options.drives)  // every term of the table: non-negative ones in [0, 1), others +-0.1
      for (int k = 0; k < kDriveTermCount; ++k)
        drive.term(k) = kDriveTermTable[k].non_negative ? unit(rng) : 0.2 * (unit(rng) - 0.5);
    JointLimits limits;
    if (type == JointType::kRevolute) limits.lower = -2.5, limits.upper = 2.5;
    if (type == JointType::kPrismatic) limits.lower = -0.5, limits.upper = 0.5;
    model.addBody(parent, "body" + std::to_string(i + 1), "joint" + std::to_string(i + 1), type,
                  joint_placement, axis, body_placement, inertia, limits, drive);
  }
  model.finalize();
  return model;
}

Model permutedTree(std::uint64_t seed, bool drives) {
  const Model tree = randomTree(seed, {.num_bodies = 12,
                                       .prismatic = false,
                                       .general_axes = false,
                                       .body_placements = false,
                                       .drives = drives});
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> coin(0, 1);
  // The tree's inertias, drives and limits on a new structure.
  Model model;
  model.setGravity(tree.gravity());
  model.setDriveTerms(tree.driveTerms());
  for (int i = 0; i < tree.numJoints(); ++i) {
    Pose<double> placement;
    placement.rotation.setZero();
    for (int a = 0; a < 3; ++a)
      placement.rotation(a, kAxisPermutations[i % 6][a]) = coin(rng) ? 1.0 : -1.0;
    if (placement.rotation.determinant() < 0) placement.rotation.row(0) *= -1.0;  // a rotation
    placement.translation = randomVector(rng, 3, 0.5);
    model.addBody(i / 2 - 1, tree.link_names[i], tree.joint_names[i], JointType::kRevolute,
                  placement, Eigen::Vector3d::UnitZ(), tree.body_placements()[i],
                  tree.inertias()[i], tree.limits[i], tree.drives()[i]);
  }
  model.finalize();
  return model;
}

Model Planar2R::model() const {
  Model model;
  model.name = "planar_2r";
  model.setGravity(Eigen::Vector3d(0.0, -g, 0.0));
  auto link = [](double m, double lc, double izz) {
    Eigen::Matrix<double, 7, 1> paper;
    paper << m, lc, 0.0, 0.0, 0.01, 0.01 + izz, izz;  // Ixx, Iyy arbitrary: out of plane
    return fromStandardVector(paperToStandard(paper));
  };
  Pose<double> elbow;
  elbow.translation = Eigen::Vector3d(l1, 0.0, 0.0);
  model.addBody(-1, "link1", "shoulder", JointType::kContinuous, Pose<double>(),
                Eigen::Vector3d::UnitZ(), Pose<double>(), link(m1, lc1, I1));
  model.addBody(0, "link2", "elbow", JointType::kContinuous, elbow, Eigen::Vector3d::UnitZ(),
                Pose<double>(), link(m2, lc2, I2));
  model.finalize();
  return model;
}

Eigen::Matrix2d Planar2R::massMatrix(const Eigen::Vector2d& q) const {
  const double c2 = std::cos(q[1]);
  const double d11 = m1 * lc1 * lc1 + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * c2) + I1 + I2;
  const double d12 = m2 * (lc2 * lc2 + l1 * lc2 * c2) + I2;
  const double d22 = m2 * lc2 * lc2 + I2;
  Eigen::Matrix2d m;
  m << d11, d12, d12, d22;
  return m;
}

Eigen::Vector2d Planar2R::coriolis(const Eigen::Vector2d& q, const Eigen::Vector2d& dq) const {
  const double h = -m2 * l1 * lc2 * std::sin(q[1]);
  return {2 * h * dq[0] * dq[1] + h * dq[1] * dq[1], -h * dq[0] * dq[0]};
}

Eigen::Vector2d Planar2R::gravity(const Eigen::Vector2d& q) const {
  const double c1 = std::cos(q[0]), c12 = std::cos(q[0] + q[1]);
  return {(m1 * lc1 + m2 * l1) * g * c1 + m2 * lc2 * g * c12, m2 * lc2 * g * c12};
}

TrackingController pumaSinusoidController(const Model& model, double amplitude, double f_low,
                                          double f_high) {
  SinusoidalReference r;
  r.q0 = puma560Pose("qn");
  r.amplitude = Eigen::VectorXd::Constant(6, amplitude);
  r.frequency = Eigen::VectorXd::LinSpaced(6, f_low, f_high);
  r.phase = Eigen::VectorXd::Zero(6);
  return TrackingController(model, r, defaultGains(model, r.q0), Eigen::VectorXd::Constant(6, 1e9));
}

Trajectory pumaSinusoidTrajectory(const Model& model, double duration, double amplitude,
                                  double f_low, double f_high) {
  TrackingController controller = pumaSinusoidController(model, amplitude, f_low, f_high);
  SimulationOptions options;
  options.duration = duration;
  return simulate(model, controller, options);
}

Trajectory pumaSearchTrajectory(double duration) {
  return pumaSinusoidTrajectory(makePuma560(), duration, 0.5, 0.2, 0.6);
}

std::string tempPath(const std::string& name) {
  static std::atomic<int> counter{0};
  return std::string(DYNID_TEST_TMP) + "/" + std::to_string(::getpid()) + "_" +
         std::to_string(counter++) + "_" + name;
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = tempPath(name);
  writeFileAtomically(path, text);
  return path;
}

}  // namespace dynid::test
