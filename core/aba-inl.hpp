#pragma once

#include <array>
#include <utility>

#include "core/aba.hpp"
#include "core/checks.hpp"
#include "core/friction.hpp"

namespace dynid {

namespace aba_detail {
/// parent += pXi* Ia iXp, with Ia = IA - U U^T / D the articulated inertia the child hands on and
/// pXi* = [[R, [p]x R], [0, R]]: rotate IA's three 3x3 blocks, shift them by p, then subtract
/// U' U'^T / D with U' = pXi* U. The congruence of IA does not wait for the division by D.
/// parent = base + that (base is the parent's inertia so far: parent itself, or its rigid-body
/// inertia for the first child, which saves pass 1 a copy); writes U' to U_parent (pass 3 uses it)
/// and adds pXi* pa, the child's bias force handed on, to bias_parent.
template <typename Scalar>
DYNID_FLATTEN void addTransformedInertia(const Pose<Scalar>& X, const Matrix6<Scalar>& IA,
                                         const Vector6<Scalar>& U, const Scalar& inv_d,
                                         const Matrix6<Scalar>& base, Matrix6<Scalar>& parent,
                                         Vector6<Scalar>& U_parent, const Vector6<Scalar>& pa,
                                         Vector6<Scalar>& bias_parent) {
  const Matrix3<Scalar>& R = X.rotation;
  // A = R IA_tl R^T, B = R IA_tr R^T, C = R IA_br R^T.
  Matrix3<Scalar> half;
  half.noalias() = R * IA.template topLeftCorner<3, 3>();
  Matrix3<Scalar> A;
  A.noalias() = half * R.transpose();
  half.noalias() = R * IA.template topRightCorner<3, 3>();
  Matrix3<Scalar> B;
  B.noalias() = half * R.transpose();
  half.noalias() = R * IA.template bottomRightCorner<3, 3>();
  Matrix3<Scalar> C;
  C.noalias() = half * R.transpose();
  // [[1, P], [0, 1]] [[A, B], [B^T, C]] [[1, 0], [P^T, 1]] with P = [p]x, P^T = -P:
  // B2 = B + P C, A' = A + P B^T - B2 P, each product with P a set of cross products with p.
  const Vector3<Scalar>& p = X.translation;
  Matrix3<Scalar> B2;
  for (int j = 0; j < 3; ++j) B2.col(j) = B.col(j) + cross(p, C.col(j));
  for (int j = 0; j < 3; ++j) A.col(j) += cross(p, B.row(j).transpose());
  for (int r = 0; r < 3; ++r) A.row(r) += cross(p, B2.row(r).transpose()).transpose();
  const Vector3<Scalar> Uf = R * U.template tail<3>();
  const Vector3<Scalar> Un = R * U.template head<3>() + cross(p, Uf);
  const Vector3<Scalar> Vn = Un * inv_d, Vf = Uf * inv_d;
  A.noalias() -= Un * Vn.transpose();
  B2.noalias() -= Un * Vf.transpose();
  C.noalias() -= Uf * Vf.transpose();
  parent.template topLeftCorner<3, 3>() = base.template topLeftCorner<3, 3>() + A;
  parent.template topRightCorner<3, 3>() = base.template topRightCorner<3, 3>() + B2;
  parent.template bottomLeftCorner<3, 3>() =
      base.template bottomLeftCorner<3, 3>() + B2.transpose();
  parent.template bottomRightCorner<3, 3>() = base.template bottomRightCorner<3, 3>() + C;
  U_parent.template head<3>() = Un;
  U_parent.template tail<3>() = Uf;
  // The parent's bias force += pXi* pa.
  const Vector3<Scalar> f = R * pa.template tail<3>();
  const Vector3<Scalar> n_f = R * pa.template head<3>() + cross(p, f);
  bias_parent.template head<3>() += n_f;
  bias_parent.template tail<3>() += f;
}

/// G M G^T for G = [[g00, g01, 0], [g10, g11, 0], [0, 0, g22]] (a rotation about z with signed
/// rows): rows 0 and 1 mix, row 2 scales, then the same for the columns.
template <typename Scalar, typename Block>
DYNID_INLINE Matrix3<Scalar> rotateAboutZ(const Scalar& g00, const Scalar& g01, const Scalar& g10,
                                          const Scalar& g11, const Scalar& g22,
                                          const Eigen::MatrixBase<Block>& M) {
  Matrix3<Scalar> T, out;
  T.row(0) = g00 * M.row(0) + g01 * M.row(1);
  T.row(1) = g10 * M.row(0) + g11 * M.row(1);
  T.row(2) = g22 * M.row(2);
  out.col(0) = g00 * T.col(0) + g01 * T.col(1);
  out.col(1) = g10 * T.col(0) + g11 * T.col(1);
  out.col(2) = g22 * T.col(2);
  return out;
}

/// The upper triangle of a symmetric 3x3 matrix, (0,0), (0,1), (0,2), (1,1), (1,2), (2,2).
template <typename Scalar>
struct Symmetric3 {
  static constexpr int index(int a, int b) {
    const int i = a < b ? a : b, j = a < b ? b : a;
    return i == 0 ? j : (i == 1 ? 2 + j : 5);
  }
  DYNID_INLINE Scalar& operator()(int a, int b) { return e[index(a, b)]; }
  DYNID_INLINE const Scalar& operator()(int a, int b) const { return e[index(a, b)]; }
  Scalar e[6];
};

/// rotateAboutZ for a symmetric M, read from and written to its upper triangle: 7 of T = G M's
/// entries and 6 of the result's.
template <typename Scalar, typename Block>
DYNID_INLINE Symmetric3<Scalar> rotateSymmetricAboutZ(const Scalar& g00, const Scalar& g01,
                                                      const Scalar& g10, const Scalar& g11,
                                                      const Scalar& g22,
                                                      const Eigen::MatrixBase<Block>& M) {
  const Scalar t00 = g00 * M(0, 0) + g01 * M(0, 1), t01 = g00 * M(0, 1) + g01 * M(1, 1),
               t02 = g00 * M(0, 2) + g01 * M(1, 2);
  const Scalar t10 = g10 * M(0, 0) + g11 * M(0, 1), t11 = g10 * M(0, 1) + g11 * M(1, 1),
               t12 = g10 * M(0, 2) + g11 * M(1, 2);
  Symmetric3<Scalar> out;
  out(0, 0) = g00 * t00 + g01 * t01;
  out(0, 1) = g10 * t00 + g11 * t01;
  out(1, 1) = g10 * t10 + g11 * t11;
  out(0, 2) = g22 * t02;
  out(1, 2) = g22 * t12;
  out(2, 2) = g22 * (g22 * M(2, 2));
  return out;
}

/// addTransformedInertia for a revolute z joint whose frame placement rotates by a signed
/// permutation, kAxisPermutations[K] = pi (Model::placement_permutation). Then R = Pi G with G =
/// Pi^T R a rotation about z with signed rows, and pXi* = Rot(Pi) T(s) Rot(G), s = det(Pi) Pi^T p
/// (Model::placement_shift), because [p]x Pi = det(Pi) Pi [Pi^T p]x. Rotating about z and
/// permuting the result into the parent costs about half the multiplications of a general
/// rotation. The permutation is a template parameter, so the parent's entries are addressed at
/// compile time.
template <int K, typename Scalar>
DYNID_FLATTEN void addTransformedInertiaPermuted(const Pose<Scalar>& X, const Vector3<Scalar>& s,
                                                 const Matrix6<Scalar>& IA,
                                                 const Vector6<Scalar>& U, const Scalar& inv_d,
                                                 const Matrix6<Scalar>& base,
                                                 Matrix6<Scalar>& parent, Vector6<Scalar>& U_parent,
                                                 const Vector6<Scalar>& pa,
                                                 Vector6<Scalar>& bias_parent) {
  constexpr int p0 = kAxisPermutations[K][0], p1 = kAxisPermutations[K][1],
                p2 = kAxisPermutations[K][2];
  // G(j, :) = R(pi^-1(j), :).
  constexpr int r0 = p0 == 0 ? 0 : (p1 == 0 ? 1 : 2), r1 = p0 == 1 ? 0 : (p1 == 1 ? 1 : 2),
                r2 = p0 == 2 ? 0 : (p1 == 2 ? 1 : 2);
  const Matrix3<Scalar>& R = X.rotation;
  const Scalar g00 = R(r0, 0), g01 = R(r0, 1), g10 = R(r1, 0), g11 = R(r1, 1), g22 = R(r2, 2);
  // IA's diagonal blocks, and so A and C, are symmetric: their upper triangles alone (IA is read
  // there too), a third fewer products than whole blocks.
  Symmetric3<Scalar> A =
      rotateSymmetricAboutZ(g00, g01, g10, g11, g22, IA.template topLeftCorner<3, 3>());
  const Matrix3<Scalar> B =
      rotateAboutZ(g00, g01, g10, g11, g22, IA.template topRightCorner<3, 3>());
  Symmetric3<Scalar> C =
      rotateSymmetricAboutZ(g00, g01, g10, g11, g22, IA.template bottomRightCorner<3, 3>());
  // B2 = B + [s]x C; A' = A + [s]x B^T - B2 [s]x: A'(a, b) = A(a, b) + (s x B(b, :))_a +
  // (s x B2(a, :))_b.
  const auto crossEntry = [&](int a, const Scalar& x1, const Scalar& x2) {
    // (s x x)_a from x's entries a + 1 and a + 2 (mod 3).
    return s[(a + 1) % 3] * x2 - s[(a + 2) % 3] * x1;
  };
  Matrix3<Scalar> B2;
  for (int j = 0; j < 3; ++j)
    for (int a = 0; a < 3; ++a)
      B2(a, j) = B(a, j) + crossEntry(a, C((a + 1) % 3, j), C((a + 2) % 3, j));
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b)
      A(a, b) += crossEntry(a, B(b, (a + 1) % 3), B(b, (a + 2) % 3)) +
                 crossEntry(b, B2(a, (b + 1) % 3), B2(a, (b + 2) % 3));
  // - (T(s) Rot(G) U)(T(s) Rot(G) U)^T / D, applied after the congruence of IA so that the
  // division by D overlaps with it.
  const Vector3<Scalar> Uf(g00 * U[3] + g01 * U[4], g10 * U[3] + g11 * U[4], g22 * U[5]);
  const Vector3<Scalar> Un =
      Vector3<Scalar>(g00 * U[0] + g01 * U[1], g10 * U[0] + g11 * U[1], g22 * U[2]) + cross(s, Uf);
  const Vector3<Scalar> Vn = Un * inv_d, Vf = Uf * inv_d;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      A(a, b) -= Un[a] * Vn[b];
      C(a, b) -= Uf[a] * Vf[b];
    }
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) B2(a, b) -= Un[a] * Vf[b];
  // parent = base + Rot(Pi) M Rot(Pi)^T: entry (a, b) of each block takes M's (pi(a), pi(b)). The
  // upper triangle is computed and mirrored, so the parent is exactly symmetric.
  constexpr int pi[3] = {p0, p1, p2};
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      parent(a, b) = parent(b, a) = base(a, b) + A(pi[a], pi[b]);
      parent(a + 3, b + 3) = parent(b + 3, a + 3) = base(a + 3, b + 3) + C(pi[a], pi[b]);
    }
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a)
      parent(a, b + 3) = parent(b + 3, a) = base(a, b + 3) + B2(pi[a], pi[b]);
  U_parent << Un(p0), Un(p1), Un(p2), Uf(p0), Uf(p1), Uf(p2);
  // The parent's bias force += pXi* pa = (Pi (G n + s x G f), Pi G f), n and f pa's halves.
  const Vector3<Scalar> f(g00 * pa[3] + g01 * pa[4], g10 * pa[3] + g11 * pa[4], g22 * pa[5]);
  const Vector3<Scalar> n =
      Vector3<Scalar>(g00 * pa[0] + g01 * pa[1], g10 * pa[0] + g11 * pa[1], g22 * pa[2]) +
      cross(s, f);
  bias_parent.template head<3>() += Vector3<Scalar>(n(p0), n(p1), n(p2));
  bias_parent.template tail<3>() += Vector3<Scalar>(f(p0), f(p1), f(p2));
}

