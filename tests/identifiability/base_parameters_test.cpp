#include "identifiability/base_parameters.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include <Eigen/Geometry>

#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/dh.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "data/urdf.hpp"
#include "identifiability/observation.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

// Joint and link names of the test chains (as constants: GCC 12 warns falsely, -Wrestrict, on
// strings built in these loops).
const std::string kNames[7][2] = {{"j1", "l1"}, {"j2", "l2"}, {"j3", "l3"}, {"j4", "l4"},
                                  {"j5", "l5"}, {"j6", "l6"}, {"j7", "l7"}};

BaseParameters structural(const Model& model, int samples = 150, std::uint64_t seed = 1) {
  const ParameterLayout layout = model.parameterLayout();
  return computeBaseParameters(observationFromRandomStates(model, samples, seed).W,
                               standardParameterNames(layout), 0.0,
                               defaultPreference(layout.num_links, layout.perLink()));
}

std::vector<std::string> expressions(const BaseParameters& base) {
  std::vector<std::string> out;
  for (int j = 0; j < base.numBase(); ++j) out.push_back(base.expression(j));
  return out;
}

TEST(BaseParameters, PlanarTwoLinkMatchesTheTextbook) {
  // Gravity in the plane: mx1 + l1 m2, my1, Izz1 + l1^2 m2, mx2, my2, Izz2 (l1 = 0.7).
  test::Planar2R arm;
  const BaseParameters with_gravity = structural(arm.model());
  EXPECT_EQ(
      expressions(with_gravity),
      (std::vector<std::string>{"mx1 + 0.7*m2", "my1", "Izz1 + 0.49*m2", "mx2", "my2", "Izz2"}));
  EXPECT_GT(with_gravity.rankGap(), 1e10);
  // Without gravity the first moments of link 1 no longer act: 4 base parameters.
  arm.g = 0.0;
  const BaseParameters no_gravity = structural(arm.model());
  EXPECT_EQ(expressions(no_gravity),
            (std::vector<std::string>{"Izz1 + 0.49*m2", "mx2", "my2", "Izz2"}));
  EXPECT_EQ(no_gravity.baseName(0), "Izz1R");
  EXPECT_EQ(no_gravity.baseName(1), "mx2");
}

TEST(BaseParameters, BaseRegressorReproducesTheFullOneForAnyTheta) {
  std::mt19937_64 rng(5);
  for (int seed = 0; seed < 4; ++seed) {
    const Model model = seed == 0 ? makePuma560(true) : test::randomTree(seed, {.drives = true});
    const BaseParameters base = structural(model);
    // A fresh observation (other states than the ones the base was computed from).
    const Observation check = observationFromRandomStates(model, 50, 99);
    const Eigen::MatrixXd W1 = base.baseRegressor(check.W);
    for (int trial = 0; trial < 3; ++trial) {
      const Eigen::VectorXd theta = test::randomVector(rng, base.numStandard(), 1.0);
      const Eigen::VectorXd full = check.W * theta;
      // Round-off of K's least-squares fit, relative to the torque scale.
      EXPECT_LT((W1 * base.project(theta) - full).norm(), 1e-9 * (1 + full.norm())) << seed;
    }
    // The null space is annihilated by W, and standardFromBase keeps beta.
    EXPECT_LT((check.W * base.nullSpace()).cwiseAbs().maxCoeff(),
              1e-8 * check.W.cwiseAbs().maxCoeff());
    const Eigen::VectorXd beta = test::randomVector(rng, base.numBase(), 1.0);
    const Eigen::VectorXd prior = test::randomVector(rng, base.numStandard(), 1.0);
    const Eigen::VectorXd theta = base.standardFromBase(beta, prior);
    EXPECT_LT((base.project(theta) - beta).norm(), 1e-12 * (1 + beta.norm()));
    for (int k : base.dependent) EXPECT_EQ(theta[k], prior[k]);
  }
}

TEST(BaseParameters, PumaStructuralCounts) {
  // Rigid: the PUMA's 36 base parameters; link 1's 9 parameters other than its inertia about the
  // joint-1 axis never act. With drives: + Ia3..Ia6 (Ia1 and Ia2 regroup with the inertias about
  // their axes) + 18 friction parameters = 58.
  const BaseParameters rigid = structural(makePuma560(false));
  EXPECT_EQ(rigid.numBase(), 36);
  EXPECT_EQ(rigid.zero_columns.size(), 9u);
  EXPECT_GT(rigid.rankGap(), 1e8);
  const BaseParameters driven = structural(makePuma560(true));
  EXPECT_EQ(driven.numBase(), 58);
  const std::vector<std::string> exprs = expressions(driven);
  EXPECT_NE(std::find(exprs.begin(), exprs.end(), "Ixx6 - Iyy6"), exprs.end());
  EXPECT_NE(std::find(exprs.begin(), exprs.end(), "Ia3"), exprs.end());
  EXPECT_EQ(std::find(exprs.begin(), exprs.end(), "Ia2"), exprs.end());
  // The same structure from another seed.
  EXPECT_EQ(structural(makePuma560(true), 150, 7).independent, driven.independent);
}

