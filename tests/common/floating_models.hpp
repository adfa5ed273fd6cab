// Floating-base test models, and the independent computation the floating algorithms are checked
// against: the same robot with its free flyer as six virtual joints (three prismatic along the
// world axes, then revolute z, y, x) through dynid's fixed-base algorithms.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/floating/floating_data.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::test {

/// An example robot of examples/floating/ and the contacts it stands on.
struct FloatingExample {
  const char* path;  // relative to the source tree
  std::vector<std::string> contacts;
};
/// ANYmal C on its four point feet; Romeo on its two flat soles.
inline const FloatingExample kAnymalExample{"examples/floating/anymal_c/anymal.urdf",
                                            {"LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT"}};
inline const FloatingExample kRomeoExample{"examples/floating/romeo/romeo_small.urdf",
                                           {"l_sole:frame", "r_sole:frame"}};
/// ANYmal C's joints standing with its knees bent (LF, RF, LH, RH; HAA, HFE, KFE each): the
/// stance of the standing tests.
inline Eigen::VectorXd anymalKneesBent() {
  Eigen::VectorXd q(12);
  q << 0, 0.5, -1, 0, 0.5, -1, 0, -0.5, 1, 0, -0.5, 1;
  return q;
}
/// The example's model, read from the source tree.
FloatingModel loadExample(const FloatingExample& example);

/// randomTree's limbs (`options`) under a random, physically consistent base body (2..10 kg).
FloatingModel randomFloating(std::uint64_t seed, const RandomTreeOptions& options = {});

/// The floating model with its free flyer as six virtual joints: bodies 0-4 massless, body 5 the
/// base body, body 6 + i limb i. Drive terms only when `drives` (the virtual joints then carry
/// them too, at zero).
Model virtualChain(const FloatingModel& model, bool drives = false);

/// A floating state drawn at random, and the same state as the virtual chain's coordinates.
struct FloatingSample {
  BaseMotion base;
  Eigen::Vector3d position;
  Eigen::VectorXd q, dq, ddq;                    // the limbs' (n)
  Eigen::VectorXd chain_q, chain_dq, chain_ddq;  // the virtual chain's (6 + n)
};

/// Draws the chain's coordinates (Euler angles within +-1.2 rad, away from the chain's
/// singularity) and derives the base's motion from the chain's own kinematics.
FloatingSample randomFloatingSample(const FloatingModel& model, const Model& chain,
                                    std::mt19937_64& rng);

}  // namespace dynid::test
