// ceres::GradientChecker on parameters of any magnitude.
//
// GradientChecker differentiates numerically with Ridders' method, whose smallest step is an
// absolute 1e-2 (Ceres 2.1, internal/numeric_diff.h): meaningless for a 1e-4 kg m^2 inertia. The
// check therefore runs on y = x / s, with s_j = |x_j| (or 1 for a zero), so every entry of y is
// of order one, and the cost function's Jacobian is scaled by s to match. A wrong derivative of x
// is a wrong derivative of y: nothing is hidden.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/gradient_checker.h>
#include <Eigen/Core>

namespace dynid::test {

/// The Jacobian of `cost` at `blocks` agrees with Ridders' differences to `precision` (relative,
/// per entry); on failure `log` gets Ceres's table.
inline bool gradientsAgree(const ceres::CostFunction& cost,
                           const std::vector<Eigen::VectorXd>& blocks, double precision,
                           std::string* log) {
  class Scaled : public ceres::CostFunction {
   public:
    Scaled(const ceres::CostFunction& inner, const std::vector<Eigen::VectorXd>& scales)
        : inner_(inner), scales_(scales) {
      set_num_residuals(inner.num_residuals());
      *mutable_parameter_block_sizes() = inner.parameter_block_sizes();
    }
    bool Evaluate(double const* const* y, double* residuals, double** jacobians) const override {
      std::vector<Eigen::VectorXd> x(scales_.size());
      std::vector<const double*> pointers;
      for (std::size_t b = 0; b < scales_.size(); ++b) {
        x[b] = Eigen::Map<const Eigen::VectorXd>(y[b], scales_[b].size()).cwiseProduct(scales_[b]);
        pointers.push_back(x[b].data());
      }
      if (!inner_.Evaluate(pointers.data(), residuals, jacobians)) return false;
      // dr/dy = dr/dx diag(s); Jacobians are row-major.
      for (std::size_t b = 0; jacobians != nullptr && b < scales_.size(); ++b)
        if (jacobians[b] != nullptr)
          for (int r = 0; r < num_residuals(); ++r)
            for (int c = 0; c < scales_[b].size(); ++c)
              jacobians[b][r * scales_[b].size() + c] *= scales_[b][c];
      return true;
    }

   private:
    const ceres::CostFunction& inner_;
    std::vector<Eigen::VectorXd> scales_;
  };
  std::vector<Eigen::VectorXd> scales, y;
  std::vector<const double*> pointers;
  for (const Eigen::VectorXd& x : blocks) {
    Eigen::VectorXd s = x.cwiseAbs();
    for (double& e : s)
      if (e == 0.0) e = 1.0;
    scales.push_back(s);
    y.push_back(x.cwiseQuotient(s));
  }
  for (const Eigen::VectorXd& v : y) pointers.push_back(v.data());
  const Scaled scaled(cost, scales);
  ceres::NumericDiffOptions numeric;
  ceres::GradientChecker checker(
      &scaled, static_cast<const std::vector<const ceres::Manifold*>*>(nullptr), numeric);
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(pointers.data(), precision, &results);
  if (!results.return_value) {
    if (log != nullptr) *log = "the cost function failed to evaluate";
    return false;
  }
  // Mixed tolerance: relative to the entry, but never below precision * 1e-3 of the block's
  // largest entry, where Ridders' round-off (about 1e-13 absolute) exceeds a relative bound.
  bool ok = true;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const auto& exact = results.jacobians[b];
    const auto& numeric = results.numeric_jacobians[b];
    const double floor = 1e-3 * numeric.cwiseAbs().maxCoeff();
    for (int r = 0; r < exact.rows(); ++r)
      for (int c = 0; c < exact.cols(); ++c)
        if (std::abs(exact(r, c) - numeric(r, c)) >
            precision * std::max(std::abs(numeric(r, c)), floor))
          ok = false;
  }
  if (!ok && log != nullptr) *log = results.error_log;
  return ok;
}

}  // namespace dynid::test
