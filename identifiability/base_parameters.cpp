#include "identifiability/base_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "identifiability/observation.hpp"
#include "identifiability/tall_qr.hpp"

namespace dynid {

namespace {
/// R of A D^-1 (D = diag(norms), a zero norm taken as 1), streamed through TallQr in row blocks.
Eigen::MatrixXd scaledTriangularFactor(const Eigen::MatrixXd& A, const Eigen::VectorXd& norms) {
  Eigen::VectorXd inverse(norms.size());
  for (Eigen::Index j = 0; j < norms.size(); ++j)
    inverse[j] = norms[j] > 0.0 ? 1.0 / norms[j] : 1.0;
  constexpr Eigen::Index kBlock = 1024;
  TallQr factor(A.cols(), kBlock);
  for (Eigen::Index start = 0; start < A.rows(); start += kBlock) {
    const Eigen::Index k = std::min(kBlock, A.rows() - start);
    factor.add(A.middleRows(start, k) * inverse.asDiagonal());
  }
  return factor.r();
}

/// |R_jj| of the Householder QR (no pivoting) of W with unit-norm columns; norms returned too.
Eigen::VectorXd scaledRDiagonal(const Eigen::MatrixXd& W, Eigen::VectorXd* norms) {
  *norms = W.colwise().norm().transpose();
  const Eigen::VectorXd diagonal = scaledTriangularFactor(W, *norms).diagonal().cwiseAbs();
  Eigen::VectorXd out = diagonal;
  for (Eigen::Index j = 0; j < W.cols(); ++j)
    if ((*norms)[j] == 0.0) out[j] = 0.0;
  return out;
}

/// A column whose norm is at most this fraction of the largest column's is round-off, not a
/// parameter that acts: trigonometric round-off (cos(pi/2) = 6e-17) leaves columns of 1e-17 to
/// 1e-14 of the largest, while the smallest real ones (a light wrist's inertias) stay above 1e-6.
constexpr double kNegligibleColumn = 1e-10;

/// 1e-8 (about sqrt(machine epsilon)) of the largest |R_jj|. Dependent columns of an unpivoted QR
/// keep round-off that grows with the conditioning of W (seen up to 3e-13 on the PUMA's random
/// states), while genuinely independent unit columns of a structural W keep |R_jj| >= 1e-4; an
/// eps-based tolerance (MATLAB's max(m, p) eps max|R_jj|) lands inside that round-off.
double defaultTolerance(const Eigen::VectorXd& diagonal) {
  return 1e-8 * (diagonal.size() > 0 ? diagonal.maxCoeff() : 0.0);
}

}  // namespace

double BaseParameters::rankGap() const {
  return largest_dropped > 0.0 ? smallest_kept / largest_dropped
                               : std::numeric_limits<double>::infinity();
}

Eigen::VectorXd BaseParameters::project(const Eigen::VectorXd& theta) const {
  if (theta.size() != numStandard())
    throw InputError("parameter vector has " + std::to_string(theta.size()) +
                     " entries, expected " + std::to_string(numStandard()));
  Eigen::VectorXd theta2(dependent.size());
  for (std::size_t k = 0; k < dependent.size(); ++k) theta2[k] = theta[dependent[k]];
  Eigen::VectorXd beta = K * theta2;
  for (int j = 0; j < numBase(); ++j) beta[j] += theta[independent[j]];
  return beta;
}

Eigen::VectorXd BaseParameters::standardFromBase(const Eigen::VectorXd& beta,
                                                 const Eigen::VectorXd& prior) const {
  if (beta.size() != numBase())
    throw InputError("base vector has " + std::to_string(beta.size()) + " entries, expected " +
                     std::to_string(numBase()));
  if (prior.size() != numStandard())
    throw InputError("prior has " + std::to_string(prior.size()) + " entries, expected " +
                     std::to_string(numStandard()));
  Eigen::VectorXd theta = prior;
  Eigen::VectorXd theta2(dependent.size());
  for (std::size_t k = 0; k < dependent.size(); ++k) theta2[k] = prior[dependent[k]];
  const Eigen::VectorXd theta1 = beta - K * theta2;
  for (int j = 0; j < numBase(); ++j) theta[independent[j]] = theta1[j];
  return theta;
}

Eigen::MatrixXd BaseParameters::baseRegressor(const Eigen::MatrixXd& W) const {
  if (W.cols() != numStandard())
    throw InputError("observation matrix has " + std::to_string(W.cols()) + " columns, expected " +
                     std::to_string(numStandard()));
  Eigen::MatrixXd out(W.rows(), numBase());
  for (int j = 0; j < numBase(); ++j) out.col(j) = W.col(independent[j]);
  return out;
}

Eigen::MatrixXd BaseParameters::projectionMatrix() const {
  // beta_j = theta_independent(j) + sum_k K_jk theta_dependent(k).
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(numBase(), numStandard());
  for (int j = 0; j < numBase(); ++j) {
    P(j, independent[j]) = 1.0;
    for (std::size_t k = 0; k < dependent.size(); ++k) P(j, dependent[k]) += K(j, k);
  }
  return P;
}

BaseCoordinates BaseParameters::coordinates() const {
  BaseCoordinates out{projectionMatrix(), {}};
  for (int j = 0; j < numBase(); ++j) out.names.push_back(baseName(j));
  return out;
}

void StructuralOptions::check() const {
  checkOption("", "samples", samples, "`samples`");
  checkOption("", "tolerance", tolerance, "`tolerance`");
}

BaseParameters structuralBaseParameters(const Model& model, const StructuralOptions& options) {
  options.check();
  if (model.numJoints() == 0) throw InputError("model '" + model.name + "' has no joints");
  const ParameterLayout layout = model.parameterLayout();
  const int samples =
      options.samples > 0 ? options.samples : std::max(100, 5 * layout.size() / model.numJoints());
  return computeBaseParameters(observationFromRandomStates(model, samples, options.seed).W,
                               standardParameterNames(layout), options.tolerance,
                               defaultPreference(layout.num_links, layout.perLink()));
}

BaseParameters blockBaseParameters(const Model& model, const std::vector<int>& block,
                                   const StructuralOptions& options) {
  options.check();
  if (model.numJoints() == 0) throw InputError("model '" + model.name + "' has no joints");
  const ParameterLayout layout = model.parameterLayout();
  const std::vector<std::string> names = standardParameterNames(layout);
  if (block.empty()) throw InputError("the block of parameters is empty");
  for (int c : block)
    if (c < 0 || c >= layout.size())
      throw InputError("parameter index " + std::to_string(c) + " is out of range");
  const int samples =
      options.samples > 0 ? options.samples : std::max(100, 5 * layout.size() / model.numJoints());
  const Eigen::MatrixXd W = observationFromRandomStates(model, samples, options.seed).W;
  Eigen::MatrixXd w(W.rows(), static_cast<Eigen::Index>(block.size()));
  std::vector<std::string> block_names;
  for (std::size_t k = 0; k < block.size(); ++k) {
    w.col(static_cast<Eigen::Index>(k)) = W.col(block[k]);
    block_names.push_back(names[block[k]]);
  }
  const BaseParameters inner = computeBaseParameters(w, block_names, options.tolerance);
  BaseParameters out = inner;
  out.standard_names = names;
  const auto remap = [&](std::vector<int>& v) {
    for (int& i : v) i = block[static_cast<std::size_t>(i)];
  };
  remap(out.independent);
  remap(out.dependent);
  remap(out.zero_columns);
  const auto spread = [&](const Eigen::VectorXd& v, double rest) {
    Eigen::VectorXd full = Eigen::VectorXd::Constant(layout.size(), rest);
    for (std::size_t k = 0; k < block.size(); ++k) full[block[k]] = v[static_cast<Eigen::Index>(k)];
    return full;
  };
  out.r_diagonal = spread(inner.r_diagonal, 0.0);
  out.significance = spread(inner.significance, 0.0);
  out.column_norms = spread(inner.column_norms, 1.0);
  return out;
}

Eigen::VectorXd baseParameterScale(const Eigen::VectorXd& truth) {
  if (truth.size() == 0) return truth;
  // A true value below 1e-9 of the mean magnitude is a round-off zero (a regrouping such as
  // Iyy - Ixx of a symmetric link), normalised like an exact 0.
  const double mean = truth.cwiseAbs().mean();
  const auto zero = [&](double v) { return std::abs(v) <= 1e-9 * mean; };
  double fallback = 0.0;
  int nonzero = 0;
  for (int j = 0; j < truth.size(); ++j)
    if (!zero(truth[j])) fallback += std::abs(truth[j]), ++nonzero;
  fallback = nonzero > 0 ? fallback / nonzero : 1.0;
  Eigen::VectorXd scale(truth.size());
  for (int j = 0; j < truth.size(); ++j) scale[j] = zero(truth[j]) ? fallback : std::abs(truth[j]);
  return scale;
}

double baseParameterError(const Eigen::VectorXd& beta, const Eigen::VectorXd& truth, double* max) {
  if (beta.size() != truth.size())
    throw InputError("base estimate has " + std::to_string(beta.size()) + " entries, truth " +
                     std::to_string(truth.size()));
  if (truth.size() == 0) return 0.0;
  const Eigen::VectorXd scale = baseParameterScale(truth);
  double sum = 0.0, largest = 0.0;
  for (int j = 0; j < truth.size(); ++j) {
    const double e = std::abs(beta[j] - truth[j]) / scale[j];
    sum += e * e;
    largest = std::max(largest, e);
  }
  if (max != nullptr) *max = largest;
  return std::sqrt(sum / static_cast<double>(truth.size()));
}

Eigen::MatrixXd BaseParameters::nullSpace() const {
  const int d = static_cast<int>(dependent.size());
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(numStandard(), d);
  for (int k = 0; k < d; ++k) {
    N(dependent[k], k) = 1.0;
    for (int j = 0; j < numBase(); ++j) N(independent[j], k) = -K(j, k);
  }
  return N;
}

std::vector<std::pair<std::string, double>> BaseParameters::combination(int j,
                                                                        double relative) const {
  std::vector<std::pair<std::string, double>> out{{standard_names[independent[j]], 1.0}};
  const double lead = column_norms[independent[j]];
  for (std::size_t k = 0; k < dependent.size(); ++k) {
    // Effect on the scaled W: K_jk |w_k| relative to |w_j|.
    if (std::abs(K(j, k)) * column_norms[dependent[k]] <= relative * lead) continue;
    out.emplace_back(standard_names[dependent[k]], K(j, k));
  }
  return out;
}

std::string BaseParameters::baseName(int j) const {
  return standard_names[independent[j]] + (combination(j).size() > 1 ? "R" : "");
}

std::string BaseParameters::expression(int j, int digits) const {
  std::string out;
  for (const auto& [name, coefficient] : combination(j)) {
    if (out.empty()) {
      out = name;
      continue;
    }
    const double magnitude = std::abs(coefficient);
    out += coefficient < 0 ? " - " : " + ";
    if (std::abs(magnitude - 1.0) > 1e-12) out += formatNumber(magnitude, digits) + "*";
    out += name;
  }
  return out;
}

std::vector<int> defaultPreference(int num_links, int per_link) {
  // Offsets within a link block: inertias (4..9), first moments (1..3), mass (0), drives (10..).
  std::vector<int> within = {4, 5, 6, 7, 8, 9, 1, 2, 3, 0};
  for (int k = 10; k < per_link; ++k) within.push_back(k);
  std::vector<int> order;
  for (int i = 0; i < num_links; ++i)
    for (int k : within) order.push_back(i * per_link + k);
  return order;
}

BaseParameters computeBaseParameters(const Eigen::MatrixXd& W,
                                     const std::vector<std::string>& names, double tolerance,
                                     const std::vector<int>& preference) {
  const Eigen::Index p = W.cols();
  if (static_cast<Eigen::Index>(names.size()) != p)
    throw InputError("observation matrix has " + std::to_string(p) + " columns but " +
                     std::to_string(names.size()) + " parameter names");
  if (!W.allFinite()) throw InputError("observation matrix has a non-finite entry");
  std::vector<int> order = preference;
  if (order.empty())
    for (int j = 0; j < p; ++j) order.push_back(j);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int j = 0; j < p; ++j)
    if (static_cast<Eigen::Index>(sorted.size()) != p || sorted[j] != j)
      throw InputError("the preference order must list every column exactly once");

