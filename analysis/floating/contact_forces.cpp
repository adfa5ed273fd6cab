#include "analysis/floating/contact_forces.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {

namespace {
/// The projection of x onto the cone {n . x >= 0, |x - (n . x) n| <= mu n . x} (n unit).
Eigen::Vector3d projectOnCone(const Eigen::Vector3d& x, const Eigen::Vector3d& n, double mu) {
  const double normal = n.dot(x);
  const Eigen::Vector3d tangent = x - normal * n;
  const double t = tangent.norm();
  if (t <= mu * normal) return x;                         // inside
  if (mu * t <= -normal) return Eigen::Vector3d::Zero();  // inside the polar cone
  // Onto the cone's surface: the nearest point on the ray at angle atan(mu) in x's plane.
  const double s = (normal + mu * t) / (1.0 + mu * mu);
  return s * n + (mu * s / t) * tangent;
}

/// How far x is outside the cone (0 inside): the larger of the normal's deficit and the
/// tangent's excess.
double coneExcess(const Eigen::Vector3d& x, const Eigen::Vector3d& n, double mu) {
  const double normal = n.dot(x);
  return std::max({0.0, -normal, (x - normal * n).norm() - mu * normal});
}

void checkCones(const Eigen::MatrixXd& map, const Eigen::VectorXd& wrench,
                const ContactCones& cones) {
  if (map.rows() != 6 || wrench.size() != 6)
    throw InputError("contact forces: the map has " + std::to_string(map.rows()) +
                     " rows and the wrench " + std::to_string(wrench.size()) + " entries, not 6");
  for (int row : cones.coned)
    if (row < 0 || row + 3 > map.cols())
      throw InputError("contact forces: a coned force at row " + std::to_string(row) + " of " +
                       std::to_string(map.cols()));
  if (!cones.axes.empty() && cones.axes.size() != cones.coned.size())
    throw InputError("contact forces: " + std::to_string(cones.axes.size()) + " cone axes for " +
                     std::to_string(cones.coned.size()) + " coned forces");
  if (!(cones.friction >= 0.0) || !std::isfinite(cones.friction))
    throw InputError("`friction` must be finite and non-negative");
}
}  // namespace

std::optional<Eigen::VectorXd> contactForces(const Eigen::MatrixXd& map,
                                             const Eigen::VectorXd& wrench,
                                             const ContactCones& cones) {
  checkCones(map, wrench, cones);
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> solver(map);
  const Eigen::VectorXd least = solver.solve(wrench);
  if (cones.friction == 0.0 || cones.coned.empty()) return least;
  const double scale = std::max(wrench.norm(), 1e-300);
  // The affine set {map f = wrench} is least + the null space: its projection is least + P (x -
  // least), P = 1 - map^+ map the null space's projector.
  const Eigen::MatrixXd P =
      Eigen::MatrixXd::Identity(map.cols(), map.cols()) - solver.pseudoInverse() * map;
  const auto projectInCones = [&](Eigen::VectorXd& x) {
    for (std::size_t k = 0; k < cones.coned.size(); ++k)
      x.segment<3>(cones.coned[k]) =
          projectOnCone(x.segment<3>(cones.coned[k]), cones.axis(k), cones.friction);
  };
  // ADMM on min |f|^2 s.t. f affine, g in the cones, f = g (scaled by the wrench's norm); the
  // iterates in place (no allocation per iteration: a state the cones cannot hold runs them all).
  const double rho = 1.0;
  const Eigen::Index m = map.cols();
  const Eigen::VectorXd base = least / scale;
  Eigen::VectorXd f = base, g = base, u = Eigen::VectorXd::Zero(m), step(m), previous(m);
  projectInCones(g);
  for (int iteration = 0; iteration < 20000; ++iteration) {
    step = (rho / (2.0 + rho)) * (g - u) - base;
    f = base;
    f.noalias() += P * step;
    previous = g;
    g = f + u;
    projectInCones(g);
    u += f - g;
    if ((f - g).norm() < 1e-10 && rho * (g - previous).norm() < 1e-10) break;
  }
  f *= scale;
  double excess = 0.0;
  for (std::size_t k = 0; k < cones.coned.size(); ++k)
    excess =
        std::max(excess, coneExcess(f.segment<3>(cones.coned[k]), cones.axis(k), cones.friction));
  if (excess > 1e-9 * scale) return std::nullopt;
  return f;
}

}  // namespace dynid
