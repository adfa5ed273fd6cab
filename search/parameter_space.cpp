#include "search/parameter_space.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/parameters.hpp"

namespace dynid {

const char* parameterFormName(ParameterForm form) {
  return form == ParameterForm::kPaper ? "paper" : "standard";
}

ParameterForm parseParameterForm(const std::string& name) {
  if (name == "paper") return ParameterForm::kPaper;
  if (name == "standard") return ParameterForm::kStandard;
  throw InputError("unknown parameter form '" + name + "' (expected paper or standard)");
}

namespace {
int perLink(ParameterForm form) { return form == ParameterForm::kPaper ? 7 : 10; }
/// Parameter kinds: 0 mass, 1 first moment or COM, 2 inertia.
int kindOf(int k) { return k == 0 ? 0 : (k <= 3 ? 1 : 2); }
/// Must stay >= 0: masses and, in the paper form, the principal inertias.
bool nonNegative(ParameterForm form, int k) {
  return k == 0 || (form == ParameterForm::kPaper && k >= 4);
}
}  // namespace

ParameterSpace::ParameterSpace(const Model& initial, const SpaceOptions& options)
    : initial_model_(initial), options_(options) {
  if (!(options.relative_range >= 0.0) || !(options.absolute_range >= 0.0))
    throw InputError("parameter ranges must be >= 0");
  full_initial_ = fullVector(initial);
  for (const RigidInertia<double>& inertia : initial.inertias()) {
    com_products_.push_back(inertiaAboutCom(inertia));
    com_products_.back().diagonal().setZero();
  }
  const int per = perLink(options.form);
  // The free-parameter mask: names in the form's naming.
  const std::vector<std::string> names =
      options.form == ParameterForm::kPaper
          ? paperParameterNames(initial.numJoints())
          : standardParameterNames({initial.numJoints(), DriveTerms::none()});
  std::vector<char> held(names.size(), 0);
  for (const std::string& name : options.fixed) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      throw InputError("cannot fix '" + name + "': no such parameter in the " +
                       parameterFormName(options.form) + " form (names like m2, " +
                       names[std::min<std::size_t>(8, names.size() - 1)] + ")");
    held[it - names.begin()] = 1;
  }
  std::vector<double> lower, upper, start;
  for (int index = 0; index < numFull(); ++index) {
    const int k = index % per;
    const double x0 = full_initial_[index];
    double lo, hi;
    if (held[index]) {
      if (k == 0) fixed_mass_ += x0;
      continue;
    }
    if (x0 != 0.0) {
      lo = x0 - options.relative_range * std::abs(x0);
      hi = x0 + options.relative_range * std::abs(x0);
    } else if (options.absolute_range > 0.0) {
      lo = -options.absolute_range;
      hi = options.absolute_range;
    } else {
      continue;  // fixed at 0
    }
    if (nonNegative(options.form, k)) lo = std::max(lo, 0.0);
    if (hi <= lo) {
      if (k == 0) fixed_mass_ += x0;
      continue;
    }
    if (k == 0) mass_positions_.push_back(static_cast<int>(free_.size()));
    free_.push_back(index);
    lower.push_back(lo);
    upper.push_back(hi);
    start.push_back(std::min(std::max(x0, lo), hi));
  }
  lower_ = Eigen::Map<Eigen::VectorXd>(lower.data(), lower.size());
  upper_ = Eigen::Map<Eigen::VectorXd>(upper.data(), upper.size());
  initial_ = Eigen::Map<Eigen::VectorXd>(start.data(), start.size());
  if (options.total_mass_constraint) {
    if (mass_positions_.empty()) throw InputError("the total-mass constraint needs a free mass");
    double lo = fixed_mass_, hi = fixed_mass_;
    for (int p : mass_positions_) lo += lower_[p], hi += upper_[p];
    if (options.total_mass < lo - 1e-12 || options.total_mass > hi + 1e-12)
      throw InputError("the total mass " + std::to_string(options.total_mass) +
                       " kg is outside what the mass bounds allow [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "] kg");
  }
}

std::vector<std::string> ParameterSpace::freeNames() const {
  const std::vector<std::string> all =
      options_.form == ParameterForm::kPaper
          ? paperParameterNames(initial_model_.numJoints())
          : standardParameterNames({initial_model_.numJoints(), DriveTerms::none()});
  std::vector<std::string> out;
  for (int index : free_) out.push_back(all[index]);
  return out;
}

