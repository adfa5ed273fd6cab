// Log-Cholesky parameters of a rigid body's inertia (Rucker & Wensing, "Smooth Parameterization of
// Rigid-Body Inertia", IEEE RA-L 2022): 10 unconstrained numbers that map onto exactly the
// physically realisable inertias with a positive definite pseudo-inertia, so an optimiser moving
// freely in them never leaves the physical set.
//
// The pseudo-inertia of a body with mass m, first moment h and rotational inertia I (about the
// frame origin) is the symmetric 4x4
//     J = [ Sigma  h ]      Sigma = tr(I)/2 * 1 - I   (the second moment of the mass),
//         [ h^T    m ]
// and the body is physically realisable exactly when J is positive semi-definite (Wensing et al.,
// 2017: this implies m >= 0, a positive semi-definite inertia about the centre of mass and the
// triangle inequalities). The log-Cholesky vector
//     phi = (alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3)
// builds the upper-triangular factor
//     U = e^alpha [ e^d1  s12   s13   t1 ]
//                 [ 0     e^d2  s23   t2 ]
//                 [ 0     0     e^d3  t3 ]
//                 [ 0     0     0     1  ]
// and J = U U^T, which is positive definite for every finite phi.
#pragma once

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "core/errors.hpp"
#include "core/parameters.hpp"

namespace dynid {

inline constexpr int kLogCholeskyCount = 10;

/// The standard 10-vector [m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz] (parameters.hpp) of the
/// log-Cholesky vector phi (10 entries, any Scalar, e.g. ceres::Jet).
template <typename Scalar>
Eigen::Matrix<Scalar, 10, 1> logCholeskyToStandard(const Scalar* phi) {
  using std::exp;
  // U / e^alpha, upper triangular.
  Eigen::Matrix<Scalar, 4, 4> u = Eigen::Matrix<Scalar, 4, 4>::Zero();
  u(0, 0) = exp(phi[1]), u(1, 1) = exp(phi[2]), u(2, 2) = exp(phi[3]), u(3, 3) = Scalar(1);
  u(0, 1) = phi[4], u(1, 2) = phi[5], u(0, 2) = phi[6];
  u(0, 3) = phi[7], u(1, 3) = phi[8], u(2, 3) = phi[9];
  // J = e^(2 alpha) u u^T.
  const Eigen::Matrix<Scalar, 4, 4> j = exp(Scalar(2) * phi[0]) * (u * u.transpose());
  // I = tr(Sigma) 1 - Sigma.
  const Matrix3<Scalar> sigma = j.template topLeftCorner<3, 3>();
  Matrix3<Scalar> inertia = -sigma;
  inertia.diagonal().array() += sigma.trace();
  Eigen::Matrix<Scalar, 10, 1> p;
  p << j(3, 3), j(0, 3), j(1, 3), j(2, 3), inertia(0, 0), inertia(0, 1), inertia(0, 2),
      inertia(1, 1), inertia(1, 2), inertia(2, 2);
  return p;
}

/// The pseudo-inertia J (4x4) of a standard 10-vector.
inline Eigen::Matrix4d pseudoInertia(const Eigen::Matrix<double, 10, 1>& p) {
  const RigidInertia<double> body = fromStandardVector(p);
  Eigen::Matrix4d j;
  j.topLeftCorner<3, 3>() = -body.inertia;
  j.topLeftCorner<3, 3>().diagonal().array() += 0.5 * body.inertia.trace();
  j.topRightCorner<3, 1>() = body.first_moment;
  j.bottomLeftCorner<1, 3>() = body.first_moment.transpose();
  j(3, 3) = body.mass;
  return j;
}

/// The log-Cholesky vector of a standard 10-vector whose pseudo-inertia is positive definite (the
/// inverse of logCholeskyToStandard). Throws NumericalError when it is not positive definite.
inline Eigen::Matrix<double, 10, 1> standardToLogCholesky(const Eigen::Matrix<double, 10, 1>& p) {
  // U U^T = J with U upper triangular: reverse the order, take the lower Cholesky factor L of
  // the reversed matrix, and reverse back (U = P L P, P the reversal).
  const Eigen::Matrix4d j = pseudoInertia(p);
  const Eigen::Matrix4d reversed = j.reverse();
  const Eigen::LLT<Eigen::Matrix4d> llt(reversed);
  if (llt.info() != Eigen::Success)
    throw NumericalError("the pseudo-inertia is not positive definite: no log-Cholesky form");
  const Eigen::Matrix4d l = llt.matrixL();
  const Eigen::Matrix4d u = l.reverse();
  const double scale = u(3, 3);
  Eigen::Matrix<double, 10, 1> phi;
  phi << std::log(scale), std::log(u(0, 0) / scale), std::log(u(1, 1) / scale),
      std::log(u(2, 2) / scale), u(0, 1) / scale, u(1, 2) / scale, u(0, 2) / scale, u(0, 3) / scale,
      u(1, 3) / scale, u(2, 3) / scale;
  return phi;
}

/// A physically consistent standard 10-vector near p: the pseudo-inertia J is scaled to a unit
/// diagonal (J_n = D^-1/2 J D^-1/2, D = |diag J|, so that mass and second moments weigh alike),
/// its eigenvalues raised to at least `floor`, and scaled back. p itself when every eigenvalue of
/// J_n is already at least `floor`. A small floor gives the nearest consistent body; a larger one
/// (1e-2, say) a body safely inside the consistent set, where log-Cholesky coordinates are not
/// degenerate.
inline Eigen::Matrix<double, 10, 1> nearestConsistent(const Eigen::Matrix<double, 10, 1>& p,
                                                      double floor = 1e-9) {
  const Eigen::Matrix4d j = pseudoInertia(p);
  // D: |diag J|, a zero entry replaced by the mean of the others (or 1).
  Eigen::Vector4d d = j.diagonal().cwiseAbs();
  const double mean = d.sum() > 0.0 ? d.sum() / (d.array() > 0.0).count() : 1.0;
  for (double& e : d)
    if (e == 0.0) e = mean;
  const Eigen::Vector4d root = d.cwiseSqrt();
  const Eigen::Matrix4d normalised =
      root.cwiseInverse().asDiagonal() * j * root.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(normalised);
  if (eigen.eigenvalues().minCoeff() >= floor) return p;
  const Eigen::Vector4d values = eigen.eigenvalues().cwiseMax(floor);
  const Eigen::Matrix4d repaired = root.asDiagonal() * eigen.eigenvectors() * values.asDiagonal() *
                                   eigen.eigenvectors().transpose() * root.asDiagonal();
  // Back from J: m = J33, h = J(0:3, 3), I = tr(Sigma) 1 - Sigma.
  const Eigen::Matrix3d sigma = repaired.topLeftCorner<3, 3>();
  Eigen::Matrix3d inertia = -sigma;
  inertia.diagonal().array() += sigma.trace();
  Eigen::Matrix<double, 10, 1> out;
  out << repaired(3, 3), repaired(0, 3), repaired(1, 3), repaired(2, 3), inertia(0, 0),
      inertia(0, 1), inertia(0, 2), inertia(1, 1), inertia(1, 2), inertia(2, 2);
  return out;
}

}  // namespace dynid
