// Template bodies of floating_rnea.hpp; include only to instantiate a new Scalar.
#pragma once

#include <algorithm>
#include <type_traits>

#include "core/crba-inl.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/friction.hpp"

namespace dynid {

// A lambda's body inlined into its caller (GCC and clang take the attribute after the parameters).
#if defined(__GNUC__)
#define DYNID_INLINE_LAMBDA __attribute__((always_inline))
#else
#define DYNID_INLINE_LAMBDA
#endif

namespace floating_detail {
/// The parent's velocity and acceleration of limb body i: the base's when it hangs from it.
template <typename Scalar>
DYNID_INLINE const Vector6<Scalar>& parentOf(const std::vector<Vector6<Scalar>>& limb,
                                             const Vector6<Scalar>& base, int parent) {
  return parent < 0 ? base : limb[static_cast<std::size_t>(parent)];
}

/// w x (e_k x): two entries.
template <typename Scalar>
DYNID_INLINE Vector3<Scalar> crossUnit(const Vector3<Scalar>& w, int k, const Scalar& x) {
  // w x e_k: k = 0 (0, w_z, -w_y), 1 (-w_z, 0, w_x), 2 (w_y, -w_x, 0).
  Vector3<Scalar> out;
  out[k] = Scalar(0);
  out[(k + 1) % 3] = w[(k + 2) % 3] * x;
  out[(k + 2) % 3] = -w[(k + 1) % 3] * x;
  return out;
}

/// The limbs' joint transforms liMi at q, as setJointTransformsBlock writes them, a joint about
/// -e_x or -e_y also by turning its placement's columns (the rotation by q about -e_k is the one
/// by -q about e_k: the sine negated).
template <typename Scalar>
DYNID_INLINE void setLimbTransforms(const FloatingModelTpl<Scalar>& model,
                                    std::vector<Pose<Scalar>>& liMi,
                                    const ConstVectorRef<Scalar>& q) {
  const ModelTpl<Scalar>& limbs = model.limbs();
  if constexpr (std::is_same_v<Scalar, double>) {
    const int n = limbs.numJoints();
    SinCosBlock block;
    for (int first = 0; first < n; first += SinCosBlock::kSize) {
      const int count = std::min(SinCosBlock::kSize, n - first);
      sinCosBlock(q.data() + first, count, block);
      for (int k = 0, i = first; k < count; ++k, ++i) {
        const int r = model.revoluteAxes()[i];
        if (r < 0)
          setJointTransform(limbs, i, q[i], liMi[i]);
        else if (r == 2 || model.axisSigns()[i] > 0)
          crba_detail::revoluteTransformByColumns(limbs, i, block.s[k], block.c[k], liMi[i]);
        else
          crba_detail::turnPlacementColumns(limbs.frame_placements()[i], r, -block.s[k], block.c[k],
                                            liMi[i]);
      }
    }
  } else {
    setJointTransformsBlock(limbs, liMi, q);
  }
}

/// The forward pass shared by inverse dynamics and the regressor: every body's twist and
/// acceleration (gravity as the base's -g) in its joint frame, the base's in the base frame. It
/// works on 3-vector halves, as rnea does (mixed scalar and packed accesses to 6-vectors stall
/// store forwarding), and hands each body's halves (i, w, v, dw, dv) to `body` while they are in
/// registers (inverse dynamics: its force; the regressor: its columns), the base body's first as
/// body -1 (in the base frame). Checks the sizes and the Data first (InputError).
template <typename Scalar, typename PerBody>
DYNID_INLINE void forwardPass(const FloatingModelTpl<Scalar>& model, FloatingDataTpl<Scalar>& data,
                              const BaseMotionTpl<Scalar>& base, const ConstVectorRef<Scalar>& q,
                              const ConstVectorRef<Scalar>& dq, const ConstVectorRef<Scalar>& ddq,
                              PerBody&& body) {
  using V3 = Vector3<Scalar>;
  checkFloatingData(model, data);
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  checkState(limbs, ld, q, dq, ddq, "ddq");
  data.base_v = base.twist;
  data.base_a = base.acceleration;
  data.base_a.template tail<3>() -= transposeTimes(base.rotation, model.gravity());
  body(-1, V3(data.base_v.template head<3>()), V3(data.base_v.template tail<3>()),
       V3(data.base_a.template head<3>()), V3(data.base_a.template tail<3>()));
  const int n = limbs.numJoints();
  setLimbTransforms(model, ld.liMi, q);
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = ld.liMi[i];
    const int p = limbs.parents()[i];
    const Vector6<Scalar>& vp = parentOf(ld.v, data.base_v, p);
    const Vector6<Scalar>& ap = parentOf(ld.a, data.base_a, p);
    const V3 wp = vp.template head<3>(), lp = vp.template tail<3>();
    const V3 dwp = ap.template head<3>(), dlp = ap.template tail<3>();
    // iXp m = (R^T w, R^T (v - t x w)); then + S dq, and the acceleration's v x S dq + S ddq.
    V3 w = transposeTimes(X.rotation, wp);
    V3 v = transposeTimes(X.rotation, V3(lp - cross(X.translation, wp)));
    V3 dw = transposeTimes(X.rotation, dwp);
    V3 dv = transposeTimes(X.rotation, V3(dlp - cross(X.translation, dwp)));
    const int k = limbs.subspace_index()[i], r = model.revoluteAxes()[i];
    if (r >= 0) {  // revolute about +-e_r: the rates' sign folded in
      const Scalar x = model.axisSigns()[i] > 0 ? dq[i] : Scalar(-dq[i]);
      dw += crossUnit(w, r, x);
      dv += crossUnit(v, r, x);
      w[r] += x;
      dw[r] += model.axisSigns()[i] > 0 ? ddq[i] : Scalar(-ddq[i]);
    } else if (k >= 3) {                 // prismatic along e_(k-3)
      dv += crossUnit(w, k - 3, dq[i]);  // v x (0, e dq) = (0, w x e dq)
      v[k - 3] += dq[i];
      dv[k - 3] += ddq[i];
    } else {  // a general axis: the spatial algebra
      Vector6<Scalar> vel, acc;
      vel << w, v;
      addJointMotion(limbs, i, dq[i], vel);
      acc << dw, dv;
      acc += crossJointMotion(limbs, i, vel, dq[i]);
      addJointMotion(limbs, i, ddq[i], acc);
      w = vel.template head<3>(), v = vel.template tail<3>();
      dw = acc.template head<3>(), dv = acc.template tail<3>();
    }
    ld.v[i].template head<3>() = w, ld.v[i].template tail<3>() = v;
    ld.a[i].template head<3>() = dw, ld.a[i].template tail<3>() = dv;
    body(i, w, v, dw, dv);
  }
}
}  // namespace floating_detail

