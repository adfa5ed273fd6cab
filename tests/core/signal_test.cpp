#include "core/signal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/errors.hpp"

namespace dynid {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::VectorXd sine(int n, double rate, double f, double phase = 0.0) {
  Eigen::VectorXd x(n);
  for (int k = 0; k < n; ++k) x[k] = std::sin(2 * kPi * f * k / rate + phase);
  return x;
}

TEST(Signal, ButterworthIsMinus3DbAtTheCutoffAndFlatAtDc) {
  for (int order : {1, 2, 3, 4, 5, 8}) {
    for (double cutoff : {1.0, 10.0, 40.0}) {
      const std::vector<Biquad> f = butterworthLowPass(order, cutoff, 200.0);
      EXPECT_EQ(static_cast<int>(f.size()), (order + 1) / 2);
      // The bilinear transform with pre-warping puts |H| = 1/sqrt(2) exactly at the cutoff.
      EXPECT_NEAR(magnitudeResponse(f, cutoff, 200.0), 1.0 / std::sqrt(2.0), 1e-12)
          << order << " " << cutoff;
      EXPECT_NEAR(magnitudeResponse(f, 0.0, 200.0), 1.0, 1e-12);
      // Butterworth: |H|^2 = 1 / (1 + (w/wc)^(2 order)) in the pre-warped frequency.
      const double f2 = 0.5 * cutoff,
                   ratio = std::tan(kPi * f2 / 200) / std::tan(kPi * cutoff / 200);
      EXPECT_NEAR(magnitudeResponse(f, f2, 200.0),
                  1.0 / std::sqrt(1.0 + std::pow(ratio, 2 * order)), 1e-12);
      // Zero at Nyquist.
      EXPECT_LT(magnitudeResponse(f, 100.0, 200.0), 1e-12);
    }
  }
  EXPECT_THROW(butterworthLowPass(4, 100.0, 200.0), InputError);  // at Nyquist
  EXPECT_THROW(butterworthLowPass(4, 0.0, 200.0), InputError);
  EXPECT_THROW(butterworthLowPass(0, 10.0, 200.0), InputError);
  EXPECT_THROW(butterworthLowPass(13, 10.0, 200.0), InputError);
}

TEST(Signal, FiltfiltHasZeroPhaseAndSquaresTheMagnitude) {
  const double rate = 1000.0, cutoff = 10.0;
  const std::vector<Biquad> f = butterworthLowPass(4, cutoff, rate);
  for (double freq : {2.0, 10.0, 20.0}) {
    const Eigen::VectorXd x = sine(20000, rate, freq, 0.3);
    const Eigen::VectorXd y = filtfilt(f, x);
    // Away from the ends (the transient), y = |H|^2 x with no shift: compare against the scaled
    // input itself, sample by sample.
    const double gain = std::pow(magnitudeResponse(f, freq, rate), 2);
    const Eigen::VectorXd middle = y.segment(5000, 10000) - gain * x.segment(5000, 10000);
    // Round-off of the recursion over 2 x 20000 samples.
    EXPECT_LT(middle.cwiseAbs().maxCoeff(), 1e-9) << freq;
  }
  // -6 dB at the cutoff after the two passes.
  EXPECT_NEAR(std::pow(magnitudeResponse(f, cutoff, rate), 2), 0.5, 1e-12);
}

TEST(Signal, FiltfiltPassesLinesUnchangedToTheEnds) {
  // Odd reflection and steady-state starts: a constant and a ramp pass exactly (up to round-off),
  // edges included, which is what lets dynid trim little.
  const std::vector<Biquad> f = butterworthLowPass(4, 5.0, 500.0);
  const int n = padTransient(f) + 10;
  Eigen::VectorXd line(n);
  for (int k = 0; k < n; ++k) line[k] = 2.0 - 0.01 * k;
  // The edge transient (the group delay times the slope, ~0.1) decayed to 1e-9 of itself.
  EXPECT_LT((filtfilt(f, line) - line).cwiseAbs().maxCoeff(), 1e-8);
  // A constant: round-off of the recursion, whose poles lie within 0.04 of 1.
  EXPECT_LT((filtfilt(f, Eigen::VectorXd::Constant(50, 3.0)).array() - 3.0).abs().maxCoeff(),
            1e-12);
  EXPECT_THROW(filtfilt(f, Eigen::VectorXd::Ones(1)), InputError);
  // Shorter than the padding: still defined, the padding shrinks.
  EXPECT_EQ(filtfilt(f, line.head(5)).size(), 5);
  // In place: the same values, for a long signal and one shorter than the padding.
  for (const Eigen::VectorXd& x : {Eigen::VectorXd(line), Eigen::VectorXd(line.head(5))}) {
    Eigen::VectorXd y = x;
    filtfiltInPlace(f, y);
    EXPECT_EQ(y, filtfilt(f, x));
  }
  Eigen::VectorXd one = Eigen::VectorXd::Ones(1);
  EXPECT_THROW(filtfiltInPlace(f, one), InputError);
}

TEST(Signal, DerivativesAreExactForQuadraticsAndSecondOrderForSines) {
  const double h = 0.01;
  Eigen::VectorXd x(50), dx(50);
  for (int k = 0; k < 50; ++k) {
    const double t = k * h;
    x[k] = 1.0 + 2.0 * t - 3.0 * t * t;
    dx[k] = 2.0 - 6.0 * t;
  }
  // Exact for degree <= 2, ends included (one-sided second-order formulas).
  EXPECT_LT((derivative(x, h) - dx).cwiseAbs().maxCoeff(), 1e-10);
  // A sine: the error falls fourfold when h halves (second order).
  double errors[2];
  for (int r = 0; r < 2; ++r) {
    const double step = 0.01 / (1 << r);
    const int n = static_cast<int>(1.0 / step);
    Eigen::VectorXd s(n), ds(n);
    for (int k = 0; k < n; ++k)
      s[k] = std::sin(3.0 * k * step), ds[k] = 3.0 * std::cos(3.0 * k * step);
    errors[r] = (derivative(s, step) - ds).segment(2, n - 4).cwiseAbs().maxCoeff();
  }
  EXPECT_NEAR(errors[0] / errors[1], 4.0, 0.1);
  EXPECT_THROW(derivative(Eigen::VectorXd::Ones(2), h), InputError);
}

TEST(Signal, ResamplingIsExactForLinesOnIrregularStamps) {
  Eigen::VectorXd t(6);
  t << 0.0, 0.0007, 0.002, 0.0031, 0.0118, 0.013;
  Eigen::MatrixXd x(6, 2);
  for (int k = 0; k < 6; ++k) x(k, 0) = 3.0 * t[k] + 1.0, x(k, 1) = -t[k];
  const Eigen::MatrixXd y = resampleLinear(t, x, 0.0, 1000.0, 14);
  for (int k = 0; k < 14; ++k) {
    EXPECT_NEAR(y(k, 0), 3.0 * k * 1e-3 + 1.0, 1e-14) << k;
    EXPECT_NEAR(y(k, 1), -k * 1e-3, 1e-14) << k;
  }
  // The grid, found once, resamples each signal alike: the first stamp below each time (held at
  // the ends: the last time, 13 ms, lies on the last stamp).
  const LinearGrid grid = linearGrid(t, 0.0, 1000.0, 14);
  EXPECT_EQ(grid.below, (std::vector<int>{0, 1, 1, 2, 3, 3, 3, 3, 3, 3, 3, 3, 4, 4}));
  for (int c = 0; c < 2; ++c) EXPECT_EQ(resampleLinear(grid, x.col(c)), y.col(c));
  EXPECT_THROW(linearGrid(t.head(1), 0.0, 1000.0, 1), InputError);
}

// A signal read a part at a time, its grid found a part at a time: the same bits as the run-long
// grid, for parts from the smallest (2 stamps) to more than the signal, on jittered stamps with a
// gap, resampled faster and slower than logged; each part asked for lies within the stamps and
// holds at most `part` values.
TEST(Signal, ResamplingAPartAtATimeGivesTheBitsOfTheWholeGrid) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.3e-3, 0.3e-3);
  Eigen::VectorXd t(400), x(400);
  for (int k = 0; k < 400; ++k) {
    t[k] = 1e-3 * k + (k > 0 ? jitter(rng) : 0.0) + (k >= 250 ? 0.02 : 0.0);  // a 20 ms gap
    x[k] = std::sin(40.0 * t[k]) + 1e-3 * k;
  }
  for (double rate : {1000.0, 3100.0, 350.0}) {
    const int count = static_cast<int>(std::floor((t[399] - t[0]) * rate + 1e-9)) + 1;
    const Eigen::VectorXd whole = resampleLinear(linearGrid(t, t[0], rate, count), x);
    for (Eigen::Index part : {2, 3, 17, 100, 399, 1000}) {
      SCOPED_TRACE(std::to_string(rate) + " Hz, parts of " + std::to_string(part));
      const Eigen::VectorXd parts = resampleLinear(
          t, t[0], rate, count,
          [&](Eigen::Index first, Eigen::Index length) -> Eigen::VectorXd {
            EXPECT_GE(first, 0);
            EXPECT_LE(first + length, t.size());
            EXPECT_LE(length, part);
            return x.segment(first, length);
          },
          part);
      ASSERT_EQ(parts.size(), whole.size());
      EXPECT_TRUE(parts == whole);
    }
  }
}

