#pragma once

#include <algorithm>
#include <type_traits>

#include "core/aba-inl.hpp"
#include "core/checks.hpp"
#include "core/crba.hpp"
#include "core/friction.hpp"
#include "core/sin_cos.hpp"

namespace dynid {

namespace crba_detail {

/// X.rotation = Pi G for a revolute z joint whose placement rotates by kAxisPermutations[K] = pi
/// (Model::placement_permutation): G = Pi^T R, a rotation about z with signed rows, and
/// (Pi x)_a = x_pi(a). See aba_detail::addTransformedInertiaPermuted.
template <int K, typename Scalar>
struct PermutedRotation {
  static constexpr int p0 = kAxisPermutations[K][0], p1 = kAxisPermutations[K][1],
                       p2 = kAxisPermutations[K][2];
  // G(j, :) = R(pi^-1(j), :).
  static constexpr int r0 = p0 == 0 ? 0 : (p1 == 0 ? 1 : 2), r1 = p0 == 1 ? 0 : (p1 == 1 ? 1 : 2),
                       r2 = p0 == 2 ? 0 : (p1 == 2 ? 1 : 2);
  DYNID_INLINE explicit PermutedRotation(const Matrix3<Scalar>& R)
      : g00(R(r0, 0)), g01(R(r0, 1)), g10(R(r1, 0)), g11(R(r1, 1)), g22(R(r2, 2)) {}
  /// G x.
  DYNID_INLINE Vector3<Scalar> rotate(const Vector3<Scalar>& x) const {
    return Vector3<Scalar>(g00 * x[0] + g01 * x[1], g10 * x[0] + g11 * x[1], g22 * x[2]);
  }
  Scalar g00, g01, g10, g11, g22;
};

/// parent += the child's composite inertia c expressed in the parent's frame (X places the child),
/// for a revolute z joint with a permuted placement: rotate by G about z (half the products of a
/// general rotation), apply the parallel-axis terms with t = Pi^T p in G's frame, then permute the
/// entries into the parent's (free: pi is known at compile time). `s` is Model::placement_shift,
/// det(Pi) Pi^T p.
template <int K, typename Scalar>
DYNID_INLINE void addCompositePermuted(const Pose<Scalar>& X, const Vector3<Scalar>& s,
                                       const RigidInertia<Scalar>& c,
                                       RigidInertia<Scalar>& parent) {
  using Rotation = PermutedRotation<K, Scalar>;
  constexpr int pi[3] = {Rotation::p0, Rotation::p1, Rotation::p2};
  const Rotation G(X.rotation);
  const Scalar& m = c.mass;
  // J = G I G^T (symmetric: its upper triangle), g = G h, t = Pi^T p.
  aba_detail::Symmetric3<Scalar> J =
      aba_detail::rotateSymmetricAboutZ(G.g00, G.g01, G.g10, G.g11, G.g22, c.inertia);
  const Vector3<Scalar> g = G.rotate(c.first_moment);
  const Vector3<Scalar> t = kAxisPermutationSigns[K] > 0 ? s : Vector3<Scalar>(-s);
  // h' = g + m t; J += (m |t|^2 + 2 t.g) 1 - (m t + g) t^T - t g^T (the parallel-axis theorem),
  // symmetric: (m t + g) t^T + t g^T = m t t^T + g t^T + t g^T.
  const Vector3<Scalar> h = g + m * t;
  const Scalar shift = m * (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) +
                       Scalar(2) * (t[0] * g[0] + t[1] * g[1] + t[2] * g[2]);
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) J(a, b) -= h[a] * t[b] + t[a] * g[b];
  for (int a = 0; a < 3; ++a) J(a, a) += shift;
  // Into the parent's frame: entry a of a vector takes entry pi(a), (a, b) of a matrix (pi(a),
  // pi(b)). Permuted into locals first and added whole: the parent's entries are then stored as
  // packed pairs, as the next iteration loads them (entry-by-entry stores stall store-to-load
  // forwarding).
  Matrix3<Scalar> Jp;
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) Jp(a, b) = J(pi[a], pi[b]);
  parent.mass += m;
  parent.first_moment += Vector3<Scalar>(h[pi[0]], h[pi[1]], h[pi[2]]);
  parent.inertia += Jp;
}

