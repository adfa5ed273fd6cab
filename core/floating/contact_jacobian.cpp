#include "core/floating/contact_jacobian.hpp"

#include "core/checks.hpp"

namespace dynid {

namespace {
/// The limbs' joint frames in the base frame (data.limbs.oMj) at q; checks the body index.
void placeJoints(const FloatingModel& model, FloatingData& data, const Contact& contact,
                 const Eigen::Ref<const Eigen::VectorXd>& q) {
  checkFloatingData(model, data);
  const Model& limbs = model.limbs();
  checkSize(limbs, q, "q");
  if (contact.body < -1 || contact.body >= limbs.numJoints())
    throw InputError("contact '" + contact.name + "' is on body " + std::to_string(contact.body) +
                     ", but the model has the base (-1) and bodies 0-" +
                     std::to_string(limbs.numJoints() - 1));
  for (int i = 0; i < limbs.numJoints(); ++i) {
    setJointTransform(limbs, i, q[i], data.limbs.liMi[i]);
    const int p = limbs.parents()[i];
    data.limbs.oMj[i] = p < 0 ? data.limbs.liMi[i] : data.limbs.oMj[p] * data.limbs.liMi[i];
  }
}
}  // namespace

Pose<double> contactPose(const FloatingModel& model, FloatingData& data, const Contact& contact,
                         const Eigen::Ref<const Eigen::VectorXd>& q) {
  placeJoints(model, data, contact, q);
  if (contact.body < 0) return contact.placement;
  return data.limbs.oMj[contact.body] * model.limbs().body_placements()[contact.body] *
         contact.placement;
}

Eigen::MatrixXd contactJacobian(const FloatingModel& model, FloatingData& data,
                                const Contact& contact,
                                const Eigen::Ref<const Eigen::VectorXd>& q) {
  const Pose<double> frame = contactPose(model, data, contact, q);
  const Model& limbs = model.limbs();
  // The spatial velocity of the contact frame about the base origin, in base axes: the base's
  // twist plus each ancestor joint's S_j dq_j (S_j in base axes), then moved to the contact
  // point: v_c = v + omega x r.
  Eigen::MatrixXd spatial = Eigen::MatrixXd::Zero(6, model.numVelocities());
  spatial.leftCols<6>().setIdentity();
  for (int j = contact.body; j >= 0; j = limbs.parents()[j])
    spatial.col(6 + j) = data.limbs.oMj[j].actMotion(jointMotionAt(limbs, j, 1.0));
  const Eigen::Vector3d r = frame.translation;
  Eigen::MatrixXd out(contact.dimension(), model.numVelocities());
  const Eigen::MatrixXd linear = spatial.bottomRows<3>() - skew(r) * spatial.topRows<3>();
  if (contact.kind == Contact::Kind::kPoint) {
    out = linear;
  } else {
    out.topRows<3>() = spatial.topRows<3>();
    out.bottomRows<3>() = linear;
  }
  return out;
}

}  // namespace dynid
