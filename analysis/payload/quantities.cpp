#include "analysis/payload/quantities.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "analysis/payload/body.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/parameters.hpp"

namespace dynid {

namespace {

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

}  // namespace

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

}  // namespace dynid
