#include "analysis/payload/attach.hpp"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

int linkIndex(const Model& arm, const std::string& link) {
  if (link.empty()) return arm.numJoints() - 1;
  for (int i = 0; i < arm.numJoints(); ++i)
    if (arm.link_names[i] == link) return i;
  std::string names;
  for (const std::string& l : arm.link_names) names += (names.empty() ? "" : ", ") + l;
  throw InputError("`link` '" + link + "' is not a moving link of robot '" + arm.name +
                   "' (its links: " + names + ")");
}

Vector10d bodyFromCentre(double mass, const Eigen::Vector3d& com,
                         const Eigen::Matrix3d& inertia_about_com) {
  if (!std::isfinite(mass) || !(mass > 0.0))
    throw InputError("the body's `mass` must be finite and > 0, not " + formatNumber(mass));
  if (!com.allFinite()) throw InputError("the body's `com` must be finite");
  const Eigen::Matrix3d& i = inertia_about_com;
  if (!i.allFinite() || (i - i.transpose()).norm() > 1e-12 * (1.0 + i.norm()))
    throw InputError("the body's `inertia` must be finite and symmetric");
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(i).eigenvalues();
  // Each principal moment is at most the sum of the other two (a rigid body's mass distribution),
  // to round-off.
  const double slack = 1e-9 * moments.cwiseAbs().sum();
  if (moments[0] < -slack || moments[2] > moments[0] + moments[1] + slack)
    throw InputError("the body's `inertia` has principal moments " + formatNumber(moments[0]) +
                     ", " + formatNumber(moments[1]) + ", " + formatNumber(moments[2]) +
                     " kg m^2: no rigid body has them (each must be >= 0 and at most the sum of "
                     "the other two)");
  RigidInertia<double> body;
  body.mass = mass;
  body.first_moment = mass * com;
  const Eigen::Matrix3d c = skew(com);
  body.inertia = i - mass * c * c;  // about the frame's origin
  return toStandardVector(body);
}

Model attachBody(const Model& arm, int link, const Pose<double>& frame, const Vector10d& body) {
  if (link < 0 || link >= arm.numJoints())
    throw InputError("`link` " + std::to_string(link) + " is not a link of robot '" + arm.name +
                     "'");
  if (!body.allFinite()) throw InputError("the body's parameters must be finite");
  Model out = arm;
  RigidInertia<double> inertia = arm.inertias()[static_cast<std::size_t>(link)];
  inertia += fromStandardVector(body).transformedBy(frame);
  out.setLinkInertia(link, inertia);
  return out;
}

}  // namespace dynid