/// F in the parent's frame (X.actForce(F)) for a permuted placement: f' = Pi G f and
/// n' = Pi (G n + s x G f), since p x Pi y = det(Pi) Pi (Pi^T p x y).
template <int K, typename Scalar>
DYNID_INLINE void actForcePermuted(const Pose<Scalar>& X, const Vector3<Scalar>& s,
                                   Vector6<Scalar>& F) {
  using Rotation = PermutedRotation<K, Scalar>;
  constexpr int pi[3] = {Rotation::p0, Rotation::p1, Rotation::p2};
  const Rotation G(X.rotation);
  const Vector3<Scalar> f = G.rotate(F.template tail<3>());
  const Vector3<Scalar> n = G.rotate(F.template head<3>()) + cross(s, f);
  F << n[pi[0]], n[pi[1]], n[pi[2]], f[pi[0]], f[pi[1]], f[pi[2]];
}

/// actForcePermuted's moment about z alone, (G n + s x G f) at pi(2): the projection on a revolute
/// z parent's axis.
template <int K, typename Scalar>
DYNID_INLINE Scalar projectedForcePermuted(const Pose<Scalar>& X, const Vector3<Scalar>& s,
                                           const Vector6<Scalar>& F) {
  using Rotation = PermutedRotation<K, Scalar>;
  const Rotation G(X.rotation);
  const Vector3<Scalar> f = G.rotate(F.template tail<3>());
  const Vector3<Scalar> n = G.rotate(F.template head<3>());
  constexpr int c = Rotation::p2;
  constexpr int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
  return n[c] + (s[c1] * f[c2] - s[c2] * f[c1]);
}

/// body(std::integral_constant<int, K>) for the permutation index k in 0..5.
template <typename Body>
DYNID_INLINE void withPermutation(int k, Body&& body) {
  switch (k) {
    case 0:
      return body(std::integral_constant<int, 0>());
    case 1:
      return body(std::integral_constant<int, 1>());
    case 2:
      return body(std::integral_constant<int, 2>());
    case 3:
      return body(std::integral_constant<int, 3>());
    case 4:
      return body(std::integral_constant<int, 4>());
    default:
      return body(std::integral_constant<int, 5>());
  }
}

/// CRBA from the joint transforms already in data.liMi (set by crba or rnea). One sweep from the
/// leaves: at joint j the composite inertia Ic_j is complete, F_j = Ic_j S_j joins the forces of
/// j's subtree, all now in frame j, M(j, i) = S_j . F_i for each of them, and then they all move to
/// j's parent's frame with the same transform: transforms independent of each other, where a
/// column walked to the root one transform after another waited on each.
template <typename Scalar>
DYNID_FLATTEN void massMatrixFromTransforms(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data) {
  const int n = model.numJoints();
  for (int i = 0; i < n; ++i) data.composite[i] = model.frame_inertias()[i];
  data.M.setZero();
  std::vector<Vector6<Scalar>>& F = data.column_force;  // joint i's, in frame frame_of[i]
  std::vector<int>& frame_of = data.column_frame;
  for (int j = n - 1; j >= 0; --j) {
    // F = Ic_j S_j; for S_j = (e_z, 0) that is (I e_z, -h x e_z), a column and a swap.
    const RigidInertia<Scalar>& Ic = data.composite[j];
    if (model.subspace_index()[j] == 2)
      F[j] << Ic.inertia(0, 2), Ic.inertia(1, 2), Ic.inertia(2, 2), -Ic.first_moment[1],
          Ic.first_moment[0], Scalar(0);
    else
      F[j] = Ic.apply(model.motion_subspaces()[j]);
    frame_of[j] = j;
    data.M(j, j) = projectOnJoint(model, j, F[j]);
    if (model.driveTerms().inertial()) data.M(j, j) += driveInertia(model, j);
    for (int i = j + 1; i < n; ++i)
      if (frame_of[i] == j) data.M(j, i) = data.M(i, j) = projectOnJoint(model, j, F[i]);
    const int p = model.parents()[j];
    if (p < 0) continue;
    const int k = model.placement_permutation()[j];
    const Vector3<Scalar>& s = model.placement_shift()[j];
    const Pose<Scalar>& X = data.liMi[j];
    if (k >= 0) {
      withPermutation(k, [&](auto K) {
        addCompositePermuted<K()>(X, s, data.composite[j], data.composite[p]);
        if (model.parents()[p] < 0 && model.subspace_index()[p] == 2) {
          // The root's entries need only the moment's z component in its frame: (G n + s x G f)
          // at pi(2), a third of the transform.
          for (int i = j; i < n; ++i)
            if (frame_of[i] == j) {
              data.M(p, i) = data.M(i, p) = projectedForcePermuted<K()>(X, s, F[i]);
              frame_of[i] = -1;  // done
            }
          return;
        }
        for (int i = j; i < n; ++i)
          if (frame_of[i] == j) {
            actForcePermuted<K()>(X, s, F[i]);
            frame_of[i] = p;
          }
      });
    } else {
      data.composite[p] += data.composite[j].transformedBy(X);
      for (int i = j; i < n; ++i)
        if (frame_of[i] == j) {
          F[i] = X.actForce(F[i]);
          frame_of[i] = p;
        }
    }
  }
}
}  // namespace crba_detail

