#include "core/lanes.hpp"

#include "core/drive_terms.hpp"

#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "tests/common/ulp.hpp"

namespace dynid {
namespace {

// Faithful rounding (< 1 ulp) is the kernel's contract. The largest error seen here is 0.77 ulp
// (the C library's 0.56); a kernel that lost a term or r's low part fails (1.03 and 1.4 ulp).
TEST(Lanes, SinCosIsWithinAnUlpOfTheExactValues) {
  const std::vector<double> x = sinCosTestArguments();
  double worst_sin = 0.0, worst_cos = 0.0, c_library_sin = 0.0, c_library_cos = 0.0;
  for (std::size_t i = 0; i < x.size(); i += 4) {
    Lanes<4> in, s, c;
    for (int l = 0; l < 4; ++l) in.set(l, x[i + static_cast<std::size_t>(l)]);
    sinCos(in, s, c);
    for (int l = 0; l < 4; ++l) {
      const long double xl = x[i + static_cast<std::size_t>(l)];
      worst_sin = std::max(worst_sin, ulpError(s[l], sinl(xl)));
      worst_cos = std::max(worst_cos, ulpError(c[l], cosl(xl)));
      double s_c = 0.0, c_c = 0.0;
      ::sincos(x[i + static_cast<std::size_t>(l)], &s_c, &c_c);
      c_library_sin = std::max(c_library_sin, ulpError(s_c, sinl(xl)));
      c_library_cos = std::max(c_library_cos, ulpError(c_c, cosl(xl)));
    }
  }
  std::cout << "largest errors over " << x.size() << " arguments [ulp]: sin " << worst_sin
            << ", cos " << worst_cos << " (the C library's sincos: " << c_library_sin << ", "
            << c_library_cos << ")\n";
  EXPECT_LT(worst_sin, 1.0);
  EXPECT_LT(worst_cos, 1.0);
  // Near a multiple of pi/2 the result is r itself: cos of the double nearest pi/2 to the bit.
  Lanes<2> s, c;
  sinCos(Lanes<2>(std::numbers::pi / 2), s, c);
  EXPECT_EQ(c[0], 6.123233995736766e-17);
  EXPECT_EQ(s[0], 1.0);
}

TEST(Lanes, SinCosKeepsSignedZerosAndHandsTheRestToTheCLibrary) {
  Lanes<2> s, c;
  const Lanes<2> negative_zero(-0.0);
  EXPECT_TRUE(std::signbit(negative_zero[0]) && std::signbit(negative_zero[1]));
  EXPECT_TRUE(std::signbit(Lanes<4>(-0.0)[3]) && std::signbit(Lanes<8>(-0.0)[7]));
  sinCos(negative_zero, s, c);
  EXPECT_TRUE(std::signbit(s[0]) && std::signbit(s[1]));
  EXPECT_EQ(c[0], 1.0);
  sinCos(Lanes<2>(0.0), s, c);
  EXPECT_FALSE(std::signbit(s[0]));
  const double inf = std::numeric_limits<double>::infinity();
  for (double beyond :
       {1e5 * (1 + 1e-15), -3e7, 1e300, inf, -inf, std::numeric_limits<double>::quiet_NaN()}) {
    Lanes<2> in;
    in.set(0, beyond);
    in.set(1, 0.25);
    sinCos(in, s, c);
    double s_c = 0.0, c_c = 0.0;
    ::sincos(beyond, &s_c, &c_c);
    if (std::isnan(s_c)) {
      EXPECT_TRUE(std::isnan(s[0]) && std::isnan(c[0])) << beyond;
    } else {
      EXPECT_EQ(s[0], s_c) << beyond;
      EXPECT_EQ(c[0], c_c) << beyond;
    }
    Lanes<2> alone;
    sinCos(Lanes<2>(0.25), alone, c);
    EXPECT_EQ(s[1], alone[0]) << "the in-range lane beside " << beyond;
    sinCos(in, in, c);  // sin written over its argument
    EXPECT_EQ(in[1], alone[0]);
    EXPECT_TRUE(in[0] == s[0] || (std::isnan(in[0]) && std::isnan(s[0]))) << beyond;
  }
}

// The GC rollouts rely on this: a lane's result is the same bits in any lane of any width
// (search/gc_error.hpp), whatever its neighbours hold.
TEST(Lanes, SinCosOfALaneDependsOnItsArgumentAlone) {
  const std::vector<double> x = sinCosTestArguments();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < x.size(); i += 8) {
    Lanes<8> in8, s8, c8;
    for (int l = 0; l < 8; ++l) in8.set(l, x[i + static_cast<std::size_t>(l)]);
    sinCos(in8, s8, c8);
    for (int l = 0; l < 8; ++l) {
      // The same argument in lane 1 of two lanes, beside one the C library takes.
      Lanes<2> in2, s2, c2;
      in2.set(0, l % 2 == 0 ? nan : 3e9);
      in2.set(1, in8[l]);
      sinCos(in2, s2, c2);
      Lanes<4> in4, s4, c4;
      for (int m = 0; m < 4; ++m) in4.set(m, x[i + static_cast<std::size_t>((l + m) % 8)]);
      sinCos(in4, s4, c4);
      ASSERT_EQ(s2[1], s8[l]) << in8[l];
      ASSERT_EQ(c2[1], c8[l]) << in8[l];
      ASSERT_EQ(s4[0], s8[l]) << in8[l];
      ASSERT_EQ(c4[0], c8[l]) << in8[l];
      ASSERT_EQ(sin(in4)[0], s8[l]);
      ASSERT_EQ(cos(in4)[0], c8[l]);
    }
  }
}

TEST(Lanes, SignOutsideIsTheScalarRuleInEveryLane) {
  const double rest = 1e-3;
  const double x[4] = {5e-4, -2e-3, 1e-3, std::numeric_limits<double>::quiet_NaN()};
  Lanes<4> in;
  for (int l = 0; l < 4; ++l) in.set(l, x[l]);
  const Lanes<4> out = signOutside(in, rest);
  for (int l = 0; l < 3; ++l) EXPECT_EQ(out[l], signOutside(x[l], rest)) << l;
  EXPECT_EQ(out[3], 0.0);  // NaN: 0, as the scalar rule gives
  EXPECT_EQ(signOutside(x[3], rest), 0.0);
}

}  // namespace
}  // namespace dynid
