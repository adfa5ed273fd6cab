#include "tests/common/floating_models.hpp"

#include "core/parameters.hpp"
#include "core/rnea.hpp"
#include "data/urdf.hpp"

namespace dynid::test {

FloatingModel loadExample(const FloatingExample& example) {
  return loadFloatingUrdf(std::string(DYNID_SOURCE_DIR) + "/" + example.path);
}

FloatingModel randomFloating(std::uint64_t seed, const RandomTreeOptions& options) {
  std::mt19937_64 rng(seed + 1000);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix<double, 7, 1> paper;
  const double a = 0.05 + 0.3 * unit(rng), b = 0.05 + 0.3 * unit(rng);
  const double c = std::abs(a - b) + (a + b - std::abs(a - b)) * unit(rng);
  paper << 2.0 + 8.0 * unit(rng), randomVector(rng, 3, 0.1), a, b, c;
  return FloatingModel(randomTree(seed, options), fromStandardVector(paperToStandard(paper)),
                       "trunk");
}

Model virtualChain(const FloatingModel& model, bool drives) {
  const Model& limbs = model.limbs();
  Model out;
  out.name = limbs.name + "_virtual";
  const RigidInertia<double> none;
  const char* names[6] = {"px", "py", "pz", "rz", "ry", "rx"};
  const int axes[6] = {0, 1, 2, 2, 1, 0};
  for (int k = 0; k < 6; ++k)
    out.addBody(k - 1, k == 5 ? model.baseName() : names[k], names[k],
                k < 3 ? JointType::kPrismatic : JointType::kContinuous, Pose<double>(),
                Eigen::Vector3d::Unit(axes[k]), Pose<double>(),
                k == 5 ? model.baseInertia() : none);
  for (int i = 0; i < limbs.numJoints(); ++i) {
    const int p = limbs.parents()[i];
    out.addBody(p < 0 ? 5 : p + 6, limbs.link_names[i], limbs.joint_names[i],
                limbs.joint_types()[i], limbs.joint_placements()[i], limbs.axes()[i],
                limbs.body_placements()[i], limbs.inertias()[i], limbs.limits[i],
                limbs.drives()[i]);
  }
  out.setGravity(limbs.gravity());
  if (drives) out.setDriveTerms(limbs.driveTerms());
  out.finalize();
  return out;
}

FloatingSample randomFloatingSample(const FloatingModel& model, const Model& chain,
                                    std::mt19937_64& rng) {
  const int n = model.numJoints();
  FloatingSample s;
  s.chain_q = randomVector(rng, 6 + n, 1.2);
  s.chain_dq = randomVector(rng, 6 + n, 1.5);
  s.chain_ddq = randomVector(rng, 6 + n, 3.0);
  s.q = s.chain_q.tail(n), s.dq = s.chain_dq.tail(n), s.ddq = s.chain_ddq.tail(n);
  Data data(chain);
  rnea(chain, data, s.chain_q, s.chain_dq, s.chain_ddq);
  // Body 5's joint frame is the base frame (identity placements): its rotation in the world, its
  // twist, and its acceleration less the -g RNEA adds at the root.
  Pose<double> world_base;
  for (int k = 0; k < 6; ++k) world_base = world_base * data.liMi[k];
  s.position = world_base.translation;
  s.base.rotation = world_base.rotation;
  s.base.twist = data.v[5];
  s.base.acceleration = data.a[5];
  s.base.acceleration.tail<3>() += world_base.rotation.transpose() * chain.gravity();
  return s;
}

}  // namespace dynid::test
