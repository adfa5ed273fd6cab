#include "identifiability/rows/fit_rows.hpp"

#include <cmath>

#include "core/drive_terms.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/memory.hpp"
#include "core/signal.hpp"

namespace dynid {

std::string TorqueFilter::describe() const {
  if (!active()) return "none";
  return "order-" + std::to_string(order) + " Butterworth at " + formatNumber(cutoff, 4) +
         " Hz (zero phase), sampled at " + formatNumber(rate, 6) + " Hz";
}

int filterReach(const TorqueFilter& filter) {
  const std::vector<Biquad> sections = butterworthLowPass(filter.order, filter.cutoff, filter.rate);
  // The zero-phase impulse response: a unit sample in the middle of zeros long enough that the
  // ends' padding (odd reflection) leaves it untouched to the transient's 1e-9.
  const int half = 2 * padTransient(sections);
  Eigen::VectorXd h = Eigen::VectorXd::Zero(2 * half + 1);
  h[half] = 1.0;
  filtfiltInPlace(sections, h);
  const double total = h.cwiseAbs().sum();
  double outside = total - std::abs(h[half]);  // beyond a reach of 0
  int reach = 0;
  while (reach < half && outside > kFilterReachShare * total) {
    ++reach;
    outside -= std::abs(h[half - reach]) + std::abs(h[half + reach]);
  }
  return reach;
}

FitRows::FitRows(const Model& model) : model_(model) {
  for (int k = 0; k < kDriveTermCount; ++k)
    if (model.driveTerms().has(k) && kDriveTermTable[k].signed_by_velocity)
      signed_terms_.push_back(k);
}

namespace {

/// The first sample of each run of `time` (steps above 1.5 / rate, or not increasing, start one),
/// and its end: boundaries[r] .. boundaries[r + 1].
std::vector<Eigen::Index> runBoundaries(const Eigen::VectorXd& time, double rate) {
  std::vector<Eigen::Index> out{0};
  const double longest = 1.5 / rate;
  for (Eigen::Index k = 1; k < time.size(); ++k) {
    const double step = time[k] - time[k - 1];
    if (!(step > 0.0) || step > longest) out.push_back(k);
  }
  out.push_back(time.size());
  return out;
}

}  // namespace

FitRows::FitRows(const Model& model, const Eigen::VectorXd& time, const Eigen::MatrixXd& dq,
                 const TorqueFilter& filter)
    : FitRows(model) {
  const int n = model.numJoints();
  if (dq.rows() != n || dq.cols() != time.size())
    throw InputError("the rows of a fit: " + std::to_string(dq.rows()) + " x " +
                     std::to_string(dq.cols()) + " velocities and " + std::to_string(time.size()) +
                     " stamps for " + std::to_string(n) + " joints");
  if (!filter.active() || !(filter.rate > 0.0))
    throw InputError("the rows of a filtered fit need the torque's filter and its rate");
  filter_ = filter;
  reach_ = filterReach(filter);
  if (signed_terms_.empty()) return;  // nothing the filter changes, nothing left out
  const auto terms = static_cast<Eigen::Index>(signed_terms_.size());
  const Eigen::Index samples = time.size();
  requireMemory(static_cast<double>(samples) * static_cast<double>(n) *
                    (static_cast<double>(terms) * sizeof(double) + 1.0),
                std::to_string(samples) + " samples' filtered friction columns");
  const std::vector<Biquad> sections = butterworthLowPass(filter.order, filter.cutoff, filter.rate);
  fitted_.resize(n, samples);
  columns_.resize(static_cast<Eigen::Index>(n) * terms, samples);
  const std::vector<Eigen::Index> runs = runBoundaries(time, filter.rate);
  // Each sample's acceleration by central differences within its run (one-sided at its ends).
  Eigen::MatrixXd ddq(n, samples);
  for (std::size_t r = 0; r + 1 < runs.size(); ++r) {
    const Eigen::Index first = runs[r], last = runs[r + 1] - 1;
    for (Eigen::Index k = first; k <= last; ++k) {
      const Eigen::Index a = std::max(first, k - 1), b = std::min(last, k + 1);
      ddq.col(k) = b > a ? Eigen::VectorXd((dq.col(b) - dq.col(a)) / (time[b] - time[a]))
                         : Eigen::VectorXd::Zero(n);
    }
  }
  const double denominator = static_cast<double>(std::max<Eigen::Index>(samples, 1));
  std::vector<double> slow(static_cast<std::size_t>(n)), calm(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    slow[static_cast<std::size_t>(j)] =
        kDwellSpeedShare * std::sqrt(dq.row(j).squaredNorm() / denominator);
    calm[static_cast<std::size_t>(j)] =
        kDwellAccelerationShare * std::sqrt(ddq.row(j).squaredNorm() / denominator);
  }
  Eigen::VectorXd x;
  std::vector<Eigen::Index> resting;  // per run: resting samples before each index (a prefix sum)
  for (std::size_t r = 0; r + 1 < runs.size(); ++r) {
    const Eigen::Index first = runs[r], count = runs[r + 1] - first;
    for (int j = 0; j < n; ++j) {
      const double rest = model.restVelocity(j);
      const double slow_j = slow[static_cast<std::size_t>(j)],
                   calm_j = calm[static_cast<std::size_t>(j)];
      for (Eigen::Index t = 0; t < terms; ++t) {
        x.resize(count);
        for (Eigen::Index k = 0; k < count; ++k)
          x[k] =
              driveBasis(signed_terms_[static_cast<std::size_t>(t)], dq(j, first + k), 0.0, rest);
        if (count >= 2) filtfiltInPlace(sections, x);
        columns_.row(j * terms + t).segment(first, count) = x.transpose();
      }
      // A sample is static where the joint rests, and where it dwells: slow and hardly
      // accelerating (a stick the filter smooths into a creep), not passing through zero.
      resting.assign(static_cast<std::size_t>(count + 1), 0);
      for (Eigen::Index k = 0; k < count; ++k) {
        const double sign = signOutside(dq(j, first + k), rest);
        const bool dwell =
            std::abs(dq(j, first + k)) <= slow_j && std::abs(ddq(j, first + k)) <= calm_j;
        const bool still = sign == 0.0 || dwell;
        resting[static_cast<std::size_t>(k + 1)] =
            resting[static_cast<std::size_t>(k)] + (still ? 1 : 0);
      }
      for (Eigen::Index k = 0; k < count; ++k) {
        const Eigen::Index lo = std::max<Eigen::Index>(0, k - reach_),
                           hi = std::min<Eigen::Index>(count, k + reach_ + 1);
        fitted_(j, first + k) =
            resting[static_cast<std::size_t>(hi)] == resting[static_cast<std::size_t>(lo)] ? 1 : 0;
      }
    }
  }
}

bool FitRows::fitted(long long s, int j, double dq_j) const {
  if (signed_terms_.empty()) return true;
  if (fitted_.size() > 0) {
    if (s < 0 || s >= fitted_.cols())
      throw InputError("sample " + std::to_string(s) + " of a training set of " +
                       std::to_string(fitted_.cols()) + " whose rows were measured");
    return fitted_(j, static_cast<Eigen::Index>(s)) != 0;
  }
  return std::abs(dq_j) > kSignMargin * model_.restVelocity(j);
}

void FitRows::apply(long long s, const Eigen::Ref<const Eigen::VectorXd>& dq,
                    Eigen::Ref<Eigen::MatrixXd> Y, Eigen::Ref<Eigen::VectorXd> tau) const {
  if (signed_terms_.empty()) return;
  const ParameterLayout layout = model_.parameterLayout();
  const auto terms = static_cast<Eigen::Index>(signed_terms_.size());
  for (int j = 0; j < model_.numJoints(); ++j) {
    if (!fitted(s, j, dq[j])) {
      Y.row(j).setZero();
      tau[j] = 0.0;
      continue;
    }
    if (columns_.size() == 0) continue;
    for (Eigen::Index t = 0; t < terms; ++t)
      Y(j, layout.driveIndex(j, signed_terms_[static_cast<std::size_t>(t)])) =
          columns_(j * terms + t, static_cast<Eigen::Index>(s));
  }
}

double FitRows::filteredDriveCorrection(const Model& identified, long long s, int j,
                                        double dq_j) const {
  if (columns_.size() == 0) return 0.0;
  const auto terms = static_cast<Eigen::Index>(signed_terms_.size());
  double out = 0.0;
  for (Eigen::Index t = 0; t < terms; ++t) {
    const int k = signed_terms_[static_cast<std::size_t>(t)];
    out += identified.drives()[static_cast<std::size_t>(j)].term(k) *
           (columns_(j * terms + t, static_cast<Eigen::Index>(s)) -
            driveBasis(k, dq_j, 0.0, model_.restVelocity(j)));
  }
  return out;
}

}  // namespace dynid
