#include "analysis/payload.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "analysis/records/document.hpp"
#include "analysis/records/prepare_record.hpp"
#include "analysis/runs.hpp"
#include "core/checks.hpp"
#include "core/drive_terms.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "core/parameters.hpp"
#include "core/regressor.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/robots.hpp"
#include "data/urdf_writeback.hpp"

namespace dynid {

namespace {

constexpr double kZ95 = 1.959963984540054;  // two-sided 95 % normal quantile

/// Median sample step [s].
double medianStep(const Eigen::VectorXd& t) {
  if (t.size() < 2) return 0.0;
  std::vector<double> steps(static_cast<std::size_t>(t.size() - 1));
  for (Eigen::Index k = 0; k + 1 < t.size(); ++k) steps[k] = t[k + 1] - t[k];
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return steps[steps.size() / 2];
}

/// Mean squared position difference of loaded sample k against unloaded sample k + s over the
/// overlap, every `stride`-th sample.
double mismatch(const Eigen::MatrixXd& ql, const Eigen::MatrixXd& qu, long s, long stride) {
  const long nl = ql.cols(), nu = qu.cols();
  const long first = std::max(0L, -s), last = std::min(nl, nu - s);
  double sum = 0.0;
  long count = 0;
  for (long k = first; k < last; k += stride, ++count)
    sum += (ql.col(k) - qu.col(k + s)).squaredNorm();
  return count > 0 ? sum / count : std::numeric_limits<double>::infinity();
}

struct Alignment {
  long shift = 0;  // unloaded sample = loaded sample + shift
  Eigen::VectorXd rms;
};

/// The integer sample shift that best overlays the unloaded run's positions on the loaded run's
/// (overlap at least half the shorter run): a coarse search on every D-th shift and sample, then
/// every shift around the best.
Alignment alignRuns(const Trajectory& loaded, const Trajectory& unloaded) {
  const long nl = loaded.numSamples(), nu = unloaded.numSamples();
  const long overlap = std::min(nl, nu) / 2;
  const long stride = std::max(1L, std::min(nl, nu) / 1000);
  long best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  for (long s = -(nl - overlap); s <= nu - overlap; s += stride) {
    const double c = mismatch(loaded.q, unloaded.q, s, stride);
    if (c < best_cost) best_cost = c, best = s;
  }
  const long centre = best;
  best_cost = std::numeric_limits<double>::infinity();
  for (long s = std::max(centre - stride, -(nl - overlap));
       s <= std::min(centre + stride, nu - overlap); ++s) {
    const double c = mismatch(loaded.q, unloaded.q, s, 1);
    if (c < best_cost) best_cost = c, best = s;
  }
  Alignment out;
  out.shift = best;
  const long first = std::max(0L, -best), last = std::min(nl, nu - best);
  out.rms = ((loaded.q.middleCols(first, last - first) -
              unloaded.q.middleCols(first + best, last - first))
                 .rowwise()
                 .squaredNorm() /
             static_cast<double>(std::max(1L, last - first)))
                .cwiseSqrt();
  return out;
}

/// The gradient of f at `at` by central differences (steps of 1e-6 of each parameter's size).
template <class F>
Vector10d centralGradient(const Vector10d& at, F f) {
  Vector10d gradient;
  for (int k = 0; k < 10; ++k) {
    const double h = 1e-6 * std::max(std::abs(at[k]), 1e-6 * std::abs(at[0]) + 1e-12);
    Vector10d up = at, down = at;
    up[k] += h;
    down[k] -= h;
    gradient[k] = (f(up) - f(down)) / (2.0 * h);
  }
  return gradient;
}

/// Variance of a scalar function's linearisation: j^T C j, where an entry of infinite variance
/// that j touches makes it infinite.
double propagate(const Matrix10d& c, const Vector10d& j) {
  for (int k = 0; k < 10; ++k)
    if (j[k] != 0.0 && !std::isfinite(c(k, k))) return std::numeric_limits<double>::infinity();
  double v = 0.0;
  for (int a = 0; a < 10; ++a)
    for (int b = 0; b < 10; ++b)
      if (j[a] != 0.0 && j[b] != 0.0) v += j[a] * c(a, b) * j[b];
  return std::max(v, 0.0);
}

/// The derived quantities of a body (m, c, I_c's six entries, principal moments): 13 values.
Eigen::Matrix<double, 13, 1> derived(const Vector10d& p) {
  Eigen::Matrix<double, 13, 1> out;
  const double m = p[0];
  const Eigen::Vector3d c =
      m != 0.0 ? Eigen::Vector3d(p.segment<3>(1) / m) : Eigen::Vector3d::Zero();
  const Eigen::Matrix3d ic = inertiaAboutCom(fromStandardVector(p));
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(ic).eigenvalues();
  out << m, c, ic(0, 0), ic(0, 1), ic(0, 2), ic(1, 1), ic(1, 2), ic(2, 2), moments;
  return out;
}

const std::array<const char*, 13> kDerivedNames = {
    "m", "cx", "cy", "cz", "Ixx_c", "Ixy_c", "Ixz_c", "Iyy_c", "Iyz_c", "Izz_c", "I1", "I2", "I3"};

/// The share of a value its 95 % half-width may reach for the value to count as determined.
constexpr double kDeterminedShare = 0.2;
/// ... and for a drive gain: 0.5 % (so that a scale reported determined is within 1 % at four
/// standard deviations).
constexpr double kGainShare = 0.005;
/// ... and for a principal axis: 10 degrees.
constexpr double kAxisAngle = 10.0 * M_PI / 180.0;

/// The 95 % half-width below which a quantity counts as determined (docs/PAYLOAD.md): 20 % of its
/// magnitude for the mass and the principal moments; 5 mm for a centre-of-mass coordinate; 20 %
/// of the largest principal moment for an entry of the inertia about the centre of mass.
double determinedBound(int k, const Eigen::Matrix<double, 13, 1>& v) {
  if (k == 0) return kDeterminedShare * std::abs(v[0]);
  if (k <= 3) return 5e-3;
  const double largest = std::max({std::abs(v[10]), std::abs(v[11]), std::abs(v[12])});
  if (k <= 9) return kDeterminedShare * largest;
  return kDeterminedShare * std::abs(v[k]);
}

std::string combinationText(const Vector10d& direction, const std::vector<std::string>& names) {
  const double top = direction.cwiseAbs().maxCoeff();
  std::ostringstream text;
  bool first = true;
  for (int k = 0; k < 10; ++k) {
    const double c = direction[k] / top;
    if (std::abs(c) < 0.1) continue;
    text << (first ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + "));
    if (std::abs(std::abs(c) - 1.0) > 1e-3) text << formatNumber(std::abs(c), 3) << "*";
    text << names[k];
    first = false;
  }
  return text.str();
}

int linkIndex(const Model& arm, const std::string& link) {
  if (link.empty()) return arm.numJoints() - 1;
  for (int i = 0; i < arm.numJoints(); ++i)
    if (arm.link_names[i] == link) return i;
  std::string names;
  for (const std::string& l : arm.link_names) names += (names.empty() ? "" : ", ") + l;
  throw InputError("link '" + link + "' is not a moving link of robot '" + arm.name +
                   "' (its links: " + names + ")");
}

}  // namespace

void PayloadRequest::check() const {
  checkOption("payload", "prior-weight", prior_weight, "prior_weight");
  if (known_mass) checkOption("payload", "payload-mass", *known_mass, "known_mass");
  checkOption("payload", "max-motion-difference", max_motion_difference, "max_motion_difference");
  if (known_com && !known_mass)
    throw InputError("known_com: a known centre of mass needs the known mass");
  if (known_com && !known_com->allFinite())
    throw InputError("known_com: the centre of mass must be finite");
  if (known_mass && unloaded_file.empty() && unloaded == nullptr)
    throw InputError("known_mass: drive gains need the unloaded run of the same motion");
  if (!tool.translation.allFinite() || !tool.rotation.allFinite() ||
      tool.translation.norm() > kMaxModelLength ||
      !(tool.rotation.transpose() * tool.rotation).isApprox(Eigen::Matrix3d::Identity(), 1e-9) ||
      tool.rotation.determinant() < 0.0)
    throw InputError("tool: the attachment frame must be a finite rigid transform");
  if (prior) {
    if (!prior->allFinite() || !((*prior)[0] > 0.0))
      throw InputError("prior: the prior payload must have a finite, positive mass");
    const auto violations = checkPhysicalConsistency(fromStandardVector(*prior), 0, "prior");
    if (!violations.empty())
      throw InputError("prior: the prior payload is not physically consistent (" +
                       violations[0].condition + ": " + violations[0].detail + ")");
  }
  if (data_file.empty() && data == nullptr)
    throw InputError("data_file: a log with the payload attached is needed");
}

namespace {
/// The derived quantities with their intervals, the principal axes, what the motion does not
/// see or sees only together, and the smallest payload resolved.
/// One quantity with its 95 % interval; determined when the half width is within `bound`.
void addQuantity(PayloadOutcome& out, const std::string& name, const std::string& unit,
                 const std::string& group, double value, double variance, double bound) {
  PayloadQuantity q;
  q.name = name;
  q.unit = unit;
  q.group = group;
  q.value = value;
  q.std_dev = std::sqrt(variance);
  q.half_width = kZ95 * q.std_dev;
  q.determined = std::isfinite(q.half_width) && q.half_width <= bound;
  out.quantities.push_back(q);
}

/// The principal axes' angles with their 95 % intervals, and a warning when one is loose.
void describeAxes(PayloadOutcome& out, const PrincipalBody& principal) {
  const auto add = [&](const std::string& name, const std::string& unit, const std::string& group,
                       double v, double var,
                       double bound) { addQuantity(out, name, unit, group, v, var, bound); };
  // The principal axes: axis a turns toward axis b by v_b^T dI_c v_a / (lambda_a - lambda_b) to
  // first order; its 95 % angle is that of the two turns together. The value is the axis's angle
  // from the attachment frame's axis of the same index.
  bool axes_determined = true;
  for (int a = 0; a < 3; ++a) {
    double angle_variance = 0.0;
    for (int b = 0; b < 3; ++b) {
      if (b == a) continue;
      const double gap = principal.moments[a] - principal.moments[b];
      if (gap == 0.0) {
        angle_variance = std::numeric_limits<double>::infinity();
        break;
      }
      const Eigen::Vector3d va = principal.axes.col(a), vb = principal.axes.col(b);
      const Vector10d gradient = centralGradient(out.standard, [&](const Vector10d& p) {
        return vb.dot(inertiaAboutCom(fromStandardVector(p)) * va) / gap;
      });
      angle_variance += propagate(out.covariance, gradient);
    }
    const double value = std::acos(std::clamp(std::abs(principal.axes(a, a)), 0.0, 1.0));
    add(std::string("axis").append(std::to_string(a + 1)), "rad", "principal axes", value,
        angle_variance, kAxisAngle);
    axes_determined = axes_determined && out.quantities.back().determined;
  }
  if (!axes_determined)
    out.warnings.push_back(
        "the principal axes are not all determined to 10 degrees (two principal moments lie "
        "within each other's intervals): KUKA's A, B, C and ABB's aom are then one choice among "
        "those the data allow; the inertia about the centre of mass (UR, Franka) is what the "
        "data give");
}

/// What the motion does not see, and what it sees only in combination.
void describeCombinations(PayloadOutcome& out, const PayloadFit& fit,
                          const std::vector<std::string>& names) {
  for (Eigen::Index c = 0; c < fit.null_directions.cols(); ++c)
    out.unseen.push_back(combinationText(fit.null_directions.col(c), names));
  {
    std::vector<int> loose;
    for (int k = 0; k < 10; ++k) {
      const PayloadQuantity& q = out.quantities[13 + k];
      if (!q.determined && std::isfinite(q.std_dev)) loose.push_back(k);
    }
    if (loose.size() >= 2) {
      const Vector10d scale =
          (Vector10d() << 1, 0.1, 0.1, 0.1, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01).finished();
      Eigen::MatrixXd c(loose.size(), loose.size());
      for (std::size_t a = 0; a < loose.size(); ++a)
        for (std::size_t b = 0; b < loose.size(); ++b)
          c(a, b) = out.covariance(loose[a], loose[b]) / (scale[loose[a]] * scale[loose[b]]);
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(c);
      for (Eigen::Index e = 0; e < eigen.eigenvalues().size(); ++e) {
        Vector10d direction = Vector10d::Zero();
        for (std::size_t a = 0; a < loose.size(); ++a)
          direction[loose[a]] =
              eigen.eigenvectors()(static_cast<Eigen::Index>(a), e) / scale[loose[a]];
        const double half = kZ95 * std::sqrt(std::max(eigen.eigenvalues()[e], 0.0));
        // Determined in combination: the combination's interval is below a tenth of the loosest
        // part's, and it has at least two parts.
        const double loosest = kZ95 * std::sqrt(c.diagonal().maxCoeff());
        int parts = 0;
        const double top = eigen.eigenvectors().col(e).cwiseAbs().maxCoeff();
        for (std::size_t a = 0; a < loose.size(); ++a)
          if (std::abs(eigen.eigenvectors()(static_cast<Eigen::Index>(a), e)) >= 0.1 * top) ++parts;
        if (parts >= 2 && half <= 0.1 * loosest)
          out.combined.push_back(combinationText(direction, names));
      }
    }
  }
}

void describeBody(PayloadOutcome& out, const PayloadFit& fit) {
  // Derived quantities and their intervals (delta method on the least-squares covariance).
  const std::vector<std::string> names = {"m",   "mx",  "my",  "mz",  "Ixx",
                                          "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
  if (!(out.standard[0] > 0.0)) throw NumericalError("the consistent payload has no mass");
  out.setBody(out.standard);
  const PrincipalBody principal{out.mass, out.com, out.principal_moments, out.principal_axes};
  const Eigen::Matrix<double, 13, 1> value = derived(out.standard);
  Eigen::Matrix<double, 13, 1> variance;
  for (int i = 0; i < 13; ++i)
    variance[i] =
        propagate(out.covariance,
                  centralGradient(out.standard, [&](const Vector10d& p) { return derived(p)[i]; }));
  // The principal moments in the order of `principal.moments` (the axes' order).
  Eigen::Vector3d moment_variance;
  {
    const Eigen::Vector3d sorted = value.tail<3>();
    for (int a = 0; a < 3; ++a) {
      int nearest = 0;
      for (int b = 1; b < 3; ++b)
        if (std::abs(sorted[b] - principal.moments[a]) <
            std::abs(sorted[nearest] - principal.moments[a]))
          nearest = b;
      moment_variance[a] = variance[10 + nearest];
    }
  }
  const auto add = [&](const std::string& name, const std::string& unit, const std::string& group,
                       double v, double var,
                       double bound) { addQuantity(out, name, unit, group, v, var, bound); };
  for (int i = 0; i < 10; ++i) {
    const char* unit = i == 0 ? "kg" : i <= 3 ? "m" : "kg m^2";
    const char* group = i == 0   ? "mass"
                        : i <= 3 ? "centre of mass"
                                 : "inertia about the centre of mass";
    add(kDerivedNames[i], unit, group, value[i], variance[i], determinedBound(i, value));
  }
  for (int a = 0; a < 3; ++a)
    add(std::string("I").append(std::to_string(a + 1)), "kg m^2", "principal moments",
        principal.moments[a], moment_variance[a],
        kDeterminedShare * std::abs(principal.moments[a]));
  // The standard parameters on the same rules: mass; m x 5 mm; 20 % of the largest diagonal
  // inertia.
  const double largest_diagonal =
      std::max({std::abs(out.standard[4]), std::abs(out.standard[7]), std::abs(out.standard[9])});
  for (int k = 0; k < 10; ++k) {
    const double bound = k == 0   ? kDeterminedShare * std::abs(out.standard[0])
                         : k <= 3 ? 5e-3 * std::abs(out.standard[0])
                                  : kDeterminedShare * largest_diagonal;
    add(names[k],
        k == 0   ? "kg"
        : k <= 3 ? "kg m"
                 : "kg m^2",
        "standard parameters", out.standard[k], out.covariance(k, k), bound);
  }

  describeAxes(out, principal);

  describeCombinations(out, fit, names);
  out.smallest_mass = kZ95 * std::sqrt(variance[0]) / kDeterminedShare;
  out.smallest_moment = kZ95 * std::sqrt(moment_variance.maxCoeff()) / kDeterminedShare;
}

/// Advice when the mass, centre of mass or inertia is not determined.
void adviseOnMotion(PayloadOutcome& out, const Trajectory& loaded) {
  const int n = loaded.numJoints();
  // Advice: the wrist joint that moved least.
  bool inertia_undetermined = false, com_undetermined = false;
  for (const PayloadQuantity& q : out.quantities) {
    if (q.group == "principal moments" && !q.determined) inertia_undetermined = true;
    if (q.group == "centre of mass" && !q.determined) com_undetermined = true;
  }
  if (!out.quantities[0].determined)
    out.advice.push_back("the mass is not determined: the payload (" + formatNumber(out.mass, 3) +
                         " kg) is below what this log resolves (" +
                         formatNumber(out.smallest_mass, 3) +
                         " kg to +-20 %): record a longer or faster motion, or use a less noisy "
                         "torque signal");
  if (com_undetermined || inertia_undetermined || !out.unseen.empty()) {
    int least = std::max(0, n - 3);
    double least_rms = std::numeric_limits<double>::infinity();
    for (int j = std::max(0, n - 3); j < n; ++j) {
      const double rms = std::sqrt(loaded.dq.row(j).squaredNorm() / loaded.numSamples());
      if (rms < least_rms) least_rms = rms, least = j;
    }
    out.advice.push_back(
        std::string(inertia_undetermined ? "the inertia" : "the centre of mass") +
        " is not determined by this motion: rotate the wrist more, joint " +
        std::to_string(least + 1) + " above all (RMS speed " + formatNumber(least_rms, 3) +
        " rad/s in this log), and in several orientations; dynid excite --payload designs such a "
        "motion");
  }
}

/// The arm's friction terms re-estimated with the payload: each extra column's arm value, value
/// with the payload and standard deviation.
std::vector<FrictionChange> frictionChanges(const ParameterLayout& layout,
                                            const std::vector<int>& extra_columns,
                                            const Eigen::VectorXd& theta_arm,
                                            const PayloadFit& fit) {
  std::vector<FrictionChange> out;
  const std::vector<std::string> names = standardParameterNames(layout);
  for (std::size_t i = 0; i < extra_columns.size(); ++i) {
    FrictionChange c;
    c.name = names[static_cast<std::size_t>(extra_columns[i])];
    c.arm = theta_arm[extra_columns[i]];
    c.with_payload = c.arm + fit.extra[static_cast<Eigen::Index>(i)];
    c.std_dev =
        std::sqrt(fit.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)));
    out.push_back(c);
  }
  return out;
}

/// The arm's URDF (carrying the arm's parameters when it was given as a model) with the payload
/// as a fixed link on its attachment link.
std::string urdfWithPayload(const PayloadRequest& request, const Model& arm,
                            const PayloadOutcome& out) {
  std::string text = readFile(request.urdf_file);
  if (request.urdf_carries_arm) text = urdfWithParameters(text, request.urdf_file, arm);
  return urdfWithFixedBody(text, request.urdf_file, out.link_name, "payload", request.tool,
                           fromStandardVector(out.standard));
}

/// Drive gains from the known mass: the body rows (the extra columns dropped) fitted with it.
DriveGains driveGains(const PayloadRequest& request, const PayloadRows& rows, int f,
                      const Eigen::VectorXd& arm_difference) {
  const int n = rows.numJoints();
  DriveGains gains;
  {
    PayloadRows body_rows(n, 0);
    body_rows.reserve(rows.numSamples());
    const Eigen::MatrixXd design = rows.design();
    const Eigen::VectorXd target = rows.target();
    const Eigen::MatrixXd none(n, 0);
    for (int k = 0; k < rows.numSamples(); ++k)
      body_rows.add(design.block(static_cast<Eigen::Index>(k) * n, f, n, 10), none,
                    target.segment(static_cast<Eigen::Index>(k) * n, n));
    const GainFit g =
        fitDriveGains(body_rows, *request.known_mass, request.known_com, 0, arm_difference);
    gains.scale = g.scale;
    gains.scale_std = g.scale_std;
    gains.iterations = g.iterations;
    for (int j = 0; j < n; ++j)
      gains.determined.push_back(kZ95 * g.scale_std[j] <= kGainShare * std::abs(g.scale[j]) ? 1
                                                                                            : 0);
    const PreparationFound found = findPreparation(request.data_file);
    if (found.record && static_cast<int>(found.record->torque_constants.size()) == n)
      for (int j = 0; j < n; ++j)
        gains.torque_constants.push_back(found.record->torque_constants[j] * g.scale[j]);
  }

  return gains;
}

/// The unloaded run of a pair, aligned on the loaded run by position (refused when the motions
/// differ), and its residual against the arm model; `pair` false without one.
struct UnloadedRun {
  bool pair = false;
  Trajectory trajectory;
  Eigen::MatrixXd residual;  // n x its samples
  long shift = 0;            // loaded sample k pairs with unloaded sample k + shift
};
UnloadedRun unloadedRun(const PayloadRequest& request, const Trajectory& loaded, Data& data,
                        PayloadOutcome& out) {
  const Model& arm = request.arm;
  const int n = arm.numJoints();
  const Eigen::VectorXd theta_arm = arm.standardParameters();
  UnloadedRun run;
  run.pair = !request.unloaded_file.empty() || request.unloaded != nullptr;
  if (!run.pair) return run;
  Trajectory& unloaded = run.trajectory;
  {
    unloaded = request.unloaded ? *request.unloaded : readDatasetCsv(request.unloaded_file, n);
    if (unloaded.numJoints() != n)
      throw InputError(request.unloaded_file + ": " + std::to_string(unloaded.numJoints()) +
                       " joints, the arm has " + std::to_string(n));
    const double dl = medianStep(loaded.time), du = medianStep(unloaded.time);
    if (unloaded.numSamples() < 2 || !(std::abs(dl - du) <= 1e-6 * dl))
      throw InputError(request.unloaded_file + ": sampled every " + formatNumber(du) +
                       " s, the loaded run every " + formatNumber(dl) +
                       " s: prepare both at one rate (dynid prepare --rate)");
    const Alignment a = alignRuns(loaded, unloaded);
    run.shift = a.shift;
    out.shift = static_cast<double>(a.shift) * dl;
    out.motion_difference = a.rms;
    for (int j = 0; j < n; ++j)
      if (!(a.rms[j] <= request.max_motion_difference))
        throw InputError(request.unloaded_file + ": its motion differs from " + request.data_file +
                         "'s: joint " + std::to_string(j + 1) + " is " + formatNumber(a.rms[j], 3) +
                         " rad RMS apart after the best time shift (" + formatNumber(out.shift, 4) +
                         " s; at most " + formatNumber(request.max_motion_difference) +
                         " rad): record the same commanded motion with and without the payload, "
                         "or, when the payload's weight alone pulls the arm off its path, allow "
                         "more with --max-motion-difference (each run's own motion is used, so "
                         "the arm model's errors then cancel less)");
    run.residual.resize(n, unloaded.numSamples());
    for (int k = 0; k < unloaded.numSamples(); ++k)
      run.residual.col(k) =
          unloaded.tau.col(k) - jointTorqueRegressor(arm, data, unloaded.q.col(k),
                                                     unloaded.dq.col(k), unloaded.ddq.col(k)) *
                                    theta_arm;
  }
  return run;
}

/// With refit_friction: the arm's non-inertial drive-term columns of the joints that move.
std::vector<int> frictionColumns(const PayloadRequest& request, const Trajectory& loaded) {
  const ParameterLayout layout = request.arm.parameterLayout();
  const int n = request.arm.numJoints();
  std::vector<int> extra_columns;
  if (request.refit_friction) {
    for (int j = 0; j < n; ++j) {
      const double rms = std::sqrt(loaded.dq.row(j).squaredNorm() / loaded.numSamples());
      if (!(rms > 1e-3)) continue;
      for (int t = 0; t < kDriveTermCount; ++t)
        if (layout.drives.has(static_cast<DriveTerm>(t)) && !kDriveTermTable[t].inertial)
          extra_columns.push_back(layout.driveIndex(j, t));
    }
    if (extra_columns.empty())
      throw InputError(
          "refit_friction: the arm model has no friction terms (give its drive "
          "terms, e.g. --drive-terms fv,fc) or no joint moves");
  }
  return extra_columns;
}

/// A log of another robot (or in other units): a payload heavier than the arm, a residual that
/// follows the arm's own torque (refused); a heavy payload, residuals far above prepare's noise
/// (warned).
void checkPlausible(const PayloadRequest& request, const PayloadRows& rows, const PayloadFit& fit,
                    const Eigen::MatrixXd& arm_torque, PayloadOutcome& out) {
  const Model& arm = request.arm;
  const int n = arm.numJoints();
  const int f = static_cast<int>(fit.extra.size());
  // A log of another robot: a payload heavier than the whole arm.
  const double arm_mass = totalMass(arm);
  if (std::abs(out.least_squares[0]) > arm_mass)
    throw InputError(
        request.data_file + ": explaining it takes a payload of " +
        formatNumber(out.least_squares[0], 3) + " kg, more than the whole arm (" +
        formatNumber(arm_mass, 3) + " kg): is it a log of this robot (" + arm.name +
        "), with the torques in N m" +
        (out.mode == "difference" ? ", and the unloaded run of the same robot?" : "?"));
  if (std::abs(out.least_squares[0]) > 0.5 * arm_mass)
    out.warnings.push_back("the payload (" + formatNumber(out.least_squares[0], 3) +
                           " kg) weighs more than half the arm (" + formatNumber(arm_mass, 3) +
                           " kg): check that the log is of this robot and in N m");
  if (out.mode == "single") {
    // The residual against the arm model's own torque, over all joints: a log of another robot
    // (or in other units) leaves a residual that is the arm's torque scaled; noise and a fair
    // model's errors do not.
    const Eigen::MatrixXd design = rows.design();
    const Eigen::VectorXd target = rows.target();
    Eigen::VectorXd at(f + 10);
    at << fit.extra, fit.theta;
    const Eigen::VectorXd residual = target - design * at;
    const Eigen::Map<const Eigen::VectorXd> model(arm_torque.data(), residual.size());
    const double ra = residual.dot(model), aa = model.squaredNorm(), rr = residual.squaredNorm();
    if (aa > 0.0 && rr > 0.0) {
      const double slope = ra / aa, r2 = ra * ra / (aa * rr);
      if (std::abs(slope) > 0.25 && r2 > 0.5)
        throw InputError(request.data_file + ": its torques are the arm model's times " +
                         formatNumber(1.0 + slope, 3) +
                         " (what the model and a payload leave unexplained follows the arm's own "
                         "torque, R^2 " +
                         formatNumber(r2, 2) + "): is it a log of this robot (" + arm.name +
                         "), in N m, with the right torque constants?");
    }
  }

  // Residuals far above the noise prepare measured: the estimate carries the arm model's errors.
  if (const PreparationFound found = findPreparation(request.data_file);
      out.mode == "single" && found.record &&
      static_cast<int>(found.record->tau_noise_rms.size()) == n) {
    std::string joints;
    for (int j = 0; j < n; ++j) {
      const double noise = found.record->tau_noise_rms[j];
      if (std::isfinite(noise) && noise > 0.0 && out.residual_rms[j] > 5.0 * noise)
        joints += (joints.empty() ? "" : ", ") + std::to_string(j + 1) + " (" +
                  formatNumber(out.residual_rms[j] / noise, 3) + "x)";
    }
    if (!joints.empty())
      out.warnings.push_back(
          "the arm model and the payload leave more than 5 times the noise prepare measured "
          "unexplained on joint " +
          joints +
          ": the payload carries the arm model's errors; an unloaded run of the same motion "
          "(--unloaded) cancels them");
  }
}

/// The figure's samples: the payload's torque, measured and estimated, at most 2000.
void plotSamples(const PayloadRows& rows, const PayloadFit& fit, const Trajectory& loaded,
                 const std::vector<int>& used, PayloadOutcome& out) {
  const int n = loaded.numJoints();
  const int f = static_cast<int>(fit.extra.size());
  const int keep = std::min(out.samples, 2000);
  out.plot_time.resize(keep);
  out.plot_measured.resize(n, keep);
  out.plot_predicted.resize(n, keep);
  const Eigen::MatrixXd design = rows.design();
  const Eigen::VectorXd target = rows.target();
  Eigen::VectorXd at(f + 10);
  at << fit.extra, fit.theta;
  for (int i = 0; i < keep; ++i) {
    const long k = static_cast<long>(static_cast<double>(i) * out.samples / keep);
    out.plot_time[i] = loaded.time[used[k]];
    out.plot_measured.col(i) = target.segment(k * n, n);
    out.plot_predicted.col(i) = design.middleRows(k * n, n) * at;
  }
}

}  // namespace

PayloadOutcome payloadRun(const PayloadRequest& request) {
  request.check();
  const Model& arm = request.arm;
  const int n = arm.numJoints();
  const ParameterLayout layout = arm.parameterLayout();
  PayloadOutcome out;
  out.link = linkIndex(arm, request.link);
  out.link_name = arm.link_names[out.link];
  out.robot = arm.name;
  out.arm_source = request.arm_source;
  out.data_file = request.data_file;
  out.unloaded_file = request.unloaded_file;
  out.tool = request.tool;
  out.mode = request.unloaded_file.empty() && request.unloaded == nullptr ? "single" : "difference";
  out.prior_weight = request.prior_weight;
  out.prior_given = request.prior.has_value();

  const Trajectory loaded = request.data ? *request.data : readDatasetCsv(request.data_file, n);
  if (loaded.numJoints() != n)
    throw InputError(request.data_file + ": " + std::to_string(loaded.numJoints()) +
                     " joints, the arm has " + std::to_string(n));
  if (loaded.numSamples() < 2) throw InputError(request.data_file + ": fewer than 2 samples");
  const Eigen::VectorXd theta_arm = arm.standardParameters();
  Data data(arm);
  const Matrix10d to_link = standardTransform(request.tool);

  // The unloaded run: aligned on the loaded run's samples, its residual against the arm model.
  const UnloadedRun unloaded_run = unloadedRun(request, loaded, data, out);
  const bool pair = unloaded_run.pair;
  const Trajectory& unloaded = unloaded_run.trajectory;
  const Eigen::MatrixXd& unloaded_residual = unloaded_run.residual;
  const long shift = unloaded_run.shift;

  // The extra columns: the arm's non-inertial drive terms of the joints that move.
  const std::vector<int> extra_columns = frictionColumns(request, loaded);
  const int f = static_cast<int>(extra_columns.size());
  PayloadRows rows(n, f);
  rows.reserve(loaded.numSamples());
  Eigen::MatrixXd extra(n, f);
  std::vector<int> used;                               // loaded samples in the problem
  Eigen::MatrixXd arm_torque(n, loaded.numSamples());  // of the samples used, in order
  // With a pair: the arm model's torque at the loaded sample minus at the unloaded one, for the
  // drive gains (the targets have it subtracted; measured currents scale it too).
  Eigen::VectorXd arm_difference(pair ? static_cast<Eigen::Index>(n) * loaded.numSamples() : 0);
  for (int k = 0; k < loaded.numSamples(); ++k) {
    const long u = k + shift;
    if (pair && (u < 0 || u >= unloaded.numSamples())) continue;
    const Eigen::MatrixXd& Y =
        jointTorqueRegressor(arm, data, loaded.q.col(k), loaded.dq.col(k), loaded.ddq.col(k));
    const Eigen::VectorXd model_torque = Y * theta_arm;
    Eigen::VectorXd target = loaded.tau.col(k) - model_torque;
    if (pair) {
      target -= unloaded_residual.col(u);
      arm_difference.segment(static_cast<Eigen::Index>(used.size()) * n, n) =
          model_torque - (unloaded.tau.col(u) - unloaded_residual.col(u));
    }
    for (int i = 0; i < f; ++i) extra.col(i) = Y.col(extra_columns[i]);
    rows.add(Y.middleCols(layout.linkIndex(out.link, 0), 10) * to_link, extra, target);
    arm_torque.col(static_cast<Eigen::Index>(used.size())) = model_torque;
    used.push_back(k);
  }
  out.samples = rows.numSamples();

  PayloadFitOptions options;
  options.prior = request.prior;
  options.prior_weight = request.prior_weight;
  const PayloadFit fit = fitPayload(rows, options);
  out.least_squares = fit.least_squares;
  out.standard = fit.theta;
  out.prior = fit.prior;
  out.covariance = fit.covariance.bottomRightCorner(10, 10);
  out.noise = fit.noise;
  out.residual_rms = fit.residual_rms;
  out.target_rms = fit.target_rms;
  out.batch = fit.batch;
  out.least_squares_consistent = fit.least_squares_consistent;
  out.converged = fit.converged;
  out.termination = fit.termination;

  checkPlausible(request, rows, fit, arm_torque, out);
  describeBody(out, fit);
  adviseOnMotion(out, loaded);
  if (!out.least_squares_consistent)
    out.warnings.push_back(
        "the least-squares payload is not physically consistent: the consistent estimate is held "
        "inside the physical set by the prior, and its intervals are those of least squares");

  out.friction = frictionChanges(layout, extra_columns, theta_arm, fit);

  if (request.known_mass)
    out.gains = driveGains(request, rows, f,
                           arm_difference.head(static_cast<Eigen::Index>(used.size()) * n));

  plotSamples(rows, fit, loaded, used, out);
  if (!request.urdf_file.empty()) out.urdf = urdfWithPayload(request, arm, out);
  return out;
}

void PayloadOutcome::setBody(const Vector10d& body) {
  const PrincipalBody principal = principalBody(body);
  standard = body;
  mass = principal.mass;
  com = principal.com;
  principal_moments = principal.moments;
  principal_axes = principal.axes;
  inertia_com = inertiaAboutCom(fromStandardVector(body));
}

PrincipalBody principalBody(const Vector10d& standard) {
  if (!(standard[0] > 0.0)) throw InputError("a body needs a positive mass");
  PrincipalBody out;
  out.mass = standard[0];
  out.com = standard.segment<3>(1) / standard[0];
  const Eigen::Matrix3d ic = inertiaAboutCom(fromStandardVector(standard));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(ic);
  // Of the 24 proper rotations whose columns are the eigenvectors (any order, any sign), the one
  // nearest the identity.
  const std::array<std::array<int, 3>, 6> orders = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& order : orders)
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d r;
      for (int c = 0; c < 3; ++c)
        r.col(c) = eigen.eigenvectors().col(order[c]) * ((signs >> c) & 1 ? -1.0 : 1.0);
      if (r.determinant() < 0.0) continue;
      if (r.trace() > best + 1e-12) {
        best = r.trace();
        out.axes = r;
        for (int c = 0; c < 3; ++c) out.moments[c] = eigen.eigenvalues()[order[c]];
      }
    }
  return out;
}