namespace crba_detail {
/// Revolute joint i's transform from s = sin q_i, c = cos q_i: for an axis along x or y the
/// placement's columns turned (P Rx, P Ry: the same sums as the 3 x 3 product, without its zero
/// terms), else setRevoluteTransform.
/// P R_axis(q) for axis 0 (x) or 1 (y), from s = sin q, c = cos q: two of P's columns turned.
template <typename Scalar>
DYNID_INLINE void turnPlacementColumns(const Pose<Scalar>& P, int axis, const Scalar& s,
                                       const Scalar& c, Pose<Scalar>& out) {
  // Rx turns columns 1, 2: (c P1 + s P2, c P2 - s P1); Ry turns 2, 0: (c P2 + s P0, c P0 - s P2).
  const int fixed = axis, a = axis == 0 ? 1 : 2, b = axis == 0 ? 2 : 0;
  for (int r = 0; r < 3; ++r) {
    out.rotation(r, fixed) = P.rotation(r, fixed);
    out.rotation(r, a) = c * P.rotation(r, a) + s * P.rotation(r, b);
    out.rotation(r, b) = c * P.rotation(r, b) - s * P.rotation(r, a);
  }
  out.translation = P.translation;
}

template <typename Scalar>
DYNID_INLINE void revoluteTransformByColumns(const ModelTpl<Scalar>& model, int i, const Scalar& s,
                                             const Scalar& c, Pose<Scalar>& out) {
  const AxisKind kind = model.axis_kinds()[i];
  if (kind != AxisKind::kX && kind != AxisKind::kY) {
    setRevoluteTransform(model, i, s, c, out);
    return;
  }
  turnPlacementColumns(model.frame_placements()[i], kind == AxisKind::kX ? 0 : 1, s, c, out);
}
}  // namespace crba_detail

/// Every joint's transform liMi at q; for double, the sines and cosines eight at a time in SIMD
/// registers (core/sin_cos.hpp: within 1 ulp of the C library's, the same bits on every CPU).
/// CRBA's and the floating algorithms' (core/floating/).
template <typename Scalar>
DYNID_INLINE void setJointTransformsBlock(const ModelTpl<Scalar>& model,
                                          std::vector<Pose<Scalar>>& liMi,
                                          const ConstVectorRef<Scalar>& q) {
  const int n = model.numJoints();
  if constexpr (std::is_same_v<Scalar, double>) {
    SinCosBlock block;
    for (int first = 0; first < n; first += SinCosBlock::kSize) {
      const int count = std::min(SinCosBlock::kSize, n - first);
      sinCosBlock(q.data() + first, count, block);
      for (int k = 0, i = first; k < count; ++k, ++i)
        if (model.joint_types()[i] == JointType::kPrismatic)
          setJointTransform(model, i, q[i], liMi[i]);
        else
          crba_detail::revoluteTransformByColumns(model, i, block.s[k], block.c[k], liMi[i]);
    }
  } else {
    for (int i = 0; i < n; ++i) setJointTransform(model, i, q[i], liMi[i]);
  }
}

template <typename Scalar>
const MatrixX<Scalar>& crba(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                            const ConstVectorRef<Scalar>& q) {
  checkData(model, data);
  checkSize(model, q, "q");
  setJointTransformsBlock(model, data.liMi, q);
  crba_detail::massMatrixFromTransforms(model, data);
  return data.M;
}

}  // namespace dynid
