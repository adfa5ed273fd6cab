#include "search/refinement/evaluation.hpp"

#include <algorithm>
#include <chrono>

#include <atomic>
#include <cstring>

#include <ceres/cost_function.h>

namespace dynid {

struct ParallelSegmentEvaluation::Entry {
  std::unique_ptr<ceres::CostFunction> cost;
  std::vector<const double*> parameters;  // the blocks given to add()
  std::vector<int> sizes;
  // The cache: the parameter values it was computed at, its residuals and (row-major, per block)
  // Jacobians, whether the evaluation succeeded and whether it holds Jacobians.
  std::vector<std::vector<double>> at;
  Eigen::VectorXd residuals;
  std::vector<std::vector<double>> jacobians;
  std::vector<double*> jacobian_pointers;  // into jacobians
  bool valid = false, ok = false, with_jacobians = false;
  mutable std::atomic<long> fallbacks{0};

  void evaluate(bool want_jacobians) {
    for (std::size_t b = 0; b < parameters.size(); ++b)
      std::memcpy(at[b].data(), parameters[b], sizeof(double) * at[b].size());
    try {  // the pool's tasks must not throw: a throwing evaluation is a failed one
      ok = cost->Evaluate(parameters.data(), residuals.data(),
                          want_jacobians ? jacobian_pointers.data() : nullptr);
    } catch (...) {
      ok = false;
    }
    with_jacobians = want_jacobians;
    valid = true;
  }

  bool holds(double const* const* point, bool want_jacobians) const {
    if (!valid || (want_jacobians && !with_jacobians)) return false;
    for (std::size_t b = 0; b < at.size(); ++b)
      if (std::memcmp(at[b].data(), point[b], sizeof(double) * at[b].size()) != 0) return false;
    return true;
  }
};

namespace {

/// Copies its entry's cache, or evaluates the cost function itself when the cache does not match.
class CachedCost : public ceres::CostFunction {
 public:
  explicit CachedCost(ParallelSegmentEvaluation::Entry& entry) : entry_(entry) {
    set_num_residuals(entry.cost->num_residuals());
    *mutable_parameter_block_sizes() = entry.cost->parameter_block_sizes();
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const ParallelSegmentEvaluation::Entry& e = entry_;
    if (!e.holds(parameters, jacobians != nullptr)) {
      ++e.fallbacks;
      return e.cost->Evaluate(parameters, residuals, jacobians);
    }
    if (!e.ok) return false;
    std::memcpy(residuals, e.residuals.data(), sizeof(double) * e.residuals.size());
    if (jacobians != nullptr)
      for (std::size_t b = 0; b < e.jacobians.size(); ++b)
        if (jacobians[b] != nullptr)
          std::memcpy(jacobians[b], e.jacobians[b].data(), sizeof(double) * e.jacobians[b].size());
    return true;
  }

 private:
  ParallelSegmentEvaluation::Entry& entry_;
};

}  // namespace

ParallelSegmentEvaluation::ParallelSegmentEvaluation(ThreadPool& pool) : pool_(pool) {}
ParallelSegmentEvaluation::~ParallelSegmentEvaluation() = default;

std::unique_ptr<ceres::CostFunction> ParallelSegmentEvaluation::add(
    std::unique_ptr<ceres::CostFunction> cost, std::vector<double*> blocks) {
  auto entry = std::make_unique<Entry>();
  entry->sizes = cost->parameter_block_sizes();
  const int residuals = cost->num_residuals();
  entry->residuals.resize(residuals);
  for (const int size : entry->sizes) {
    entry->at.emplace_back(static_cast<std::size_t>(size));
    entry->jacobians.emplace_back(static_cast<std::size_t>(size) * residuals);
  }
  entry->parameters.assign(blocks.begin(), blocks.end());
  for (std::vector<double>& jacobian : entry->jacobians)
    entry->jacobian_pointers.push_back(jacobian.data());
  entry->cost = std::move(cost);
  auto proxy = std::make_unique<CachedCost>(*entry);
  entries_.push_back(std::move(entry));
  return proxy;
}

void ParallelSegmentEvaluation::PrepareForEvaluation(bool evaluate_jacobians,
                                                     bool new_evaluation_point) {
  // The same point with Jacobians already cached: nothing to do.
  if (!new_evaluation_point &&
      (!evaluate_jacobians || entries_.empty() || entries_.front()->with_jacobians))
    return;
  ++batches_;
  const auto start = std::chrono::steady_clock::now();
  pool_.parallelFor(static_cast<int>(entries_.size()), [&](int i, int) {
    entries_[static_cast<std::size_t>(i)]->evaluate(evaluate_jacobians);
  });
  if (evaluate_jacobians)
    longest_jacobians_ =
        std::max(longest_jacobians_,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

long ParallelSegmentEvaluation::fallbacks() const {
  long total = 0;
  for (const auto& e : entries_) total += e->fallbacks;
  return total;
}

}  // namespace dynid