// Flattened: the forward pass, its per-body step and the transforms inline into one loop.
template <typename Scalar>
DYNID_FLATTEN const VectorX<Scalar>& floatingRnea(const FloatingModelTpl<Scalar>& model,
                                                  FloatingDataTpl<Scalar>& data,
                                                  const BaseMotionTpl<Scalar>& base,
                                                  const ConstVectorRef<Scalar>& q,
                                                  const ConstVectorRef<Scalar>& dq,
                                                  const ConstVectorRef<Scalar>& ddq) {
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  // f = I a + v x* (I v), with I v = (I_o w + h x v, m v - h x w); the base body's too.
  floating_detail::forwardPass(
      model, data, base, q, dq, ddq,
      [&](int i, const Vector3<Scalar>& w, const Vector3<Scalar>& v, const Vector3<Scalar>& dw,
          const Vector3<Scalar>& dv) DYNID_INLINE_LAMBDA {
        if (i < 0) {
          const RigidInertia<Scalar>& IB = model.baseInertia();
          data.base_f = IB.apply(data.base_a) + crossForce(data.base_v, IB.apply(data.base_v));
          return;
        }
        const RigidInertia<Scalar>& I = limbs.frame_inertias()[i];
        const Vector3<Scalar> hw = I.inertia * w + cross(I.first_moment, v);
        const Vector3<Scalar> hv = I.mass * v - cross(I.first_moment, w);
        ld.f[i].template head<3>() =
            I.inertia * dw + cross(I.first_moment, dv) + cross(w, hw) + cross(v, hv);
        ld.f[i].template tail<3>() = I.mass * dv - cross(I.first_moment, dw) + cross(w, hv);
      });
  const int n = limbs.numJoints();
  // Backward pass: tau_i = S_i^T f_i (+ drives); each force carried to its parent, the roots'
  // to the base body, whose total is the wrench the motion needs.
  for (int i = n - 1; i >= 0; --i) {
    const int r = model.revoluteAxes()[i];
    Scalar tau_i = r < 0                      ? projectOnJoint(limbs, i, ld.f[i])
                   : model.axisSigns()[i] > 0 ? ld.f[i][r]
                                              : Scalar(-ld.f[i][r]);
    if (limbs.driveTerms().any()) tau_i += driveTorque(limbs, i, dq[i], ddq[i]);
    data.tau[6 + i] = tau_i;
    // f_p += pXi* f_i = (R n + t x R f, R f), on halves.
    const int p = limbs.parents()[i];
    const Pose<Scalar>& X = ld.liMi[i];
    const Vector3<Scalar> rf = X.rotation * Vector3<Scalar>(ld.f[i].template tail<3>());
    const Vector3<Scalar> rn =
        X.rotation * Vector3<Scalar>(ld.f[i].template head<3>()) + cross(X.translation, rf);
    Vector6<Scalar>& fp = p < 0 ? data.base_f : ld.f[p];
    fp.template head<3>() += rn;
    fp.template tail<3>() += rf;
  }
  data.tau.template head<6>() = data.base_f;
  return data.tau;
}

