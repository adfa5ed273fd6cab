// Signal processing for logged joint signals: zero-phase Butterworth low-pass filtering, uniform
// resampling, finite-difference and Savitzky-Golay derivatives, and power spectra. Every function
// works on one run: samples that are consecutive in time, with no gap (analysis/logs/raw_log.hpp
// splits logs into runs).
//
// Symbols: x a signal (one value per sample, an Eigen vector), rate the sampling rate [Hz],
// cutoff the filter's -3 dB frequency [Hz].
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

namespace dynid {

/// One second-order section y = (b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2) x.
struct Biquad {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
};

/// A digital Butterworth low-pass of `order` (1..12) with its -3 dB point at `cutoff`, designed
/// by the bilinear transform with the cutoff pre-warped, as second-order sections (a first-order
/// section, b2 = a2 = 0, for an odd order). Unit gain at DC. Throws InputError unless
/// 0 < cutoff < rate / 2 and 1 <= order <= 12.
std::vector<Biquad> butterworthLowPass(int order, double cutoff, double rate);

/// |H(e^{i 2 pi f / rate})| of the cascade: its magnitude response at frequency f [Hz].
double magnitudeResponse(const std::vector<Biquad>& sections, double f, double rate);

/// The cascade run forward, then backward over the result (zero phase; the magnitude response is
/// squared: -6 dB at the cutoff). The ends are extended by odd reflection (2 x(0) - x(k)) over
/// `padTransient(sections)` samples (fewer when the signal is shorter) and each section starts
/// in its steady state for the first padded value, so a constant passes unchanged and a line
/// does to 1e-9 of its edge transient when the signal is longer than the padding.
/// Throws InputError when the signal has fewer than 2 samples.
Eigen::VectorXd filtfilt(const std::vector<Biquad>& sections, const Eigen::VectorXd& x);
/// The same values written over x (one padded copy while it runs, not two).
void filtfiltInPlace(const std::vector<Biquad>& sections, Eigen::VectorXd& x);

/// The number of samples by which the ends are padded: until the slowest pole's transient has
/// fallen to 1e-9 (scipy's 3 x (2 x sections + 1) is too short for low cutoffs: a ramp's edge
/// transient then reaches the data).
int padTransient(const std::vector<Biquad>& sections);

/// Samples of (time, x) at the uniform times t0, t0 + 1/rate, ... <= time.back(), by linear
/// interpolation (time strictly increasing, x one column per signal, one row per sample).
Eigen::MatrixXd resampleLinear(const Eigen::Ref<const Eigen::VectorXd>& time,
                               const Eigen::Ref<const Eigen::MatrixXd>& x, double t0, double rate,
                               int count);

/// Where the uniform times t0 + k / rate (k < count) fall among strictly increasing stamps (at
/// least 2): per time, the stamp below it (at most the last but one) and the weight of the next,
/// clamped to [0, 1]. Computed once, it resamples every signal on those stamps as resampleLinear
/// does, bit for bit.
struct LinearGrid {
  std::vector<int> below;
  Eigen::VectorXd weight;
};
/// Throws InputError for fewer than 2 stamps or more than INT_MAX.
LinearGrid linearGrid(const Eigen::Ref<const Eigen::VectorXd>& time, double t0, double rate,
                      int count);
/// x (one value per stamp of the grid) at the grid's times.
Eigen::VectorXd resampleLinear(const LinearGrid& grid, const Eigen::Ref<const Eigen::VectorXd>& x);
/// x at the times t0 + k / rate (k < count) among strictly increasing `time` (at least 2
/// stamps), for a signal read a part at a time: x(first, length) returns its values at stamps
/// [first, first + length) (length >= 2). The grid is found a part at a time too: the same bits as
/// resampleLinear(linearGrid(time, t0, rate, count), x), holding at most `part` of x's values and
/// no whole-length grid.
Eigen::VectorXd resampleLinear(
    const Eigen::Ref<const Eigen::VectorXd>& time, double t0, double rate, int count,
    const std::function<Eigen::VectorXd(Eigen::Index first, Eigen::Index length)>& x,
    Eigen::Index part);

/// First derivative of a uniformly sampled signal (step h [s]): central differences inside,
/// second-order one-sided differences at the ends. Exact for polynomials of degree <= 2.
Eigen::VectorXd derivative(const Eigen::VectorXd& x, double h);

/// Savitzky-Golay: at every sample, the least-squares polynomial of `degree` through the
/// `window` samples around it (odd window > degree), differentiated `order` times (0: smoothed
/// value, 1, 2; step h [s]). Near the ends the window stays inside the signal and the polynomial
/// is evaluated off-centre. Exact for polynomials of degree <= `degree`. Throws InputError for an
/// even window, window <= degree, order > degree, or a signal shorter than the window.
Eigen::VectorXd savitzkyGolay(const Eigen::VectorXd& x, double h, int window, int degree,
                              int order);

/// A one-sided power spectral density: density[k] at frequency[k] = k rate / segment, in
/// (signal unit)^2 / Hz, so that its sum times rate / segment is the signal's variance.
struct Spectrum {
  Eigen::VectorXd frequency, density;
};
/// Welch's estimate: Hann-windowed segments of `segment` samples (even, >= 8) with 50 % overlap,
/// each with its mean and linear trend removed, periodograms averaged. With `max_segments` > 0,
/// at most that many segments, spread evenly over the signal (less overlap, same estimate of a
/// stationary signal; bounded time on long logs). Throws InputError when the signal is shorter
/// than one segment.
Spectrum welchSpectrum(const Eigen::VectorXd& x, double rate, int segment, int max_segments = 0);

}  // namespace dynid