/// addTransformedInertiaPermuted<K> for K = 0..5, indexed by Model::placement_permutation.
template <typename Scalar, int... K>
constexpr auto permutedTransforms(std::integer_sequence<int, K...>) {
  return std::array{&addTransformedInertiaPermuted<K, Scalar>...};
}
template <typename Scalar>
inline constexpr auto kPermutedTransforms =
    permutedTransforms<Scalar>(std::make_integer_sequence<int, 6>());

/// What a floating base hands the passes (core/floating/floating_aba.hpp): the root bodies' parent
/// is the base, whose twist, articulated inertia, bias force and acceleration these are. A fixed
/// base passes none (kFloating false): its roots' parent is still.
template <typename Scalar>
struct AbaRoot {
  const Vector6<Scalar>* twist = nullptr;         // pass 1: the base's twist (base frame)
  Matrix6<Scalar>* inertia = nullptr;             // pass 2: the base's articulated inertia so far
  Vector6<Scalar>* bias = nullptr;                // pass 2: ... and bias force
  const Vector6<Scalar>* acceleration = nullptr;  // pass 3: the base's (gravity as -g)
};

/// ABA's pass 1 (velocities, bias forces, articulated inertias initialised), pass 2 (leaves to
/// root: U, D, u, the parents' inertias and bias forces) and pass 3 (root to leaves: ddq). With
/// kFloating, the roots hang from `root`'s base.
template <bool kFloating = false, typename Scalar>
DYNID_INLINE void abaVelocityPass(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                  const ConstVectorRef<Scalar>& dq,
                                  const ConstVectorRef<Scalar>& tau,
                                  const AbaRoot<Scalar>& root = {});
