#include "core/sin_cos.hpp"

#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/lanes.hpp"
#include "tests/common/ulp.hpp"

namespace dynid {
namespace {

std::vector<int> availableIsas() {
  std::vector<int> isas;
  for (int isa = kBuildIsa; isa <= cpuLaneIsa(); ++isa) isas.push_back(isa);
  return isas;
}

// Faithful rounding (< 1 ulp) is the contract, on every instruction set the CPU has. Estrin's
// scheme rounds the series differently from the rollouts' Horner kernel (0.77 ulp at most there):
// the largest errors are printed.
TEST(SinCosBlock, IsWithinAnUlpOfTheExactValuesOnEveryInstructionSet) {
  const std::vector<double> x = sinCosTestArguments();  // a multiple of 8 long
  for (int isa : availableIsas()) {
    double worst_sin = 0.0, worst_cos = 0.0;
    SinCosBlock block;
    for (std::size_t i = 0; i < x.size(); i += SinCosBlock::kSize) {
      sinCosBlock(&x[i], SinCosBlock::kSize, block, isa);
      for (int l = 0; l < SinCosBlock::kSize; ++l) {
        const long double xl = x[i + static_cast<std::size_t>(l)];
        worst_sin = std::max(worst_sin, ulpError(block.s[l], sinl(xl)));
        worst_cos = std::max(worst_cos, ulpError(block.c[l], cosl(xl)));
      }
    }
    std::cout << "instruction set " << isa << ", largest errors over " << x.size()
              << " arguments [ulp]: sin " << worst_sin << ", cos " << worst_cos << "\n";
    EXPECT_LT(worst_sin, 1.0) << isa;
    EXPECT_LT(worst_cos, 1.0) << isa;
  }
  SinCosBlock block;
  const double half_pi = std::numbers::pi / 2;
  sinCosBlock(&half_pi, 1, block);
  EXPECT_EQ(block.c[0], 6.123233995736766e-17);  // r itself near a multiple of pi/2, to the bit
  EXPECT_EQ(block.s[0], 1.0);
}

// Every count (a part of each register, on 2, 4 and 8 lanes) and every instruction set gives each
// argument the bits it gets alone on the build's own: a result depends on its argument only. The
// arguments past the count are not read: the last block ends at the end of a page, the next one
// unmapped.
TEST(SinCosBlock, GivesTheSameBitsForAnyCountAndInstructionSet) {
  const long page = sysconf(_SC_PAGESIZE);
  void* mapped = mmap(nullptr, static_cast<std::size_t>(2 * page), PROT_READ | PROT_WRITE,
                      MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(mapped, MAP_FAILED);
  ASSERT_EQ(mprotect(static_cast<char*>(mapped) + page, static_cast<std::size_t>(page), PROT_NONE),
            0);
  double* const page_end = reinterpret_cast<double*>(static_cast<char*>(mapped) + page);
  const std::vector<double> values = {
      -3.0, 0.37, -0.0, 2e5, std::numeric_limits<double>::quiet_NaN(), 1.5707963267948966,
      12.5, -7.25};
  std::vector<double> s_alone(values.size()), c_alone(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    SinCosBlock one;
    sinCosBlock(&values[i], 1, one, kBuildIsa);
    s_alone[i] = one.s[0], c_alone[i] = one.c[0];
  }
  for (int isa : availableIsas())
    for (int n = 0; n <= SinCosBlock::kSize; ++n) {
      double* const x = page_end - n;
      for (int i = 0; i < n; ++i) x[i] = values[static_cast<std::size_t>(i)];
      SinCosBlock block;
      sinCosBlock(x, n, block, isa);
      for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (std::isnan(values[k])) {
          EXPECT_TRUE(std::isnan(block.s[i]) && std::isnan(block.c[i])) << isa << " " << n;
          continue;
        }
        EXPECT_EQ(std::signbit(block.s[i]), std::signbit(s_alone[k])) << isa << " " << n;
        EXPECT_EQ(block.s[i], s_alone[k]) << isa << " " << n << " " << i;
        EXPECT_EQ(block.c[i], c_alone[k]) << isa << " " << n << " " << i;
      }
    }
  munmap(mapped, static_cast<std::size_t>(2 * page));
  EXPECT_TRUE(std::signbit(s_alone[2]));  // sin(-0) = -0
  double s_c = 0.0, c_c = 0.0;
  ::sincos(values[3], &s_c, &c_c);  // beyond kSinCosRange: the C library's
  EXPECT_EQ(s_alone[3], s_c);
  EXPECT_EQ(c_alone[3], c_c);
}

TEST(SinCosBlock, RefusesAnInstructionSetTheCpuOrBuildLacksAndTooManyArguments) {
  const double x[SinCosBlock::kSize + 1] = {};
  SinCosBlock block;
  EXPECT_THROW(sinCosBlock(x, 1, block, cpuLaneIsa() + 1), InputError);
  EXPECT_THROW(sinCosBlock(x, 1, block, -1), InputError);
  EXPECT_THROW(sinCosBlock(x, SinCosBlock::kSize + 1, block), InputError);
  EXPECT_THROW(sinCosBlock(x, -1, block, kBuildIsa), InputError);
}

}  // namespace
}  // namespace dynid