Eigen::VectorXd ParameterSpace::fullVector(const Model& model) const {
  const int per = perLink(options_.form), n = model.numJoints();
  Eigen::VectorXd full(per * n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix<double, 10, 1> standard = toStandardVector(model.inertias()[i]);
    if (options_.form == ParameterForm::kPaper)
      full.segment<7>(7 * i) = standardToPaper(standard);
    else
      full.segment<10>(10 * i) = standard;
  }
  return full;
}

Eigen::VectorXd ParameterSpace::freeOf(const Eigen::VectorXd& full) const {
  Eigen::VectorXd x(numFree());
  for (int p = 0; p < numFree(); ++p) x[p] = full[free_[p]];
  return x;
}

double ParameterSpace::totalMass(const Eigen::VectorXd& x) const {
  double total = fixed_mass_;
  for (int p : mass_positions_) total += x[p];
  return total;
}

Eigen::VectorXd ParameterSpace::project(const Eigen::VectorXd& x) const {
  Eigen::VectorXd y = x.cwiseMax(lower_).cwiseMin(upper_);
  if (!options_.total_mass_constraint) return y;
  // Alternate: rescale the free masses not at a bound proportionally, then clamp.
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double deficit = options_.total_mass - totalMass(y);
    if (std::abs(deficit) <= 1e-12 * (1.0 + options_.total_mass)) break;
    double movable_mass = 0.0;
    std::vector<int> movable;
    for (int p : mass_positions_)
      if ((deficit > 0 && y[p] < upper_[p]) || (deficit < 0 && y[p] > lower_[p])) {
        movable.push_back(p);
        movable_mass += y[p];
      }
    if (movable.empty()) break;
    for (int p : movable) {
      // Proportional to the current mass; equal shares when the movable masses are all zero.
      const double share = movable_mass > 0.0 ? y[p] / movable_mass : 1.0 / movable.size();
      y[p] = std::min(std::max(y[p] + deficit * share, lower_[p]), upper_[p]);
    }
  }
  return y;
}

bool ParameterSpace::feasible(const Eigen::VectorXd& x, double tolerance) const {
  if (x.size() != numFree()) return false;
  for (int p = 0; p < numFree(); ++p)
    if (x[p] < lower_[p] - tolerance || x[p] > upper_[p] + tolerance) return false;
  return !options_.total_mass_constraint ||
         std::abs(totalMass(x) - options_.total_mass) <= tolerance * (1.0 + options_.total_mass);
}

void ParameterSpace::apply(const Eigen::VectorXd& x, Model& model) const {
  Eigen::VectorXd full = full_initial_;
  for (int p = 0; p < numFree(); ++p) full[free_[p]] = x[p];
  const int per = perLink(options_.form);
  for (int i = 0; i < model.numJoints(); ++i) {
    if (options_.form == ParameterForm::kPaper) {
      // Keep the initial model's products of inertia about the COM (zero for the PUMA).
      RigidInertia<double> inertia = fromStandardVector(paperToStandard(full.segment<7>(per * i)));
      inertia.inertia += com_products_[i];
      model.setLinkInertia(i, inertia);
    } else {
      model.setLinkInertia(i, fromStandardVector(full.segment<10>(per * i)));
    }
  }
}

Model ParameterSpace::modelAt(const Eigen::VectorXd& x) const {
  Model model = initial_model_;
  apply(x, model);
  return model;
}

Eigen::VectorXd ParameterSpace::standardAt(const Eigen::VectorXd& x) const {
  return modelAt(x).standardParameters();
}

double ParameterSpace::parameterError(const Eigen::VectorXd& x,
                                      const Eigen::VectorXd& truth_full) const {
  if (truth_full.size() != numFull())
    throw InputError("the truth has " + std::to_string(truth_full.size()) +
                     " parameters, expected " + std::to_string(numFull()));
  const int per = perLink(options_.form);
  // Scale of each kind: mean |non-zero true value|.
  double sum[3] = {0, 0, 0};
  int count[3] = {0, 0, 0};
  for (int index = 0; index < numFull(); ++index)
    if (truth_full[index] != 0.0) {
      sum[kindOf(index % per)] += std::abs(truth_full[index]);
      ++count[kindOf(index % per)];
    }
  double error = 0.0;
  for (int p = 0; p < numFree(); ++p) {
    const int index = free_[p];
    const int kind = kindOf(index % per);
    const double scale = truth_full[index] != 0.0
                             ? std::abs(truth_full[index])
                             : (count[kind] > 0 ? sum[kind] / count[kind] : 1.0);
    const double r = (truth_full[index] - x[p]) / scale;
    error += r * r;
  }
  return error;
}

}  // namespace dynid