template <bool kFloating = false, typename Scalar>
DYNID_INLINE void abaInertiaPass(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                 const AbaRoot<Scalar>& root = {});
template <bool kFloating = false, typename Scalar>
DYNID_INLINE void abaAccelerationPass(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                      const AbaRoot<Scalar>& root = {});

/// ABA's three passes with data.liMi already holding the joint transforms at q (the sizes checked
/// by the caller). Inlined into aba and into abaAtTransforms.
template <typename Scalar>
DYNID_INLINE const VectorX<Scalar>& abaPasses(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                              const ConstVectorRef<Scalar>& dq,
                                              const ConstVectorRef<Scalar>& tau);

/// aba with data.liMi already holding the joint transforms at q (RK4's later stages form them by
/// angle addition). Kept out of line: RK4 calls it four times, and four inlined copies of the
/// passes made the step 30 % slower (instruction cache).
template <typename Scalar>
DYNID_NOINLINE DYNID_FLATTEN const VectorX<Scalar>& abaAtTransforms(
    const ModelTpl<Scalar>& model, DataTpl<Scalar>& data, const ConstVectorRef<Scalar>& dq,
    const ConstVectorRef<Scalar>& tau) {
  return abaPasses(model, data, dq, tau);
}

}  // namespace aba_detail

