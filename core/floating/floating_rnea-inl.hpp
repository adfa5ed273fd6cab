// Template bodies of floating_rnea.hpp; include only to instantiate a new Scalar.
#pragma once

#include <algorithm>
#include <type_traits>

#include "core/crba-inl.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/floating/lane_pairs.hpp"
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
/// acceleration (gravity as the base's -g) in its joint frame, the base's in the base frame, as
/// lane pairs (lane_pairs.hpp: the velocity's and the acceleration's halves moved by one
/// instruction each), kept in data.motions. Each body's pairs go to `body` while they are in
/// registers (inverse dynamics: its force; the regressor: its columns), the base body's first as
/// body -1 (in the base frame). Checks the sizes and the Data first (InputError).
template <typename Scalar, typename PerBody>
DYNID_INLINE void forwardPass(const FloatingModelTpl<Scalar>& model, FloatingDataTpl<Scalar>& data,
                              const BaseMotionTpl<Scalar>& base, const ConstVectorRef<Scalar>& q,
                              const ConstVectorRef<Scalar>& dq, const ConstVectorRef<Scalar>& ddq,
                              PerBody&& body) {
  checkFloatingData(model, data);
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  checkSize(limbs, q, "q");
  checkSize(limbs, dq, "dq");
  checkSize(limbs, ddq, "ddq");
  data.base_v = base.twist;
  data.base_a = base.acceleration;
  data.base_a.template tail<3>() -= transposeTimes(base.rotation, model.gravity());
  data.base_motion = MotionPair<Scalar>::of(data.base_v, data.base_a);
  body(-1, data.base_motion);
  const int n = limbs.numJoints();
  setLimbTransforms(model, ld.liMi, q);
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = ld.liMi[i];
    const int p = limbs.parents()[i];
    const MotionPair<Scalar>& parent =
        p < 0 ? data.base_motion : data.motions[static_cast<std::size_t>(p)];
    // iXp m = (R^T w, R^T (v - t x w)) in both lanes; then + S dq, and the acceleration's
    // v x S dq + S ddq.
    MotionPair<Scalar> m{
        transposeTimes(X.rotation, parent.angular),
        transposeTimes(X.rotation, parent.linear - cross(X.translation, parent.angular))};
    const int k = limbs.subspace_index()[i], r = model.revoluteAxes()[i];
    if (r >= 0) {  // revolute about +-e_r: the rates' sign folded in
      const bool plus = model.axisSigns()[i] > 0;
      const Scalar x = plus ? dq[i] : Scalar(-dq[i]);
      const Scalar xdd = plus ? ddq[i] : Scalar(-ddq[i]);
      // The axis a constant in each branch: indexed at run time, the pairs live in memory
      // (Romeo's regressor 4100 -> 3400 ns, ANYmal's inverse dynamics 617 -> 545 ns).
      const auto about = [&]<int R>() DYNID_INLINE_LAMBDA {
        addRateCross(m.angular, m.angular, R, x);
        addRateCross(m.linear, m.linear, R, x);
        m.angular.c[R] += lane_detail::make(x, xdd);
      };
      if (r == 0)
        about.template operator()<0>();
      else if (r == 1)
        about.template operator()<1>();
      else
        about.template operator()<2>();
    } else if (k >= 3) {  // prismatic along e_(k-3): v x (0, e dq) = (0, w x e dq)
      addRateCross(m.angular, m.linear, k - 3, dq[i]);
      m.linear.c[k - 3] += lane_detail::make(dq[i], ddq[i]);
    } else {  // a general axis: the spatial algebra
      Vector6<Scalar> vel = m.velocity(), acc = m.acceleration();
      addJointMotion(limbs, i, dq[i], vel);
      acc += crossJointMotion(limbs, i, vel, dq[i]);
      addJointMotion(limbs, i, ddq[i], acc);
      m = MotionPair<Scalar>::of(vel, acc);
    }
    data.motions[static_cast<std::size_t>(i)] = m;
    body(i, m);
  }
}

/// A body's force f = I a + v x* (I v) as (moment, force) lanes, from its motion's lanes: with
/// I v = (hw, hv) = (I_o w + c x v, m v - c x w), f = (I_o dw + c x dv + w x hw + v x hv,
/// m dv - c x dw + w x hv), c the first moment.
template <typename Scalar>
DYNID_INLINE Pair3<Scalar> bodyForce(const RigidInertia<Scalar>& I, const MotionPair<Scalar>& m) {
  // Both lanes at once: A = (hw, I_o dw + c x dv), B = (hv, m dv - c x dw).
  const Pair3<Scalar> A = times(I.inertia, m.angular) + cross(I.first_moment, m.linear);
  const Pair3<Scalar> B = m.linear * I.mass - cross(I.first_moment, m.angular);
  // + (w x hw, w x hv), then + (v x hv, 0): v x B's lanes, its second dropped.
  const Pair3<Scalar> vB = cross(Vector3<Scalar>(m.linear.lane(0)), B);
  return Pair3<Scalar>::highs(A, B) +
         cross(Vector3<Scalar>(m.angular.lane(0)), Pair3<Scalar>::lows(A, B)) +
         Pair3<Scalar>::lows(vB, Pair3<Scalar>::zero());
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
  Pair3<Scalar> base_force;
  floating_detail::forwardPass(model, data, base, q, dq, ddq,
                               [&](int i, const MotionPair<Scalar>& m) DYNID_INLINE_LAMBDA {
                                 if (i < 0)
                                   base_force = floating_detail::bodyForce(model.baseInertia(), m);
                                 else
                                   data.forces[static_cast<std::size_t>(i)] =
                                       floating_detail::bodyForce(limbs.frame_inertias()[i], m);
                               });
  const int n = limbs.numJoints();
  // Backward pass: tau_i = S_i^T f_i (+ drives); each force carried to its parent, the roots'
  // to the base body, whose total is the wrench the motion needs.
  for (int i = n - 1; i >= 0; --i) {
    const Pair3<Scalar>& f = data.forces[static_cast<std::size_t>(i)];
    const int r = model.revoluteAxes()[i];
    Scalar tau_i;
    if (r < 0) {
      Vector6<Scalar> f6;
      f6 << f.lane(0), f.lane(1);
      tau_i = projectOnJoint(limbs, i, f6);
    } else {
      tau_i = model.axisSigns()[i] > 0 ? f.c[r](0) : Scalar(-f.c[r](0));
    }
    if (limbs.driveTerms().any()) tau_i += driveTorque(limbs, i, dq[i], ddq[i]);
    data.tau[6 + i] = tau_i;
    // f_p += pXi* f_i = (R n + t x R f, R f), both lanes' rotations at once.
    const int p = limbs.parents()[i];
    const Pose<Scalar>& X = ld.liMi[i];
    const Pair3<Scalar> moved = times(X.rotation, f);
    // (t x R f, 0): t x both lanes, the first dropped.
    const Pair3<Scalar> offset =
        Pair3<Scalar>::highs(cross(X.translation, moved), Pair3<Scalar>::zero());
    (p < 0 ? base_force : data.forces[static_cast<std::size_t>(p)]) += moved + offset;
  }
  data.base_f << base_force.lane(0), base_force.lane(1);
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
