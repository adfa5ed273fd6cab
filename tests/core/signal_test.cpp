#include "core/signal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

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
}

}  // namespace
}  // namespace dynid
