#include "core/signal.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/QR>
#include <unsupported/Eigen/FFT>

#include "core/errors.hpp"

namespace dynid {

std::vector<Biquad> butterworthLowPass(int order, double cutoff, double rate) {
  if (!(order >= 1 && order <= 12))
    throw InputError("the filter order must be 1 to 12, not " + std::to_string(order));
  if (!(rate > 0.0) || !std::isfinite(rate))
    throw InputError("the sampling rate must be finite and positive");
  if (!(cutoff > 0.0) || !(cutoff < rate / 2.0))
    throw InputError("the cutoff " + std::to_string(cutoff) +
                     " Hz must be above 0 and below the Nyquist frequency " +
                     std::to_string(rate / 2.0) + " Hz");
  // Pre-warped analog cutoff: the bilinear transform s = 2 rate (z - 1) / (z + 1) maps it onto
  // the digital one exactly.
  const double k = std::tan(std::numbers::pi * cutoff / rate);  // wa / (2 rate)
  std::vector<Biquad> out;
  // Analog poles of a unit Butterworth on the left half circle, in conjugate pairs:
  // s_m = exp(i pi (2m + order + 1) / (2 order)), m = 0..order/2-1; a real pole -1 for odd order.
  for (int m = 0; m < order / 2; ++m) {
    const double theta = std::numbers::pi * (2.0 * m + order + 1) / (2.0 * order);
    const double q = -2.0 * std::cos(theta);  // s^2 + q s + 1, q > 0
    // H(s) = 1 / (s^2/k^2 + q s / k + 1) with s -> (z - 1) / (z + 1) (k absorbs 2 rate / wa).
    const double a0 = 1.0 + q * k + k * k;
    Biquad b;
    b.b0 = k * k / a0, b.b1 = 2.0 * k * k / a0, b.b2 = k * k / a0;
    b.a1 = 2.0 * (k * k - 1.0) / a0;
    b.a2 = (1.0 - q * k + k * k) / a0;
    out.push_back(b);
  }
  if (order % 2 == 1) {  // 1 / (s / k + 1)
    const double a0 = 1.0 + k;
    Biquad b;
    b.b0 = k / a0, b.b1 = k / a0, b.b2 = 0.0;
    b.a1 = (k - 1.0) / a0, b.a2 = 0.0;
    out.push_back(b);
  }
  return out;
}

double magnitudeResponse(const std::vector<Biquad>& sections, double f, double rate) {
  const std::complex<double> z1 = std::polar(1.0, -2.0 * std::numbers::pi * f / rate);  // z^-1
  std::complex<double> h = 1.0;
  for (const Biquad& s : sections)
    h *= (s.b0 + s.b1 * z1 + s.b2 * z1 * z1) / (1.0 + s.a1 * z1 + s.a2 * z1 * z1);
  return std::abs(h);
}

int padTransient(const std::vector<Biquad>& sections) {
  // The slowest pole's radius r: its transient falls below 1e-9 after ln(1e-9) / ln(r) samples.
  double radius = 0.0;
  for (const Biquad& s : sections) {
    const double disc = s.a1 * s.a1 - 4.0 * s.a2;
    const double r =
        disc < 0.0 ? std::sqrt(s.a2) : 0.5 * (std::abs(s.a1) + std::sqrt(std::max(disc, 0.0)));
    radius = std::max(radius, r);
  }
  if (radius <= 0.0) return 1;
  if (radius >= 1.0) return 1 << 20;
  return static_cast<int>(std::ceil(std::log(1e-9) / std::log(radius)));
}

namespace {

/// The cascade of `M` sections over x in place (transposed direct form II), each section
/// starting in its steady state for a constant input: its input's first value. The sections run
/// sample by sample in one loop, so that their recursions overlap in the processor (one section's
/// loop is bound by the latency of its own recursion); each section's arithmetic is the same as
/// filtering the whole signal section after section.
template <int M>
void cascade(const Biquad* sections, Eigen::VectorXd& x) {
  double s1[M], s2[M];
  double u0 = x[0];
  for (int i = 0; i < M; ++i) {
    // Steady state for a constant input u: y = g u (g the DC gain), s1 = y - b0 u,
    // s2 = b2 u - a2 y.
    const Biquad& s = sections[i];
    const double g = (s.b0 + s.b1 + s.b2) / (1.0 + s.a1 + s.a2);
    s1[i] = g * u0 - s.b0 * u0;
    s2[i] = s.b2 * u0 - s.a2 * g * u0;
    u0 = s.b0 * u0 + s1[i];  // the section's first output: the next one's first input
  }
  for (Eigen::Index n = 0; n < x.size(); ++n) {
    double u = x[n];
    for (int i = 0; i < M; ++i) {
      const Biquad& s = sections[i];
      const double y = s.b0 * u + s1[i];
      s1[i] = s.b1 * u - s.a1 * y + s2[i];
      s2[i] = s.b2 * u - s.a2 * y;
      u = y;
    }
    x[n] = u;
  }
}

/// The cascade over x in place, two sections per pass (the default order 4 in one pass).
void filterInPlace(const std::vector<Biquad>& sections, Eigen::VectorXd& x) {
  std::size_t i = 0;
  for (; i + 1 < sections.size(); i += 2) cascade<2>(sections.data() + i, x);
  if (i < sections.size()) cascade<1>(sections.data() + i, x);
}

/// x padded at both ends (filtfilt's contract), run forward and backward: the result's samples
/// [pad, pad + x.size()) are the filtered signal.
Eigen::VectorXd filteredPadded(const std::vector<Biquad>& sections, const Eigen::VectorXd& x,
                               Eigen::Index& pad) {
  const Eigen::Index n = x.size();
  if (n < 2) throw InputError("a signal to filter needs at least 2 samples");
  pad = std::min<Eigen::Index>(padTransient(sections), n - 1);
  Eigen::VectorXd y(n + 2 * pad);
  for (Eigen::Index k = 0; k < pad; ++k) {
    y[k] = 2.0 * x[0] - x[pad - k];
    y[n + pad + k] = 2.0 * x[n - 1] - x[n - 2 - k];
  }
  y.segment(pad, n) = x;
  filterInPlace(sections, y);
  y.reverseInPlace();
  filterInPlace(sections, y);
  y.reverseInPlace();
  return y;
}

}  // namespace

namespace {
/// y's samples [pad, pad + n) moved to its front and the rest cut off, in y's own storage: no
/// second signal-long vector.
void unpad(Eigen::VectorXd& y, Eigen::Index pad, Eigen::Index n) {
  std::memmove(y.data(), y.data() + pad, static_cast<std::size_t>(n) * sizeof(double));
  y.conservativeResize(n);
}
}  // namespace

Eigen::VectorXd filtfilt(const std::vector<Biquad>& sections, const Eigen::VectorXd& x) {
  Eigen::Index pad = 0;
  Eigen::VectorXd y = filteredPadded(sections, x, pad);
  unpad(y, pad, x.size());
  return y;
}

void filtfiltInPlace(const std::vector<Biquad>& sections, Eigen::VectorXd& x) {
  Eigen::Index pad = 0;
  Eigen::VectorXd y = filteredPadded(sections, x, pad);
  unpad(y, pad, x.size());
  x.swap(y);
}

Eigen::MatrixXd resampleLinear(const Eigen::Ref<const Eigen::VectorXd>& time,
                               const Eigen::Ref<const Eigen::MatrixXd>& x, double t0, double rate,
                               int count) {
  const LinearGrid grid = linearGrid(time, t0, rate, count);
  Eigen::MatrixXd out(count, x.cols());
  for (Eigen::Index c = 0; c < x.cols(); ++c) out.col(c) = resampleLinear(grid, x.col(c));
  return out;
}

namespace {
/// The grid of the times t0 + k / rate for k in [first, first + count) into `grid` (resized;
/// `below` holds stamp indices into all of `time`): the one formula of every resampling, so a
/// grid found a part at a time has the same bits as one found at once.
void gridPart(const Eigen::Ref<const Eigen::VectorXd>& time, double t0, double rate, int first,
              int count, LinearGrid& grid) {
  grid.below.resize(static_cast<std::size_t>(std::max(count, 0)));
  grid.weight.resize(std::max(count, 0));
  const auto last = static_cast<int>(time.size() - 2);
  // The stamp below the first time: as the walk from stamp 0 would reach it (stamps before t,
  // at most the last but one).
  int j = 0;
  if (first > 0) {
    const double t = t0 + first / rate;
    const auto before =
        static_cast<int>(std::lower_bound(time.begin(), time.end(), t) - time.begin());
    j = std::clamp(before - 1, 0, last);
  }
  for (int i = 0; i < count; ++i) {
    const int k = first + i;
    const double t = t0 + k / rate;
    while (j < last && time[j + 1] < t) ++j;
    grid.below[static_cast<std::size_t>(i)] = j;
    grid.weight[i] = std::clamp((t - time[j]) / (time[j + 1] - time[j]), 0.0, 1.0);
  }
}
}  // namespace

LinearGrid linearGrid(const Eigen::Ref<const Eigen::VectorXd>& time, double t0, double rate,
                      int count) {
  if (time.size() < 2 || time.size() > std::numeric_limits<int>::max())
    throw InputError("resampling needs 2 to " + std::to_string(std::numeric_limits<int>::max()) +
                     " stamps, not " + std::to_string(time.size()));
  LinearGrid grid;
  gridPart(time, t0, rate, 0, count, grid);
  return grid;
}

namespace {
/// The one interpolation of both resampleLinear overloads (the same bits from either).
inline double lerp(double w, double a, double b) { return (1.0 - w) * a + w * b; }
}  // namespace

Eigen::VectorXd resampleLinear(const LinearGrid& grid, const Eigen::Ref<const Eigen::VectorXd>& x) {
  const Eigen::Index count = grid.weight.size();
  Eigen::VectorXd out(count);
  for (Eigen::Index k = 0; k < count; ++k) {
    const int j = grid.below[static_cast<std::size_t>(k)];
    const double w = grid.weight[k];
    out[k] = lerp(w, x[j], x[j + 1]);
  }
  return out;
}

Eigen::VectorXd resampleLinear(
    const Eigen::Ref<const Eigen::VectorXd>& time, double t0, double rate, int count,
    const std::function<Eigen::VectorXd(Eigen::Index first, Eigen::Index length)>& x,
    Eigen::Index part) {
  if (time.size() < 2 || time.size() > std::numeric_limits<int>::max())
    throw InputError("resampling needs 2 to " + std::to_string(std::numeric_limits<int>::max()) +
                     " stamps, not " + std::to_string(time.size()));
  Eigen::VectorXd out(std::max(count, 0));
  part = std::max<Eigen::Index>(part, 2);
  LinearGrid grid;
  for (int k0 = 0; k0 < count;) {
    // The next times' grid, then the part of x from the stamp below the first of them on; the
    // times whose two stamps lie in it.
    gridPart(time, t0, rate, k0, static_cast<int>(std::min<Eigen::Index>(part, count - k0)), grid);
    const Eigen::Index first = grid.below.front();
    const Eigen::Index length = std::min(part, time.size() - first);
    const Eigen::VectorXd values = x(first, length);
    int done = 0;
    while (done < grid.weight.size() &&
           grid.below[static_cast<std::size_t>(done)] + 1 < first + length) {
      const Eigen::Index j = grid.below[static_cast<std::size_t>(done)] - first;
      const double w = grid.weight[done];
      out[k0 + done] = lerp(w, values[j], values[j + 1]);
      ++done;
    }
    k0 += done;
  }
  return out;
}

Eigen::VectorXd derivative(const Eigen::VectorXd& x, double h) {
  const Eigen::Index n = x.size();
  if (n < 3) throw InputError("a derivative needs at least 3 samples");
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 1; k + 1 < n; ++k) out[k] = (x[k + 1] - x[k - 1]) / (2.0 * h);
  out[0] = (-3.0 * x[0] + 4.0 * x[1] - x[2]) / (2.0 * h);
  out[n - 1] = (3.0 * x[n - 1] - 4.0 * x[n - 2] + x[n - 3]) / (2.0 * h);
  return out;
}