template <typename Scalar>
const VectorX<Scalar>& aba(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                           const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                           const ConstVectorRef<Scalar>& tau) {
  checkState(model, data, q, dq, tau, "tau");
  // The joint transforms first (see rnea): independent sin/cos calls overlap.
  for (int i = 0; i < model.numJoints(); ++i) setJointTransform(model, i, q[i], data.liMi[i]);
  return aba_detail::abaPasses(model, data, dq, tau);
}

/// Pass 1: velocities v_i, velocity-product accelerations c_i = v_i x S dq, and the rigid-body
/// inertias and bias forces pA_i = v_i x* I v_i.
template <bool kFloating, typename Scalar>
DYNID_INLINE void aba_detail::abaVelocityPass(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                              const ConstVectorRef<Scalar>& dq,
                                              const ConstVectorRef<Scalar>& tau,
                                              const AbaRoot<Scalar>& root) {
  const int n = model.numJoints();
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = data.liMi[i];
    const int p = model.parents()[i];
    const Vector6<Scalar>& S = model.motion_subspaces()[i];
    const Vector3<Scalar> sw = S.template head<3>() * dq[i], sv = S.template tail<3>() * dq[i];
    Vector3<Scalar> w, vl;
    if (!kFloating && p < 0) {
      w = sw;
      vl = sv;
      data.c[i].setZero();
    } else {
      // v = iXp v_p + S dq; c = v x S dq = (iXp v_p) x S dq, since (S dq) x (S dq) = 0.
      const Vector6<Scalar>& parent = kFloating && p < 0 ? *root.twist : data.v[p];
      const Vector3<Scalar> wp = parent.template head<3>(), vp = parent.template tail<3>();
      const Vector3<Scalar> wj = X.rotation.transpose() * wp;
      const Vector3<Scalar> vj = X.rotation.transpose() * (vp - cross(X.translation, wp));
      data.c[i].template head<3>() = cross(wj, sw);
      data.c[i].template tail<3>() = cross(vj, sw) + cross(wj, sv);
      w = wj + sw;
      vl = vj + sv;
    }
    data.v[i].template head<3>() = w;
    data.v[i].template tail<3>() = vl;
    // pA = v x* (I v), I v = (Ibar w + h x vl, m vl - h x w).
    const RigidInertia<Scalar>& I = model.frame_inertias()[i];
    const Vector3<Scalar> hw = I.inertia * w + cross(I.first_moment, vl);
    const Vector3<Scalar> hv = I.mass * vl - cross(I.first_moment, w);
    data.bias_force[i].template head<3>() = cross(w, hw) + cross(vl, hv);
    data.bias_force[i].template tail<3>() = cross(w, hv);
    data.articulated_written[i] = 0;  // IA_i is the rigid-body inertia until a child adds to it
    data.u[i] = tau[i] - jointFriction(model, i, dq[i]);
  }
}

