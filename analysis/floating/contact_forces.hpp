// How the contacts that hold share the wrench a floating robot's motion needs (docs/FLOATING.md,
// "Estimation on simulated data"): the least-norm forces, or the least-norm forces within
// friction cones about the ground's normal.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace dynid {

/// The cones: `coned` the first row of each 3-D force that must stay in its cone (a point
/// contact's force; a frame contact's force, after its moment's three rows, its moment left free;
/// a sole's corner's force), `up` the ground's normal in the forces' axes (unit), `axes` each coned
/// force's own cone axis (unit, as many as `coned`; empty: `up` for every one), `friction` the
/// coefficient mu (the cone's half-angle is atan(mu)); 0 imposes no cone.
struct ContactCones {
  std::vector<int> coned;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::vector<Eigen::Vector3d> axes;
  double friction = 0.0;
  /// The cone axis of coned force k.
  const Eigen::Vector3d& axis(std::size_t k) const { return axes.empty() ? up : axes[k]; }
};

/// The forces f (stacked as the Jacobian's rows) with `map` f = `wrench` (map: 6 x rows, the
/// contact Jacobian's base columns transposed) of least norm; with a friction coefficient, each
/// coned force within its cone: the normal component non-negative and the tangential one at most
/// mu times it. Solved by the alternating direction method of multipliers (the affine set and the
/// cones, projected onto in turn) to a residual of 1e-10 of the wrench's norm; nullopt when the
/// cones cannot carry the wrench (the forces that carry it leave a cone by more than 1e-9 of the
/// wrench's norm after 20000 iterations: no such forces, or a state so close to the cones' edge
/// that the method does not settle). Without friction, the least-norm solution (never nullopt
/// while `map` has rank 6). Throws InputError on sizes that disagree, a `coned` row out of range
/// or `axes` that are not one per coned force.
std::optional<Eigen::VectorXd> contactForces(const Eigen::MatrixXd& map,
                                             const Eigen::VectorXd& wrench,
                                             const ContactCones& cones);

}  // namespace dynid
