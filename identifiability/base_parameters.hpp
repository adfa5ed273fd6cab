// Base parameters: which combinations of the standard parameters the torques determine.
//
// Method (Gautier 1990, "Numerical calculation of the base inertial parameters of robots"): scale
// each column of an observation matrix W to unit norm, take its Householder QR without pivoting,
// and call column j dependent when |R_jj| <= tolerance: it is then a linear combination of the
// columns before it. Round-off cannot pass for a parameter: a column at most 1e-10 of the largest
// column's norm never acts, and a column is independent only if its component orthogonal to the
// columns before it, |R_jj| times its norm, also exceeds 1e-10 of the largest column norm
// (docs/IDENTIFIABILITY.md, "The rank rule").
// Columns are tried in a preference order; computeBaseParameters' default takes link 1 first and,
// within each link, the inertias before the first moments, the mass and the drive parameters, so
// that masses and rotor inertias regroup into inertias and first moments as in Khalil's rules
// (Izz1 + Ia1 + Iyy2 + 0.1865*m3) rather than the other way round. Any choice gives the same span.
// With theta1 the independent parameters and theta2 the dependent ones, W2 = W1 K and
//     W theta = W1 beta,   beta = theta1 + K theta2,
// K = W1^+ W2 by least squares. The null space of W in standard coordinates is P [-K; I].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/parameters.hpp"

namespace dynid {

struct BaseParameters {
  std::vector<std::string> standard_names;  // names of theta (core/parameters.hpp)
  std::vector<int> independent;             // indices into theta of theta1, in base-parameter order
  std::vector<int> dependent;     // indices into theta of theta2 (includes the zero columns)
  std::vector<int> zero_columns;  // parameters that never affect the torques
  Eigen::MatrixXd K;              // num_base x dependent.size(), physical units
  Eigen::VectorXd r_diagonal;     // |R_jj| of the scaled W, in standard order (0 for zero columns)
  double tolerance = 0.0;         // the relative rank threshold used on |R_jj|
  /// Per column (standard order): min(|R_jj| / tolerance, |R_jj| norm_j / (1e-10 max norm)), the
  /// margin of the tighter test; independent when > 1, 0 for a column that never acts.
  Eigen::VectorXd significance;
  double smallest_kept = 0.0;    // min significance over independent columns
  double largest_dropped = 0.0;  // max significance over dependent acting columns (0 if none)

  int numStandard() const { return static_cast<int>(standard_names.size()); }
  int numBase() const { return static_cast<int>(independent.size()); }
  /// smallest_kept / largest_dropped: how clearly the rank is determined (infinity when nothing
  /// was dropped; below 1e4 the decision is close and `dynid identifiability` warns).
  double rankGap() const;

  /// beta = theta1 + K theta2 for a standard vector (p entries). Throws InputError on a size
  /// mismatch.
  Eigen::VectorXd project(const Eigen::VectorXd& theta) const;
  /// A standard vector with the given base values: theta2 from the prior, theta1 = beta - K theta2.
  /// Throws InputError on size mismatches.
  Eigen::VectorXd standardFromBase(const Eigen::VectorXd& beta, const Eigen::VectorXd& prior) const;
  /// The base regressor W1 = W(:, independent): W theta = W1 beta.
  Eigen::MatrixXd baseRegressor(const Eigen::MatrixXd& W) const;
  /// The projection as a matrix P (num_base x p): beta = P theta.
  Eigen::MatrixXd projectionMatrix() const;
  /// P with the base names (baseName), for the search and refinement modules.
  BaseCoordinates coordinates() const;
  /// Null-space basis in standard coordinates (p x (p - num_base)): W N = 0.
  Eigen::MatrixXd nullSpace() const;
  /// Name of base parameter j: its leading standard parameter, with "R" appended when others
  /// are regrouped into it (Khalil's notation), e.g. "Izz1R".
  std::string baseName(int j) const;
  /// The standard parameters in base parameter j with their coefficients (leading one first,
  /// coefficient 1), dropping coefficients whose effect is below `relative` of the leading
  /// parameter's on the scaled W (round-off, not structure).
  std::vector<std::pair<std::string, double>> combination(int j, double relative = 1e-9) const;
  /// Readable form, e.g. "Izz1 + Iyy2 + 0.1865*m3", coefficients to `digits` significant digits.
  std::string expression(int j, int digits = 4) const;