/// The cascade as filtfilt's contract states it, one section after another over the whole signal
/// (each starting in its steady state for its input's first value): the reference the filter's
/// one-loop implementation must match bit for bit.
Eigen::VectorXd sectionAfterSection(const std::vector<Biquad>& sections, Eigen::VectorXd x) {
  for (const Biquad& s : sections) {
    const double u0 = x[0], g = (s.b0 + s.b1 + s.b2) / (1.0 + s.a1 + s.a2);
    double s1 = g * u0 - s.b0 * u0, s2 = s.b2 * u0 - s.a2 * g * u0;
    for (Eigen::Index n = 0; n < x.size(); ++n) {
      const double u = x[n], y = s.b0 * u + s1;
      s1 = s.b1 * u - s.a1 * y + s2;
      s2 = s.b2 * u - s.a2 * y;
      x[n] = y;
    }
  }
  return x;
}

/// filtfilt by its contract: odd reflection, the cascade forward, then backward, section after
/// section.
Eigen::VectorXd referenceFiltfilt(const std::vector<Biquad>& sections, const Eigen::VectorXd& x) {
  const Eigen::Index n = x.size(), pad = std::min<Eigen::Index>(padTransient(sections), n - 1);
  Eigen::VectorXd y(n + 2 * pad);
  for (Eigen::Index k = 0; k < pad; ++k) {
    y[k] = 2.0 * x[0] - x[pad - k];
    y[n + pad + k] = 2.0 * x[n - 1] - x[n - 2 - k];
  }
  y.segment(pad, n) = x;
  y = sectionAfterSection(sections, y).reverse().eval();
  y = sectionAfterSection(sections, y).reverse().eval();
  return y.segment(pad, n);
}

