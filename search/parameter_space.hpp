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
  /// The links' inertias at x (numFree() entries) for any Scalar (e.g. ceres::Jet), exactly as
  /// apply() sets them; `out` gets one entry per link.
  template <typename T>
  void linkInertiasAt(const T* x, std::vector<RigidInertia<T>>& out) const;
  /// The free masses' positions in x and the sum of the fixed masses [kg]: the total mass is
  /// fixedMass() + the sum of x over massPositions().
  const std::vector<int>& massPositions() const { return mass_positions_; }
  double fixedMass() const { return fixed_mass_; }

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
  std::vector<Eigen::Matrix3d> com_products_;  // the initial products of inertia about each COM
};

template <typename T>
void ParameterSpace::linkInertiasAt(const T* x, std::vector<RigidInertia<T>>& out) const {
  const int n = initial_model_.numJoints();
  const int per = options_.form == ParameterForm::kPaper ? 7 : 10;
  // The full vector: free entries from x, the others at their initial value.
  VectorX<T> full = full_initial_.cast<T>();
  for (int p = 0; p < numFree(); ++p) full[free_[p]] = x[p];
  out.resize(n);
  for (int i = 0; i < n; ++i) {
    if (options_.form == ParameterForm::kPaper) {
      // Keep the initial model's products of inertia about the COM (zero for the PUMA).
      out[i] = fromStandardVector(paperToStandard(full.template segment<7>(per * i)));
      out[i].inertia += com_products_[i].cast<T>();
    } else {
      out[i] = fromStandardVector(full.template segment<10>(per * i));
    }
  }
}

}  // namespace dynid