  BaseParameters out;
  out.standard_names = names;
  // Unpivoted QR of the columns in preference order; results mapped back to standard order.
  Eigen::MatrixXd ordered(W.rows(), p);
  for (int j = 0; j < p; ++j) ordered.col(j) = W.col(order[j]);
  Eigen::VectorXd ordered_norms;
  const Eigen::VectorXd ordered_diagonal = scaledRDiagonal(ordered, &ordered_norms);
  out.r_diagonal.resize(p);
  out.column_norms.resize(p);
  for (int j = 0; j < p; ++j) {
    out.r_diagonal[order[j]] = ordered_diagonal[j];
    out.column_norms[order[j]] = ordered_norms[j];
  }
  out.tolerance = tolerance > 0.0 ? tolerance : defaultTolerance(out.r_diagonal);
  // Two tests, both must pass for a column to be independent: its unit-column |R_jj| above the
  // tolerance (relative: not a combination of the columns before it), and its component
  // orthogonal to them, |R_jj| times its norm, above kNegligibleColumn of the largest column norm
  // (absolute: not round-off blown up by the unit scaling). The significance s_j is the smaller of
  // the two ratios to their thresholds; the rank gap compares the kept and dropped s_j.
  const double largest_norm = out.column_norms.size() > 0 ? out.column_norms.maxCoeff() : 0.0;
  const double absolute = kNegligibleColumn * largest_norm;
  out.significance.resize(p);
  out.smallest_kept = std::numeric_limits<double>::infinity();
  for (int j = 0; j < p; ++j) {
    const double norm = out.column_norms[j];
    out.significance[j] = norm <= absolute ? 0.0
                                           : std::min(out.r_diagonal[j] / out.tolerance,
                                                      out.r_diagonal[j] * norm / absolute);
    if (norm <= absolute) {
      // Exactly zero, or round-off: the parameter never affects the torques.
      out.zero_columns.push_back(j);
      out.dependent.push_back(j);
      out.column_norms[j] = 0.0;
    } else if (out.significance[j] > 1.0) {
      out.independent.push_back(j);
      out.smallest_kept = std::min(out.smallest_kept, out.significance[j]);
    } else {
      out.dependent.push_back(j);
      out.largest_dropped = std::max(out.largest_dropped, out.significance[j]);
    }
  }
  // A zero column's K entries are 0: scale 1 keeps the solve well defined.
  for (int j : out.zero_columns) out.column_norms[j] = 1.0;
  // K = W1^+ W2: the dependent columns expressed in the independent ones (scaled for accuracy).
  Eigen::MatrixXd W1(W.rows(), out.numBase()), W2(W.rows(), out.dependent.size());
  for (int j = 0; j < out.numBase(); ++j)
    W1.col(j) = W.col(out.independent[j]) / out.column_norms[out.independent[j]];
  for (std::size_t k = 0; k < out.dependent.size(); ++k) {
    const int j = out.dependent[k];
    const bool zero =
        std::find(out.zero_columns.begin(), out.zero_columns.end(), j) != out.zero_columns.end();
    W2.col(k) =
        zero ? Eigen::VectorXd::Zero(W.rows()).eval() : (W.col(j) / out.column_norms[j]).eval();
  }
  out.K.resize(out.numBase(), out.dependent.size());
  // Nothing to express (every column independent, as a payload's block): no solve (Eigen's
  // Householder update of a matrix without columns offsets a null pointer).
  if (out.dependent.empty() || out.numBase() == 0) return out;
  const Eigen::MatrixXd K_scaled = Eigen::HouseholderQR<Eigen::MatrixXd>(W1).solve(W2);
  for (int j = 0; j < out.numBase(); ++j)
    for (std::size_t k = 0; k < out.dependent.size(); ++k)
      out.K(j, k) = K_scaled(j, k) * out.column_norms[out.dependent[k]] /
                    out.column_norms[out.independent[j]];
  return out;
}