template <typename Scalar>
const MatrixX<Scalar>& floatingCrba(const FloatingModelTpl<Scalar>& model,
                                    FloatingDataTpl<Scalar>& data,
                                    const ConstVectorRef<Scalar>& q) {
  checkFloatingData(model, data);
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  checkSize(limbs, q, "q");
  const int n = limbs.numJoints();
  setJointTransformsBlock(limbs, ld.liMi, q);
  // Composite inertias, leaves first, each in its joint frame; the roots' into the base's.
  for (int i = 0; i < n; ++i) ld.composite[i] = limbs.frame_inertias()[i];
  data.base_composite = model.baseInertia();
  for (int i = n - 1; i >= 0; --i) {
    const int p = limbs.parents()[i];
    (p < 0 ? data.base_composite : ld.composite[p]) += ld.composite[i].transformedBy(ld.liMi[i]);
  }
  data.M.template topLeftCorner<6, 6>() = data.base_composite.matrix();
  // Column j: F = Ic_j S_j carried up the chain; each ancestor k reads S_k^T F, the base all of F.
  for (int j = 0; j < n; ++j) {
    Vector6<Scalar> F = ld.composite[j].apply(jointMotionAt(limbs, j, Scalar(1)));
    data.M(6 + j, 6 + j) = projectOnJoint(limbs, j, F) + driveInertia(limbs, j);
    int i = j;
    for (int k = limbs.parents()[i]; k >= 0; i = k, k = limbs.parents()[k]) {
      F = ld.liMi[i].actForce(F);
      data.M(6 + k, 6 + j) = data.M(6 + j, 6 + k) = projectOnJoint(limbs, k, F);
    }
    F = ld.liMi[i].actForce(F);
    data.M.template block<6, 1>(0, 6 + j) = F;
    data.M.template block<1, 6>(6 + j, 0) = F.transpose();
  }
  return data.M;
}

template <typename Scalar>
const VectorX<Scalar>& floatingForwardDynamics(
    const FloatingModelTpl<Scalar>& model, FloatingDataTpl<Scalar>& data,
    const BaseMotionTpl<Scalar>& base, const ConstVectorRef<Scalar>& q,
    const ConstVectorRef<Scalar>& dq, const ConstVectorRef<Scalar>& tau,
    const std::type_identity_t<Vector6<Scalar>>& base_wrench) {
  checkFloatingData(model, data);
  checkSize(model.limbs(), tau, "tau");
  BaseMotionTpl<Scalar> still = base;
  still.acceleration.setZero();
  // h at zero acceleration: ddq is read as zeros from the acceleration buffer (sized 6 + n).
  data.acceleration.setZero();
  floatingRnea(model, data, still, q, dq, data.acceleration.tail(model.numJoints()));
  floatingCrba(model, data, q);
  data.acceleration.template head<6>() = base_wrench - data.tau.template head<6>();
  data.acceleration.tail(model.numJoints()) = tau - data.tau.tail(model.numJoints());
  data.llt.compute(data.M);
  data.llt.solveInPlace(data.acceleration);
  return data.acceleration;
}

}  // namespace dynid