Eigen::VectorXd savitzkyGolay(const Eigen::VectorXd& x, double h, int window, int degree,
                              int order) {
  if (window % 2 == 0 || window <= degree || degree < 0 || order < 0 || order > degree)
    throw InputError("Savitzky-Golay needs an odd window longer than the degree (window " +
                     std::to_string(window) + ", degree " + std::to_string(degree) +
                     ") and a derivative order at most the degree");
  const Eigen::Index n = x.size();
  if (n < window)
    throw InputError("the signal (" + std::to_string(n) +
                     " samples) is shorter than the Savitzky-Golay window (" +
                     std::to_string(window) + ")");
  const int half = window / 2;
  // Least squares over u = (k - centre) / half in [-1, 1] (well conditioned): coefficients of
  // the fit a = P x with P = (V^T V)^-1 V^T; the order-th derivative at u = s is
  // sum_i a_i i! / (i - order)! s^(i - order) / (half h)^order.
  Eigen::MatrixXd V(window, degree + 1);
  for (int r = 0; r < window; ++r) {
    const double u = static_cast<double>(r - half) / half;
    double power = 1.0;
    for (int i = 0; i <= degree; ++i, power *= u) V(r, i) = power;
  }
  const Eigen::MatrixXd P =
      V.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(window, window));
  const double scale = std::pow(half * h, -order);
  // The weights that evaluate the derivative at window position r (0..window-1).
  const auto weights = [&](int r) {
    const double s = static_cast<double>(r - half) / half;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(degree + 1);
    for (int i = order; i <= degree; ++i) {
      double falling = 1.0;
      for (int k = 0; k < order; ++k) falling *= i - k;
      d[i] = falling * std::pow(s, i - order);
    }
    return Eigen::VectorXd(scale * (P.transpose() * d));
  };
  Eigen::VectorXd out(n);
  const Eigen::VectorXd centre = weights(half);
  for (Eigen::Index k = half; k < n - half; ++k) out[k] = centre.dot(x.segment(k - half, window));
  for (int r = 0; r < half; ++r) {
    out[r] = weights(r).dot(x.head(window));
    out[n - half + r] = weights(half + 1 + r).dot(x.tail(window));
  }
  return out;
}