Excitation measureExcitation(const Eigen::MatrixXd& base_regressor) {
  Eigen::VectorXd norms;
  return excitationFromRDiagonal(scaledRDiagonal(base_regressor, &norms));
}

Excitation excitationFromRDiagonal(const Eigen::VectorXd& r_diagonal) {
  Excitation out;
  out.r_diagonal = r_diagonal;
  out.tolerance = defaultTolerance(out.r_diagonal);
  for (Eigen::Index j = 0; j < out.r_diagonal.size(); ++j) {
    if (out.r_diagonal[j] > out.tolerance)
      ++out.rank;
    else
      out.unexcited.push_back(static_cast<int>(j));
  }
  return out;
}

}  // namespace dynid

namespace dynid {
double scaledConditionNumber(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd norms = A.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < norms.size(); ++j)
    if (norms[j] == 0.0) return std::numeric_limits<double>::infinity();
  if (A.rows() < A.cols()) return std::numeric_limits<double>::infinity();
  // Singular values of the small R factor equal those of A.
  return conditionNumber(scaledTriangularFactor(A, norms));
}

double conditionNumber(const Eigen::Ref<const Eigen::MatrixXd>& r) {
  // Eigen's Jacobi SVD does not end on a NaN entry, and fails on an empty matrix: never handed one.
  if (r.size() == 0 || !r.allFinite()) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(r).singularValues();
  if (s.size() == 0 || !(s[s.size() - 1] > 0.0)) return std::numeric_limits<double>::infinity();
  return s[0] / s[s.size() - 1];
}
}  // namespace dynid