TEST(Signal, TheSectionsRunInOneLoopWithTheSameBitsAsOneAfterAnother) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  Eigen::VectorXd x = sine(3000, 1000.0, 3.0, 0.4);
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(rng);
  std::vector<Biquad> many;  // more sections than one pass takes (2), an odd number of them
  for (int order : {1, 2, 3, 4, 5, 8, 11, 12}) {
    const std::vector<Biquad> f = butterworthLowPass(order, 20.0, 1000.0);
    if (order >= 5) many.insert(many.end(), f.begin(), f.end());
    EXPECT_EQ(filtfilt(f, x), referenceFiltfilt(f, x)) << order;
  }
  ASSERT_EQ(many.size(), 19u);
  EXPECT_EQ(filtfilt(many, x), referenceFiltfilt(many, x));
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

TEST(Signal, SavitzkyGolayIsExactForPolynomialsOfItsDegreeEverywhere) {
  // A cubic with an off-centre root, sampled at 200 Hz; degree 3, windows 7 and 21.
  const double h = 5e-3;
  const int n = 60;
  Eigen::VectorXd x(n), dx(n), ddx(n);
  for (int k = 0; k < n; ++k) {
    const double t = k * h - 0.1;
    x[k] = 2.0 - 3.0 * t + 4.0 * t * t - 5.0 * t * t * t;
    dx[k] = -3.0 + 8.0 * t - 15.0 * t * t;
    ddx[k] = 8.0 - 30.0 * t;
  }
  for (int window : {7, 21}) {
    // Round-off of the least-squares weights, amplified by 1/h^order.
    EXPECT_LT((savitzkyGolay(x, h, window, 3, 0) - x).cwiseAbs().maxCoeff(), 1e-12) << window;
    EXPECT_LT((savitzkyGolay(x, h, window, 3, 1) - dx).cwiseAbs().maxCoeff(), 1e-9) << window;
    EXPECT_LT((savitzkyGolay(x, h, window, 3, 2) - ddx).cwiseAbs().maxCoeff(), 1e-6) << window;
  }
  // Degree 2 cannot follow the cubic: not exact (the test can fail).
  EXPECT_GT((savitzkyGolay(x, h, 21, 2, 2) - ddx).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_THROW(savitzkyGolay(x, h, 8, 3, 1), InputError);          // even window
  EXPECT_THROW(savitzkyGolay(x, h, 3, 3, 1), InputError);          // window <= degree
  EXPECT_THROW(savitzkyGolay(x, h, 7, 2, 3), InputError);          // order > degree
  EXPECT_THROW(savitzkyGolay(x.head(5), h, 7, 3, 1), InputError);  // shorter than the window
}

TEST(Signal, SavitzkyGolaySmoothsNoiseLikeItsLeastSquaresVarianceSays) {
  // White noise of unit variance: the centred degree-2 smoother of window 2m+1 leaves variance
  // 3(3m^2 + 3m - 1) / ((2m - 1)(2m + 1)(2m + 3)) (Savitzky & Golay's noise reduction).
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::VectorXd x(200000);
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] = gauss(rng);
  const int m = 10;
  const Eigen::VectorXd y = savitzkyGolay(x, 1.0, 2 * m + 1, 2, 0);
  const double expected =
      3.0 * (3.0 * m * m + 3.0 * m - 1.0) / ((2.0 * m - 1.0) * (2.0 * m + 1.0) * (2.0 * m + 3.0));
  const double variance = y.segment(m, y.size() - 2 * m).squaredNorm() / (y.size() - 2 * m);
  // 2e5 correlated samples: a few per cent of sampling error.
  EXPECT_NEAR(variance / expected, 1.0, 0.05);
}

