#include "core/energy.hpp"

#include "core/checks.hpp"
#include "core/friction.hpp"
#include "core/kinematics.hpp"

namespace dynid {

double kineticEnergy(const Model& model, Data& data, const ConstVectorRef<double>& q,
                     const ConstVectorRef<double>& dq) {
  checkSize(model, dq, "dq");
  forwardKinematics(model, data, q);
  double energy = 0.0;
  for (int i = 0; i < model.numJoints(); ++i) {
    // v_i = iXp v_p + S dq;  T += 1/2 v_i . I v_i (joint frames)
    const int p = model.parents()[i];
    data.v[i] = jointMotionAt(model, i, dq[i]);
    if (p >= 0) data.v[i] += data.liMi[i].actInvMotion(data.v[p]);
    energy += 0.5 * data.v[i].dot(model.frame_inertias()[i].apply(data.v[i]));
    if (model.driveTerms().inertial()) energy += 0.5 * driveInertia(model, i) * dq[i] * dq[i];
  }
  return energy;
}

double potentialEnergy(const Model& model, Data& data, const ConstVectorRef<double>& q) {
  forwardKinematics(model, data, q);
  double energy = 0.0;
  for (int i = 0; i < model.numJoints(); ++i) {
    // m c in the base frame = m p + R h.
    const Pose<double>& X = data.oMi[i];
    const RigidInertia<double>& I = model.inertias()[i];
    const Eigen::Vector3d mc = I.mass * X.translation + X.rotation * I.first_moment;
    energy -= model.gravity().dot(mc);
  }
  return energy;
}

}  // namespace dynid