  // Internal: unit-norm column scale of W (1 for zero columns), used by combination().
  Eigen::VectorXd column_norms;
};

/// Base parameters from an observation matrix W (rows >= columns advisable). `names` has one entry
/// per column. tolerance <= 0 selects the default 1e-8 max |R_jj| on the unit-norm columns (about
/// sqrt(machine epsilon); base_parameters.cpp says why), reported with the rank gap. Throws
/// InputError when names and W disagree or W has a non-finite entry. `preference` lists every
/// column once, in the order they are tried (empty: the standard order). Base parameters are
/// reported in the standard order of their leading parameter.
BaseParameters computeBaseParameters(const Eigen::MatrixXd& W,
                                     const std::vector<std::string>& names, double tolerance = 0.0,
                                     const std::vector<int>& preference = {});

/// The structural analysis: how many seeded random states, their seed and the rank tolerance.
struct StructuralOptions {
  int samples = 0;  // random states; 0: max(100, 5 p / n)
  std::uint64_t seed = 1;
  double tolerance = 0.0;  // on |R_jj| of the unit-column W; 0: the default (computeBaseParameters)

  /// Throws InputError naming the first field out of its range (core/option_ranges.hpp:
  /// --samples, --tolerance).
  void check() const;
};

/// The model's base parameters from `options.samples` seeded random states (the structural rank,
/// independent of any dataset), with the default preference. Throws InputError when samples < 0
/// or the model has no joints.
BaseParameters structuralBaseParameters(const Model& model, const StructuralOptions& options = {});

/// The base parameters of a block of standard parameters (indices into theta) when every other
/// parameter is known (a payload: one link's 10 when the arm is identified): the structural
/// analysis of `options` on the block's columns alone, with indices, names and the projection in
/// the model's full standard order (parameters outside the block are neither independent nor
/// dependent: nullSpace() and standardFromBase() do not apply). Throws InputError for an empty
/// block or an index out of range.
BaseParameters blockBaseParameters(const Model& model, const std::vector<int>& block,
                                   const StructuralOptions& options = {});

/// The scale s_j of each base parameter's relative error: |truth_j|, or, for a true value of 0
/// (below 1e-9 of the mean magnitude: round-off), the mean magnitude of the non-zero true values
/// (as the paper's parameter error, eq. 1); all 1 when every true value is 0.
Eigen::VectorXd baseParameterScale(const Eigen::VectorXd& truth);

/// Relative error of a base estimate against the true base parameters: e_j = |beta_j - truth_j| /
/// s_j with s_j = baseParameterScale(truth)_j. Returns the RMS of e over j (`max`, when given,
/// receives the largest e_j). Throws InputError on a size mismatch.
double baseParameterError(const Eigen::VectorXd& beta, const Eigen::VectorXd& truth,
                          double* max = nullptr);

/// The default preference for a parameter layout (core/parameters.hpp): links in order; within a
/// link Ixx, Ixy, Ixz, Iyy, Iyz, Izz, mx, my, mz, m, then its drive terms in table order.
std::vector<int> defaultPreference(int num_links, int per_link);

/// How well a dataset excites each base parameter: the |R_jj| of the column-scaled base regressor's
/// QR (base order), and the numerical rank with the same default tolerance.
struct Excitation {
  Eigen::VectorXd r_diagonal;
  double tolerance = 0.0;
  int rank = 0;
  std::vector<int> unexcited;  // base parameters (indices) with |R_jj| <= tolerance
};
Excitation measureExcitation(const Eigen::MatrixXd& base_regressor);
/// The same from |R_jj| already computed (e.g. by a least-squares solve of the same scaled
/// columns).
Excitation excitationFromRDiagonal(const Eigen::VectorXd& r_diagonal);

}  // namespace dynid

namespace dynid {
/// Condition number (largest over smallest singular value) of A with unit-norm columns; infinity
/// when A is rank deficient.
double scaledConditionNumber(const Eigen::MatrixXd& A);
/// The 2-norm condition number of r, its largest singular value over its smallest (a triangular
/// factor R of A has A's): infinity when r is empty, has an entry that is not finite, or its
/// smallest singular value is zero.
double conditionNumber(const Eigen::Ref<const Eigen::MatrixXd>& r);
}  // namespace dynid
