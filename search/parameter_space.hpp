// The space the GC-error searches move in: a parameter form, which parameters are free, their
// bounds and the total-mass constraint (the paper's section III-C).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"

namespace dynid {

enum class ParameterForm {
  kPaper,     // m, cx, cy, cz, Ixx, Iyy, Izz (principal, about the COM) per link: the paper's 7
  kStandard,  // m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz per link
};
const char* parameterFormName(ParameterForm form);
ParameterForm parseParameterForm(const std::string& name);  // "paper" or "standard"

struct SpaceOptions {
  ParameterForm form = ParameterForm::kPaper;
  double relative_range = 0.5;  // bounds: initial estimate +- this fraction of its magnitude
  /// A parameter whose initial estimate is 0 stays fixed at 0 unless this is > 0; it then ranges
  /// over [-absolute_range, absolute_range] (masses and principal inertias over [0, range]).
  double absolute_range = 0.0;
  /// Parameters held at their initial estimate, by name in the form ("m2", "cx3", "Ixy4").
  std::vector<std::string> fixed = {};
  bool total_mass_constraint = false;  // sum of masses fixed to total_mass (the paper's NLO)
  double total_mass = 0.0;             // [kg]; used when the constraint is on
};

/// Free parameters x (a subset of the form's full vector) and how they map to a Model.
class ParameterSpace {
 public:
  /// `initial` supplies the structure and every parameter's initial estimate. Throws InputError
  /// for a negative range, an unknown name in `fixed`, a total mass the bounds cannot reach, or
  /// the constraint without a free mass.
  ParameterSpace(const Model& initial, const SpaceOptions& options);

  int numFree() const { return static_cast<int>(free_.size()); }
  int numFull() const { return static_cast<int>(full_initial_.size()); }
  const std::vector<int>& freeIndices() const { return free_; }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  const Eigen::VectorXd& initial() const { return initial_; }
  ParameterForm form() const { return options_.form; }
  const SpaceOptions& options() const { return options_; }
  std::vector<std::string> freeNames() const;

  /// The form's full vector of a model (7 or 10 per link).
  Eigen::VectorXd fullVector(const Model& model) const;
  /// Free entries of a full vector.
  Eigen::VectorXd freeOf(const Eigen::VectorXd& full) const;
  /// A feasible point near x: clamped to the bounds and, with the constraint, on the total-mass
  /// plane, the free masses rescaled proportionally (alternating with the clamp; exact to 1e-12
  /// relative).
  Eigen::VectorXd project(const Eigen::VectorXd& x) const;
  /// Whether x is within the bounds (and on the mass plane) to `tolerance`.
  bool feasible(const Eigen::VectorXd& x, double tolerance = 1e-9) const;
  /// Total mass of the free and fixed masses at x [kg].
  double totalMass(const Eigen::VectorXd& x) const;
  /// Writes the parameters of x into `model` (a copy of the initial model); inertias and the
  /// derived fields are updated.
  void apply(const Eigen::VectorXd& x, Model& model) const;
  Model modelAt(const Eigen::VectorXd& x) const;
  /// The standard 10-per-link (plus drives) vector at x.
  Eigen::VectorXd standardAt(const Eigen::VectorXd& x) const;

  /// The paper's parameter error, eq. (1): sum over free parameters of ((p - p') / p)^2, with p
  /// the true value. A true value of 0 is normalised by the mean magnitude of the non-zero true
  /// values of the same kind (masses, first moments or COM components, inertias), over all links.
  double parameterError(const Eigen::VectorXd& x, const Eigen::VectorXd& truth_full) const;

 private:
  Model initial_model_;
  SpaceOptions options_;
  Eigen::VectorXd full_initial_;
  std::vector<int> free_;
  std::vector<int> mass_positions_;  // positions in x of free masses
  double fixed_mass_ = 0.0;
  Eigen::VectorXd initial_, lower_, upper_;
};

}  // namespace dynid