TEST(Signal, WelchSpectrumIntegratesToTheVariance) {
  const double rate = 1000.0;
  const int segment = 1024;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 0.3);
  Eigen::VectorXd x(60000);
  // A 2 V amplitude sine at 62.5 Hz (bin 64 exactly) on white noise of 0.3 V RMS.
  for (Eigen::Index k = 0; k < x.size(); ++k)
    x[k] = 2.0 * std::sin(2.0 * std::numbers::pi * 62.5 * k / rate) + gauss(rng);
  const Spectrum s = welchSpectrum(x, rate, segment);
  ASSERT_EQ(s.frequency.size(), segment / 2 + 1);
  EXPECT_DOUBLE_EQ(s.frequency[64], 62.5);
  const double df = rate / segment;
  // Parseval: the sum is the variance, 2^2 / 2 + 0.3^2 (the Hann window's leakage stays within
  // the sum; sampling error of the noise ~1 %).
  EXPECT_NEAR(s.density.sum() * df, 2.0 + 0.09, 0.03);
  // The sine's power within +-2 bins (Hann spreads it over 3): 2 V^2.
  EXPECT_NEAR(s.density.segment(62, 5).sum() * df, 2.0, 0.02);
  // The noise floor far from the sine: 2 sigma^2 / rate per Hz, one-sided.
  const double floor = s.density.segment(300, 200).mean();
  EXPECT_NEAR(floor / (2.0 * 0.09 / rate), 1.0, 0.05);
  EXPECT_THROW(welchSpectrum(x.head(100), rate, segment), InputError);
}

}  // namespace
}  // namespace dynid