/// A DH chain with generic link parameters (seeded): random masses, centres of mass and positive
/// definite inertias, so that no parameter vanishes by accident.
DhModel genericDh(const std::string& name, DhConvention convention, const std::vector<double>& a,
                  const std::vector<double>& d, const std::vector<double>& alpha) {
  std::mt19937_64 rng(42);
  DhModel dh;
  dh.name = name;
  dh.convention = convention;
  for (std::size_t i = 0; i < a.size(); ++i) {
    DhRow r;
    r.joint_name = kNames[i][0];
    r.link_name = kNames[i][1];
    r.a = a[i], r.d = d[i], r.alpha = alpha[i];
    const Eigen::Vector3d com = test::randomVector(rng, 3, 0.1);
    const Eigen::Matrix3d m = test::randomVector(rng, 9, 0.1).reshaped(3, 3);
    r.inertia = inertiaFromCom(1.0 + std::abs(com.x()) * 10, com,
                               m * m.transpose() + 0.01 * Eigen::Matrix3d::Identity());
    dh.rows.push_back(r);
  }
  return dh;
}

/// The same robot through a URDF: its joint rotations written as rpy and read back with
/// trigonometric round-off (cos(pi/2) = 6e-17), as most real URDFs carry.
Model throughUrdf(const Model& model) { return parseUrdf(modelToUrdf(model), "x.urdf", {}); }

TEST(BaseParameters, RealKinematicsGiveTheSameRankFromDhAndFromUrdf) {
  constexpr double h = 1.5707963267948966;
  struct Case {
    const char* name;
    Model dh;
    int base;
  };
  const std::vector<Case> cases = {
      {"puma560", makePuma560(false), 36},
      {"panda", makePanda(false), 43},
      {"kuka_lwr4",
       modelFromDh(genericDh("kuka_lwr4", DhConvention::kStandard, {0, 0, 0, 0, 0, 0, 0},
                             {0.3105, 0, 0.4, 0, 0.39, 0, 0.078}, {h, -h, -h, h, h, -h, 0})),
       43},
      {"ur5",
       modelFromDh(genericDh("ur5", DhConvention::kStandard, {0, -0.425, -0.39225, 0, 0, 0},
                             {0.089159, 0, 0, 0.10915, 0.09465, 0.0823}, {h, 0, 0, h, -h, 0})),
       36}};
  for (const Case& c : cases) {
    const Model urdf = throughUrdf(c.dh);
    // The URDF's placements do carry round-off (else this test would prove nothing).
    bool round_off = false;
    for (int i = 0; i < urdf.numJoints(); ++i)
      for (int k = 0; k < 9; ++k) {
        const double x = std::abs(urdf.joint_placements()[i].rotation.data()[k]);
        round_off = round_off || (x > 0.0 && x < 1e-15);
      }
    EXPECT_TRUE(round_off || c.dh.name == "puma560") << c.name;
    const BaseParameters from_dh = structural(c.dh), from_urdf = structural(urdf);
    EXPECT_EQ(from_dh.numBase(), c.base) << c.name;
    EXPECT_EQ(from_urdf.numBase(), c.base) << c.name;
    // Where the URDF's link frames are the DH ones (modified DH: link frames on the joints), the
    // same parameters are kept; standard DH's are re-expressed in joint frames by the export.
    bool link_frames_on_joints = true;
    for (const Pose<double>& p : c.dh.body_placements())
      link_frames_on_joints = link_frames_on_joints && p.translation.norm() == 0.0 &&
                              p.rotation == Eigen::Matrix3d::Identity();
    if (link_frames_on_joints) {
      EXPECT_EQ(from_urdf.independent, from_dh.independent) << c.name;
    }
    EXPECT_GT(from_urdf.rankGap(), 1e4) << c.name;
  }
}