Vector10d standardFromPrincipal(const PrincipalBody& body) {
  RigidInertia<double> out;
  out.mass = body.mass;
  out.first_moment = body.mass * body.com;
  const Eigen::Matrix3d sc = skew(body.com);
  out.inertia = body.axes * body.moments.asDiagonal() * body.axes.transpose() - body.mass * sc * sc;
  return toStandardVector(out);
}

Eigen::Vector3d kukaAbc(const Eigen::Matrix3d& r) {
  // R = Rz(A) Ry(B) Rx(C): r20 = -sin B, r10 / r00 = tan A, r21 / r22 = tan C.
  const double b = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
  double a, c;
  if (std::hypot(r(0, 0), r(1, 0)) > 1e-12) {
    a = std::atan2(r(1, 0), r(0, 0));
    c = std::atan2(r(2, 1), r(2, 2));
  } else {  // gimbal lock: C = 0
    a = std::atan2(-r(0, 1), r(1, 1));
    c = 0.0;
  }
  return {a, b, c};
}

Eigen::Matrix3d rotationFromKukaAbc(const Eigen::Vector3d& abc) {
  return (Eigen::AngleAxisd(abc[0], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(abc[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(abc[2], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector4d abbQuaternion(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return {q.w(), q.x(), q.y(), q.z()};
}

Eigen::Matrix3d rotationFromAbbQuaternion(const Eigen::Vector4d& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

}  // namespace dynid