/// Pass 2 (leaves to root): U = IA S, D = S^T U + Ia, u = tau - S^T pA; the parent receives
/// IA - U U^T / D and pA + Ia c + U u / D.
template <bool kFloating, typename Scalar>
DYNID_INLINE void aba_detail::abaInertiaPass(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                             const AbaRoot<Scalar>& root) {
  const int n = model.numJoints();
  for (int i = n - 1; i >= 0; --i) {
    // A joint no child has added to (a leaf) reads its rigid-body inertia in place.
    const Matrix6<Scalar>& IA = data.articulated_written[i] ? data.articulated_inertia[i]
                                                            : model.frame_inertia_matrices()[i];
    const int k = model.subspace_index()[i];
    if (k >= 0)
      data.U[i] = IA.col(k);
    else
      data.U[i].noalias() = IA * model.motion_subspaces()[i];
    data.D[i] = projectOnJoint(model, i, data.U[i]);
    if (model.driveTerms().inertial()) data.D[i] += driveInertia(model, i);
    const Scalar inv_d = Scalar(1) / data.D[i];
    data.D_inv[i] = inv_d;
    data.u[i] -= projectOnJoint(model, i, data.bias_force[i]);
    const int p = model.parents()[i];
    if (!kFloating && p < 0) continue;
    // pa = pA + Ia c + U u / D with Ia c = IA c - U (U . c) / D. Pass 3 needs u - U . c too.
    data.u_minus_Uc[i] = data.u[i] - data.U[i].dot(data.c[i]);
    Vector6<Scalar> pa = data.bias_force[i];
    pa.noalias() += IA * data.c[i];
    pa += data.U[i] * (data.u_minus_Uc[i] * inv_d);
    const Pose<Scalar>& X = data.liMi[i];
    // A floating base's inertia starts as its rigid-body inertia (the caller's).
    const bool on_base = kFloating && p < 0;
    Matrix6<Scalar>& parent = on_base ? *root.inertia : data.articulated_inertia[p];
    Vector6<Scalar>& bias_parent = on_base ? *root.bias : data.bias_force[p];
    // The first child (the highest index) starts from the parent's rigid-body inertia.
    const Matrix6<Scalar>& base =
        on_base || data.articulated_written[p] ? parent : model.frame_inertia_matrices()[p];
    if (!on_base) data.articulated_written[p] = 1;
    const Vector3<Scalar>& s = model.placement_shift()[i];
    const Vector6<Scalar>& U = data.U[i];
    Vector6<Scalar>& Up = data.U_parent[i];
    const int permutation = model.placement_permutation()[i];
    if (permutation >= 0)
      kPermutedTransforms<Scalar>[permutation](X, s, IA, U, inv_d, base, parent, Up, pa,
                                               bias_parent);
    else
      addTransformedInertia(X, IA, U, inv_d, base, parent, Up, pa, bias_parent);
  }
}