TEST(BaseParameters, ARoundOffColumnNeverActs) {
  // The Panda's mz2 gives tau = 0 exactly; through a URDF its column is round-off. It must be a
  // parameter that never acts, not an independent one scaled up from noise.
  const Model urdf = throughUrdf(makePanda(false));
  const BaseParameters base = structural(urdf);
  const int mz2 = 10 + 3;
  EXPECT_NE(std::find(base.zero_columns.begin(), base.zero_columns.end(), mz2),
            base.zero_columns.end());
  EXPECT_EQ(base.significance[mz2], 0.0);
  EXPECT_EQ(std::find(base.independent.begin(), base.independent.end(), mz2),
            base.independent.end());
}

TEST(BaseParameters, ExcitationFindsAnUnmovedJoint) {
  const Model model = test::Planar2R().model();
  const BaseParameters base = structural(model);
  // The shoulder locked at q1 = 0: the Izz1R column (ddq1) vanishes and so does my1's gravity
  // column (g sin q1).
  Trajectory t;
  t.resize(2, 40);
  std::mt19937_64 rng(1);
  for (int k = 0; k < 40; ++k) {
    t.time[k] = k;
    t.q(1, k) = test::randomVector(rng, 1, 3.0)[0];
    t.dq(1, k) = test::randomVector(rng, 1, 2.0)[0];
    t.ddq(1, k) = test::randomVector(rng, 1, 2.0)[0];
  }
  const Observation o = observationFromTrajectory(model, t);
  const Excitation e = measureExcitation(base.baseRegressor(o.W));
  EXPECT_EQ(e.rank, base.numBase() - 2);
  ASSERT_EQ(e.unexcited.size(), 2u);
  EXPECT_EQ(base.baseName(e.unexcited[0]), "my1");
  EXPECT_EQ(base.baseName(e.unexcited[1]), "Izz1R");
}

TEST(BaseParameters, TheErrorScaleTreatsRoundOffZerosLikeZeros) {
  // |truth_j|, except for 0 and a round-off 1e-15 (below 1e-9 of the mean magnitude): the mean
  // magnitude of the values that are not zeros, (2 + 4) / 2.
  const Eigen::VectorXd truth = (Eigen::VectorXd(4) << 2.0, 0.0, -4.0, 1e-15).finished();
  const Eigen::VectorXd scale = baseParameterScale(truth);
  EXPECT_EQ(scale, (Eigen::VectorXd(4) << 2.0, 3.0, 4.0, 3.0).finished());
  // The error is the RMS of |beta - truth| / scale.
  const Eigen::VectorXd beta = (Eigen::VectorXd(4) << 2.2, 0.3, -4.0, 0.0).finished();
  double max = 0.0;
  EXPECT_NEAR(baseParameterError(beta, truth, &max), std::sqrt((0.01 + 0.01) / 4.0), 1e-15);
  EXPECT_NEAR(max, 0.1, 1e-15);
  EXPECT_EQ(baseParameterScale(Eigen::VectorXd::Zero(2)), Eigen::VectorXd::Ones(2));
}

TEST(BaseParameters, TheConditionNumberIsTheSingularValuesRatioAndInfiniteWithoutOne) {
  // A rotation times diag(4, 1): singular values 4 and 1 whatever the rotation.
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(0.3).toRotationMatrix();
  const Eigen::MatrixXd r = rotation * Eigen::Vector2d(4.0, 1.0).asDiagonal();
  EXPECT_NEAR(conditionNumber(r), 4.0, 1e-12);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(conditionNumber(Eigen::MatrixXd(0, 0)), inf);
  EXPECT_EQ(conditionNumber(Eigen::Matrix2d(Eigen::Vector2d(4.0, 0.0).asDiagonal())), inf);
  // An entry that is not finite (Eigen's Jacobi SVD would not end on a NaN).
  Eigen::MatrixXd nan = r;
  nan(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(conditionNumber(nan), inf);
  nan(1, 1) = inf;
  EXPECT_EQ(conditionNumber(nan), inf);
  // The scaled one is the condition number of A with unit columns: here 4 and 1 rotated are
  // already orthogonal columns of norms 4 and 1, so 1.
  EXPECT_NEAR(scaledConditionNumber(r), 1.0, 1e-12);
}

TEST(BaseParameters, RejectsBadInput) {
  EXPECT_THROW(computeBaseParameters(Eigen::MatrixXd::Ones(5, 3), {"a", "b"}), InputError);
  Eigen::MatrixXd W = Eigen::MatrixXd::Ones(5, 2);
  W(1, 1) = std::nan("");
  EXPECT_THROW(computeBaseParameters(W, {"a", "b"}), InputError);
  EXPECT_THROW(computeBaseParameters(Eigen::MatrixXd::Ones(5, 2), {"a", "b"}, 0.0, {0, 0}),
               InputError);
}

}  // namespace
}  // namespace dynid