Spectrum welchSpectrum(const Eigen::VectorXd& x, double rate, int segment, int max_segments) {
  if (segment < 8 || segment % 2 != 0)
    throw InputError("a spectrum segment must be even and at least 8 samples");
  if (x.size() < segment)
    throw InputError("the signal (" + std::to_string(x.size()) +
                     " samples) is shorter than a spectrum segment (" + std::to_string(segment) +
                     ")");
  Eigen::VectorXd window(segment);
  for (int k = 0; k < segment; ++k)
    window[k] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * k / segment);  // periodic Hann
  const double window_power = window.squaredNorm();
  // Detrending: least squares on (1, k) over a segment.
  const Eigen::VectorXd ramp = Eigen::VectorXd::LinSpaced(segment, 0.0, segment - 1.0);
  const double ramp_mean = ramp.mean();
  const double ramp_var = (ramp.array() - ramp_mean).square().sum();
  Eigen::FFT<double> fft;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(segment / 2 + 1);
  int segments = 0;
  std::vector<double> piece(static_cast<std::size_t>(segment));
  std::vector<std::complex<double>> spectrum;
  Eigen::Index hop = segment / 2;
  if (max_segments > 1)
    hop = std::max(hop, (x.size() - segment) / (max_segments - 1));
  else if (max_segments == 1)
    hop = x.size();
  for (Eigen::Index start = 0; start + segment <= x.size(); start += hop, ++segments) {
    const Eigen::VectorXd y = x.segment(start, segment);
    const double mean = y.mean();
    const double slope = (ramp.array() - ramp_mean).matrix().dot(y) / ramp_var;
    for (int k = 0; k < segment; ++k)
      piece[static_cast<std::size_t>(k)] = (y[k] - mean - slope * (k - ramp_mean)) * window[k];
    fft.fwd(spectrum, piece);
    for (int k = 0; k <= segment / 2; ++k)
      sum[k] += std::norm(spectrum[static_cast<std::size_t>(k)]);
  }
  Spectrum out;
  out.frequency = Eigen::VectorXd::LinSpaced(segment / 2 + 1, 0.0, rate / 2.0);
  // One-sided: bins strictly between DC and Nyquist count twice.
  out.density = sum / (segments * rate * window_power);
  out.density.segment(1, segment / 2 - 1) *= 2.0;
  return out;
}

}  // namespace dynid