/// Pass 3 (root to leaves): a' = iXp a_p + c, ddq = (u - U^T a') / D, a = a' + S ddq. With
/// U^T iXp a_p = (pXi* U)^T a_p (pass 2's U_parent), ddq needs only a dot product with a_p, and
/// the transform of a_p runs beside it: the chain from joint to joint is shorter.
template <bool kFloating, typename Scalar>
DYNID_INLINE void aba_detail::abaAccelerationPass(const ModelTpl<Scalar>& model,
                                                  DataTpl<Scalar>& data,
                                                  const AbaRoot<Scalar>& root) {
  const int n = model.numJoints();
  for (int i = 0; i < n; ++i) {
    const int p = model.parents()[i];
    const Pose<Scalar>& X = data.liMi[i];
    Vector3<Scalar> dw, dv;
    Scalar ddq;
    if (!kFloating && p < 0) {
      dw = data.c[i].template head<3>();
      dv.noalias() = X.rotation.transpose() * (-model.gravity());
      dv += data.c[i].template tail<3>();
      const Scalar ua = data.U[i].template head<3>().dot(dw) + data.U[i].template tail<3>().dot(dv);
      ddq = (data.u[i] - ua) * data.D_inv[i];
    } else {
      const Vector6<Scalar>& parent = kFloating && p < 0 ? *root.acceleration : data.a[p];
      const Vector3<Scalar> dwp = parent.template head<3>(), dvp = parent.template tail<3>();
      const Scalar ua = data.U_parent[i].template head<3>().dot(dwp) +
                        data.U_parent[i].template tail<3>().dot(dvp);
      ddq = (data.u_minus_Uc[i] - ua) * data.D_inv[i];
      dw.noalias() = X.rotation.transpose() * dwp;
      dv.noalias() = X.rotation.transpose() * (dvp - cross(X.translation, dwp));
      dw += data.c[i].template head<3>();
      dv += data.c[i].template tail<3>();
    }
    data.ddq[i] = ddq;
    const Vector6<Scalar>& S = model.motion_subspaces()[i];
    data.a[i].template head<3>() = dw + S.template head<3>() * ddq;
    data.a[i].template tail<3>() = dv + S.template tail<3>() * ddq;
  }
}

template <typename Scalar>
DYNID_INLINE const VectorX<Scalar>& aba_detail::abaPasses(const ModelTpl<Scalar>& model,
                                                          DataTpl<Scalar>& data,
                                                          const ConstVectorRef<Scalar>& dq,
                                                          const ConstVectorRef<Scalar>& tau) {
  // Every 6-vector is built and read as its angular and linear 3-vector halves, and S x is added
  // as arithmetic on S's halves rather than by writing one entry: a 6-vector written entry by
  // entry and then loaded as packed pairs stalls store-to-load forwarding (see rnea).
  //
  abaVelocityPass(model, data, dq, tau);
  abaInertiaPass(model, data);
  abaAccelerationPass(model, data);
  return data.ddq;
}

}  // namespace dynid
