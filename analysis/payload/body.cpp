#include "analysis/payload/body.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "core/errors.hpp"
#include "core/parameters.hpp"

namespace dynid {

PrincipalBody principalBody(const Vector10d& standard) {
  if (!(standard[0] > 0.0)) throw InputError("a body needs a positive mass");
  PrincipalBody out;
  out.mass = standard[0];
  out.com = standard.segment<3>(1) / standard[0];
  const Eigen::Matrix3d ic = inertiaAboutCom(fromStandardVector(standard));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(ic);
  // Of the 24 proper rotations whose columns are the eigenvectors (any order, any sign), the one
  // nearest the identity.
  const std::array<std::array<int, 3>, 6> orders = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& order : orders)
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d r;
      for (int c = 0; c < 3; ++c)
        r.col(c) = eigen.eigenvectors().col(order[c]) * ((signs >> c) & 1 ? -1.0 : 1.0);
      if (r.determinant() < 0.0) continue;
      if (r.trace() > best + 1e-12) {
        best = r.trace();
        out.axes = r;
        for (int c = 0; c < 3; ++c) out.moments[c] = eigen.eigenvalues()[order[c]];
      }
    }
  return out;
}

Vector10d standardFromPrincipal(const PrincipalBody& body) {
  RigidInertia<double> out;
  out.mass = body.mass;
  out.first_moment = body.mass * body.com;
  const Eigen::Matrix3d sc = skew(body.com);
  out.inertia = body.axes * body.moments.asDiagonal() * body.axes.transpose() - body.mass * sc * sc;
  return toStandardVector(out);
}

Eigen::Vector3d kukaAbc(const Eigen::Matrix3d& r) {
  // R = Rz(A) Ry(B) Rx(C): r20 = -sin B, r10 / r00 = tan A, r21 / r22 = tan C.
  const double b = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
  double a, c;
  if (std::hypot(r(0, 0), r(1, 0)) > 1e-12) {
    a = std::atan2(r(1, 0), r(0, 0));
    c = std::atan2(r(2, 1), r(2, 2));
  } else {  // gimbal lock: C = 0
    a = std::atan2(-r(0, 1), r(1, 1));
    c = 0.0;
  }
  return {a, b, c};
}

Eigen::Matrix3d rotationFromKukaAbc(const Eigen::Vector3d& abc) {
  return (Eigen::AngleAxisd(abc[0], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(abc[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(abc[2], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector4d abbQuaternion(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return {q.w(), q.x(), q.y(), q.z()};
}

Eigen::Matrix3d rotationFromAbbQuaternion(const Eigen::Vector4d& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

}  // namespace dynid
