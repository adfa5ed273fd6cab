// Measuring sine and cosine in ulps (core/lanes.hpp's kernel, core/sin_cos.hpp).
#pragma once

#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <random>
#include <vector>

namespace dynid {

/// |value - exact| in ulps of the double nearest `exact` (long double: 11 more bits than a
/// double, so the measure itself is off by at most 1/2048 ulp).
inline double ulpError(double value, long double exact) {
  int exponent = 0;
  const double nearest = static_cast<double>(exact);
  std::frexp(nearest == 0.0 ? DBL_MIN : nearest, &exponent);
  return static_cast<double>(std::fabs(static_cast<long double>(value) - exact) /
                             std::ldexp(1.0L, exponent - 53));
}

/// Arguments the kernel must get right: uniform ones near the joint angles robots have and over
/// its whole range, and the doubles nearest the multiples of pi/2 (where r cancels).
inline std::vector<double> sinCosTestArguments() {
  std::vector<double> x;
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> near(-10.0, 10.0), far(-1e5, 1e5);
  for (int i = 0; i < 400000; ++i) x.push_back(near(random));
  for (int i = 0; i < 200000; ++i) x.push_back(far(random));
  for (long k = -63661; k <= 63661; k += (std::abs(k) < 1000 ? 1 : 97)) {
    const double at = static_cast<double>(k * (std::numbers::pi_v<long double> / 2));
    x.push_back(at);
    x.push_back(std::nextafter(at, 1e300));
    x.push_back(std::nextafter(at, -1e300));
  }
  for (double tiny : {1e-300, 1e-20, 3e-9, 5e-324, 1e-8}) {
    x.push_back(tiny);
    x.push_back(-tiny);
  }
  while (x.size() % 8 != 0) x.push_back(0.5);
  return x;
}

}  // namespace dynid
