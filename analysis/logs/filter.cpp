#include "analysis/logs/prepare_steps.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/signal.hpp"

namespace dynid::prepare_steps {

/// Spectra of q and tau over every run at least one segment long (each joint normalised to unit
/// power, then summed), the trajectory band and the noise edge.
void measureSpectra(const std::vector<RawSignals>& files, const std::vector<RunSpan>& spans,
                    PrepareOutcome& out) {
  int longest = 0;
  for (const RunSpan& span : spans) longest = std::max(longest, span.count);
  // Resolution: segments of up to 16 s (a power of two), at least 64 samples.
  int segment = 64;
  while (2 * segment <= longest && 2 * segment <= 16.0 * out.rate) segment *= 2;
  if (longest < segment) return;
  const int n = files.front().n;
  std::vector<Eigen::VectorXd> q_sum(static_cast<std::size_t>(n)), tau_sum(q_sum);
  for (const RunSpan& span : spans) {
    if (span.count < segment) continue;
    const RawSignals& s = files[span.file];
    // Welch's segments with 50 % overlap, at most 16 spread evenly over the run (bounded time on
    // long logs), each resampled on its own. Weighted by the run's length: long runs dominate.
    const int welch = (span.count - segment) / (segment / 2) + 1;
    const int windows = std::min(16, welch);
    const double weight = static_cast<double>(span.count) / windows;
    for (int w = 0; w < windows; ++w) {
      const int first = windows == 1
                            ? 0
                            : static_cast<int>(std::lround(static_cast<double>(w) *
                                                           (span.count - segment) / (windows - 1)));
      for (int j = 0; j < n; ++j) {
        const Spectrum sq = welchSpectrum(resampled(s, span, 1 + j, out.rate, segment, first),
                                          out.rate, segment, 1);
        const Spectrum st = welchSpectrum(resampled(s, span, 1 + n + j, out.rate, segment, first),
                                          out.rate, segment, 1);
        if (q_sum[j].size() == 0) {
          q_sum[j] = Eigen::VectorXd::Zero(sq.density.size());
          tau_sum[j] = q_sum[j];
          out.q_spectrum.frequency = sq.frequency;
        }
        q_sum[j] += weight * sq.density;
        tau_sum[j] += weight * st.density;
      }
    }
  }
  out.q_spectrum.density = Eigen::VectorXd::Zero(out.q_spectrum.frequency.size());
  out.tau_spectrum = out.q_spectrum;
  for (int j = 0; j < n; ++j) {
    // Unit power without the DC bin (the detrended mean's leakage).
    const double q_power = q_sum[j].tail(q_sum[j].size() - 1).sum();
    const double tau_power = tau_sum[j].tail(tau_sum[j].size() - 1).sum();
    if (q_power > 0.0) out.q_spectrum.density += q_sum[j] / q_power;
    if (tau_power > 0.0) out.tau_spectrum.density += tau_sum[j] / tau_power;
  }
  const Eigen::VectorXd& d = out.q_spectrum.density;
  const Eigen::VectorXd& f = out.q_spectrum.frequency;
  const double total = d.tail(d.size() - 1).sum();
  if (!(total > 0.0)) return;  // q never moves
  double cumulative = 0.0;
  Eigen::Index band = 1;
  for (; band < d.size(); ++band) {
    cumulative += d[band];
    if (cumulative >= 0.995 * total) break;
  }
  band = std::min(band, d.size() - 1);
  out.trajectory_band = f[band];
  // The noise floor: the median density from ten times the band to a quarter of the rate (above
  // it, the resampling's interpolation bends the floor down), else over the upper half.
  std::vector<double> upper;
  for (Eigen::Index k = band; k < d.size(); ++k)
    if (f[k] >= 10.0 * out.trajectory_band && f[k] <= out.rate / 4.0) upper.push_back(d[k]);
  if (upper.size() < 8) {
    upper.clear();
    for (Eigen::Index k = d.size() / 2; k < d.size(); ++k) upper.push_back(d[k]);
  }
  const double floor = median(upper);
  out.noise_edge = f[d.size() - 1];
  for (Eigen::Index k = band; k < d.size(); ++k)
    if (d[k] <= 10.0 * floor) {
      out.noise_edge = f[k];
      break;
    }
}

namespace {
std::string hz(double f) { return formatNumber(f, 3) + " Hz"; }
}  // namespace

/// Chooses the cutoff (and says why), the trim and the Savitzky-Golay window.
void chooseFilter(const PrepareOptions& options, PrepareOutcome& out) {
  if (options.auto_cutoff) {
    if (out.q_spectrum.density.size() == 0 || !(out.trajectory_band > 0.0))
      throw InputError("`cutoff` auto needs a moving run of at least 64 samples; give `cutoff`");
    const double chosen = std::min({5.0 * out.trajectory_band, out.noise_edge, out.rate / 4.0});
    out.cutoff = std::max(chosen, std::min(1.5 * out.trajectory_band, 0.45 * out.rate));
    out.cutoff_reason = "auto: 99.5 % of q's power lies below " + hz(out.trajectory_band) +
                        " (the trajectory band); the cutoff is " + hz(out.cutoff) +
                        ", five times that, at most where q's spectrum meets its noise floor (" +
                        hz(out.noise_edge) + ") and a quarter of the rate";
  } else if (options.cutoff >= 0.0) {
    out.cutoff = options.cutoff;
    out.cutoff_reason = options.cutoff > 0.0 ? "given" : "no filter (`cutoff` 0)";
  } else {
    out.cutoff = std::min(10.0, out.rate / 4.0);
    out.cutoff_reason = out.cutoff == 10.0 ? "the default, 10 Hz"
                                           : "the default for logs slower than 40 Hz: a quarter "
                                             "of the rate";
  }
  out.tau_cutoff = options.tau_cutoff < 0.0 ? out.cutoff : options.tau_cutoff;
  // The default trim: two periods of the lowest cutoff (the slowest filter's transient).
  double lowest = 0.0;
  for (double c : {out.cutoff, out.tau_cutoff})
    if (c > 0.0) lowest = lowest > 0.0 ? std::min(lowest, c) : c;
  out.trim = options.trim >= 0.0 ? options.trim : (lowest > 0.0 ? 2.0 / lowest : 0.0);
  // A low-pass within five times the motion's band takes part of the motion with the noise;
  // friction suffers first (docs/MODEL.md, "Friction and filtering").
  if (out.trajectory_band > 0.0 && lowest > 0.0 && lowest < 5.0 * out.trajectory_band)
    out.warnings.push_back(
        "the low-pass at " + hz(lowest) + " is within five times q's trajectory band (" +
        hz(out.trajectory_band) +
        "): it smooths the motion itself, and Coulomb friction comes out low and viscous "
        "friction high (a simulated Panda filtered at 2.7 times its band: Fc 0.46-0.81x, Fv "
        "1.8-2.7x the truth; docs/MODEL.md, \"Friction and filtering\"); raise `cutoff` (and "
        "`tau_cutoff`) towards " +
        hz(5.0 * out.trajectory_band) + " if q's noise allows");
  if (!options.savitzky_golay) return;
  if (options.savgol_degree < 2 || options.savgol_degree > 6)
    throw InputError("the Savitzky-Golay degree must be 2 to 6 (ddq needs 2), not " +
                     std::to_string(options.savgol_degree));
  if (options.savgol_window > 0 &&
      (options.savgol_window % 2 == 0 || options.savgol_window <= options.savgol_degree))
    throw InputError("the Savitzky-Golay window must be odd and longer than the degree, not " +
                     std::to_string(options.savgol_window));
  // Default: about a quarter period of the cutoff (10 Hz without a filter).
  const double reference = out.cutoff > 0.0 ? out.cutoff : 10.0;
  int minimum = options.savgol_degree + 2;
  if (minimum % 2 == 0) ++minimum;
  out.savgol_window =
      options.savgol_window > 0
          ? options.savgol_window
          : std::max(minimum, 2 * static_cast<int>(std::lround(out.rate / (8.0 * reference))) + 1);
}

Filters designFilters(const PrepareOptions& options, const PrepareOutcome& out) {
  Filters filters;
  for (const auto& [cutoff, option] :
       {std::pair{out.cutoff, "`cutoff`"}, std::pair{out.tau_cutoff, "`tau_cutoff`"}})
    if (cutoff > 0.0 && !(cutoff < out.rate / 2.0))
      throw InputError(std::string(option) + " " + formatNumber(cutoff) +
                       " Hz must be below the Nyquist frequency of the output rate (" +
                       formatNumber(out.rate / 2.0) + " Hz; `rate` " + formatNumber(out.rate) +
                       ")");
  if (out.cutoff > 0.0) filters.q = butterworthLowPass(options.order, out.cutoff, out.rate);
  filters.tau_as_q = out.tau_cutoff == out.cutoff;
  if (out.tau_cutoff > 0.0 && !filters.tau_as_q)
    filters.tau = butterworthLowPass(options.order, out.tau_cutoff, out.rate);
  else if (filters.tau_as_q)
    filters.tau = filters.q;
  return filters;
}

}  // namespace dynid::prepare_steps
