// Lane pairs (core/floating/lane_pairs.hpp): each lane is the 3-vector operation it stands for,
// bit for bit (the same terms in the same order), through the SSE2 shuffles and the generic path.
#include "core/floating/lane_pairs.hpp"

#include <random>

#include <ceres/jet.h>
#include <gtest/gtest.h>

namespace dynid {
namespace {

struct Draws {
  std::mt19937 rng{7};
  std::uniform_real_distribution<double> u{-2.0, 2.0};
  Vector3<double> vector() { return {u(rng), u(rng), u(rng)}; }
  Matrix3<double> matrix() {
    Matrix3<double> m;
    for (int k = 0; k < 9; ++k) m.data()[k] = u(rng);
    return m;
  }
};

// Exact: the lanes must compute the very same floating-point operations as the 3-vector code.
void expectSame(const Vector3<double>& got, const Vector3<double>& want,
                int line = __builtin_LINE()) {
  for (int k = 0; k < 3; ++k) EXPECT_EQ(got[k], want[k]) << "component " << k << ", line " << line;
}

TEST(LanePairs, EachLaneIsTheThreeVectorOperation) {
  Draws d;
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3<double> a = d.vector(), b = d.vector(), t = d.vector();
    const Matrix3<double> r = d.matrix();
    const Pair3<double> p = Pair3<double>::join(a, b);
    expectSame(p.lane(0), a);
    expectSame(p.lane(1), b);
    expectSame(times(r, p).lane(0), transposeTimes(Matrix3<double>(r.transpose()), a));
    expectSame(times(r, p).lane(1), transposeTimes(Matrix3<double>(r.transpose()), b));
    expectSame(transposeTimes(r, p).lane(0), transposeTimes(r, a));
    expectSame(transposeTimes(r, p).lane(1), transposeTimes(r, b));
    expectSame(cross(t, p).lane(0), cross(t, a));
    expectSame(cross(t, p).lane(1), cross(t, b));
    const Pair3<double> q = Pair3<double>::join(t, a);
    expectSame(Pair3<double>::lows(p, q).lane(0), a);
    expectSame(Pair3<double>::lows(p, q).lane(1), t);
    expectSame(Pair3<double>::highs(p, q).lane(0), b);
    expectSame(Pair3<double>::highs(p, q).lane(1), a);
    expectSame((p + q).lane(1), b + a);
    expectSame((p - q).lane(0), a - t);
    expectSame((p * 1.5).lane(1), b * 1.5);
  }
}

TEST(LanePairs, ARateCrossAddsToTheSecondLaneOnly) {
  Draws d;
  for (int k = 0; k < 3; ++k) {
    const Vector3<double> w = d.vector(), dw = d.vector(), v = d.vector(), dv = d.vector();
    const double x = 0.7;
    Vector3<double> e = Vector3<double>::Zero();
    e[k] = x;
    Pair3<double> angular = Pair3<double>::join(w, dw), linear = Pair3<double>::join(v, dv);
    addRateCross(angular, angular, k, x);
    expectSame(angular.lane(0), w);
    // w x (x e_k)'s products with e_k's zeros are +-0: the sums are exact.
    expectSame(angular.lane(1), dw + cross(w, e));
    addRateCross(Pair3<double>::join(w, dw), linear, k, x);  // a prismatic joint's: w into dv
    expectSame(linear.lane(0), v);
    expectSame(linear.lane(1), dv + cross(w, e));
  }
}

TEST(LanePairs, JetsTakeTheGenericPathAndCarryTheirDerivatives) {
  using Jet = ceres::Jet<double, 2>;
  const Vector3<Jet> a(Jet(1.0, 0), Jet(2.0), Jet(3.0, 1)), b(Jet(-1.0), Jet(0.5, 0), Jet(4.0));
  const Vector3<Jet> t(Jet(0.3), Jet(-0.2), Jet(0.1));
  const Pair3<Jet> c = cross(t, Pair3<Jet>::join(a, b));
  const Vector3<Jet> want = cross(t, a);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(c.lane(0)[k].a, want[k].a);
    EXPECT_EQ(c.lane(0)[k].v, want[k].v);
  }
  EXPECT_EQ(Pair3<Jet>::highs(Pair3<Jet>::join(a, b), Pair3<Jet>::zero()).lane(0)[1].v, b[1].v);
}

}  // namespace
}  // namespace dynid
