#include "analysis/logs/rest.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace dynid {

namespace {

/// The p-quantile (0..1) of `values` (reordered), 0 for none.
double quantile(std::vector<double>& values, double p) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::ptrdiff_t>(p * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[static_cast<std::size_t>(k)];
}

/// 3 sigma of v's white noise: the MAD of v less its centred quadratic Savitzky-Golay fit. For
/// white noise that residual has variance sigma^2 (1 - c0), c0 the fit's centre weight.
double noiseLevel(const Eigen::VectorXd& v) {
  const int m = kRestNoiseWindow / 2;
  const Eigen::Index n = v.size();
  if (n < kRestNoiseWindow) return 0.0;
  const double denominator = (4.0 * m * m - 1.0) * (2.0 * m + 3.0);
  std::vector<double> weights(static_cast<std::size_t>(2 * m + 1));
  for (int k = -m; k <= m; ++k)
    weights[static_cast<std::size_t>(k + m)] =
        (3.0 * (3.0 * m * m + 3.0 * m - 1.0) - 15.0 * k * k) / denominator;
  std::vector<double> residual;
  residual.reserve(static_cast<std::size_t>(n - 2 * m));
  for (Eigen::Index t = m; t < n - m; ++t) {
    double fit = 0.0;
    for (int k = -m; k <= m; ++k) fit += weights[static_cast<std::size_t>(k + m)] * v[t + k];
    residual.push_back(v[t] - fit);
  }
  const double centre = quantile(residual, 0.5);
  for (double& r : residual) r = std::abs(r - centre);
  const double sigma = 1.4826 * quantile(residual, 0.5) / std::sqrt(1.0 - weights[m]);
  return 3.0 * sigma;
}

/// The chatter of v: |v| over its sign runs shorter than kRestChatterSeconds (exact zeros join the
/// run they fall in). The first and the last run are cut by the log's ends, so their length says
/// nothing: they never count (a log that ends 0.13 s after a reversal ends in a run of motion,
/// not of chatter: the simulated PUMA's joint 3 then had a rest velocity of 0.23 rad/s). Returns
/// the 99th percentile and counts the runs; 0 when the runs' median |v| is within
/// kRestChatterSmoothness sigma of the white noise (3 sigma = `noise_level`).
double chatterLevel(const Eigen::VectorXd& v, const Eigen::VectorXd& time, double noise_level,
                    long& runs) {
  std::vector<double> chatter;
  runs = 0;
  const Eigen::Index n = v.size();
  Eigen::Index start = 0;
  int sign = 0;
  bool first = true;                          // the run from the log's start is cut
  const auto close = [&](Eigen::Index end) {  // the run [start, end)
    if (first) {
      first = false;
      return;
    }
    if (end <= start || time[end - 1] - time[start] >= kRestChatterSeconds) return;
    ++runs;
    for (Eigen::Index t = start; t < end; ++t) chatter.push_back(std::abs(v[t]));
  };
  for (Eigen::Index t = 0; t < n; ++t) {
    const int s = v[t] > 0.0 ? 1 : (v[t] < 0.0 ? -1 : 0);
    if (s == 0 || s == sign) continue;
    if (sign != 0) {
      close(t);
      start = t;
    }
    sign = s;
  }
  // The last run is cut by the log's end: it does not count.
  if (runs < kRestMinChatterRuns) return 0.0;
  const double top = quantile(chatter, 0.99);
  if (quantile(chatter, 0.5) <= kRestChatterSmoothness * noise_level / 3.0) return 0.0;
  return top;
}

}  // namespace

std::string RestVelocity::source() const {
  if (given) return "given";
  if (std::max(chatter_level, noise_level) < kRestVelocityFloor) return "floor";
  return chatter_level > noise_level ? "chatter" : "noise";
}

std::vector<long> samplesAtRest(const std::vector<double>& rest, const Eigen::MatrixXd& dq) {
  std::vector<long> out(rest.size(), 0);
  for (std::size_t j = 0; j < rest.size() && static_cast<Eigen::Index>(j) < dq.rows(); ++j)
    out[j] = (dq.row(static_cast<Eigen::Index>(j)).array().abs() <= rest[j]).count();
  return out;
}

std::vector<RestVelocity> measureRestVelocities(const Eigen::MatrixXd& dq,
                                                const Eigen::VectorXd& time) {
  if (dq.cols() != time.size())
    throw InputError("rest velocities: " + std::to_string(dq.cols()) + " velocity samples but " +
                     std::to_string(time.size()) + " stamps");
  std::vector<RestVelocity> out(static_cast<std::size_t>(dq.rows()));
  for (Eigen::Index j = 0; j < dq.rows(); ++j) {
    RestVelocity& r = out[static_cast<std::size_t>(j)];
    const Eigen::VectorXd v = dq.row(j).transpose();
    r.noise_level = noiseLevel(v);
    r.chatter_level = chatterLevel(v, time, r.noise_level, r.chatter_runs);
    r.velocity = std::max({r.noise_level, r.chatter_level, kRestVelocityFloor});
    r.samples = v.size();
    r.samples_at_rest = (v.array().abs() <= r.velocity).count();
  }
  return out;
}

std::vector<RestVelocity> givenRestVelocities(const std::vector<double>& given,
                                              const Eigen::MatrixXd& dq) {
  const auto joints = static_cast<std::size_t>(dq.rows());
  if (given.size() != 1 && given.size() != joints)
    throw InputError("`rest_velocity` has " + std::to_string(given.size()) +
                     " values; give one for every joint or one per joint (" +
                     std::to_string(joints) + ")");
  std::vector<RestVelocity> out(joints);
  for (std::size_t j = 0; j < joints; ++j) {
    const double v = given.size() == 1 ? given[0] : given[j];
    if (!std::isfinite(v) || v < 0.0)
      throw InputError("`rest_velocity` must be finite and >= 0, not " + std::to_string(v));
    out[j].velocity = v;
    out[j].given = true;
    out[j].samples = dq.cols();
  }
  const std::vector<long> at_rest = samplesAtRest(restThresholds(out), dq);
  for (std::size_t j = 0; j < joints; ++j) out[j].samples_at_rest = at_rest[j];
  return out;
}

std::vector<double> restThresholds(const std::vector<RestVelocity>& rest) {
  std::vector<double> out;
  out.reserve(rest.size());
  for (const RestVelocity& r : rest) out.push_back(r.velocity);
  return out;
}

}  // namespace dynid
