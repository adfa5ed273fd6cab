// One study setting of the paper's experiment, shared by `dynid demo` and each `dynid batch` run:
// a robot, simulated training and held-out data (with optional noise), a perturbed initial guess,
// the base parameters, and every estimation method measured in the same coordinates.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "analysis/estimation/methods.hpp"
#include "analysis/estimation/pipeline.hpp"
#include "analysis/studies/comparison.hpp"
#include "identifiability/observation.hpp"
#include "search/optimizers.hpp"

namespace dynid {

struct StudySettings {
  std::string robot = "puma560";  // a robot spec (data/robots.hpp)
  double train_seconds = 10.0;    // the default sinusoidal tracking run of `dynid simulate`
  double test_seconds = 10.0;     // docs/SEARCH.md's held-out control path
  double noise_q = 0.0, noise_dq = 0.0, noise_tau = 0.0;  // on the recorded data, both sets
  int segments = 100;
  double horizon = 0.05;   // [s]
  double perturb = 0.3;    // the initial guess: every parameter times (1 + U(-perturb, perturb))
  std::uint64_t seed = 1;  // the initial guess, the noise (held-out: seed + 1000) and the searches
  double search_seconds = 30.0;     // per search (0: no time limit)
  long search_evaluations = 0;      // per search (0: no limit); one of the two must be set
  int refine_iterations = 200;      // per refinement stage
  double refine_seconds = 60.0;     // per refinement (0: no limit); as `dynid study`'s default
  double refine_tolerance = 1e-16;  // Ceres's relative cost change
  bool keep_if_better = true;       // keep a search's result that its refinement did not improve
  double prior_weight = kDefaultPriorWeight;  // pc: PhysicalOptions::prior_weight
  int threads = 1;
  /// The training motion: an excitation.json of `dynid excite` (empty: the default sinusoid).
  std::string trajectory;

  /// Throws InputError naming the first invalid field (by its StudySettings and manifest name)
  /// and its range from the one option table (core/option_ranges.hpp: durations as --duration,
  /// the rest as the study's options), and when neither search budget is set or threads < 1. The
  /// robot is checked when loaded.
  void check() const;
};

/// The paper's Fig. 4: held-out GC errors of random configurations near the truth (every paper
/// parameter within +-range of its true value), and where an estimate's falls among them.
struct NearTruth {
  double range = 0.02;
  std::vector<double> gc_errors;  // one per configuration, held-out data
  std::string estimate;           // the method compared
  double estimate_gc = 0.0;       // its held-out GC error
  double percentile = 0.0;        // % of the configurations with a GC error <= the estimate's
};

/// What explains the searches: the GC error's blind directions against the regressor's. The GC
/// residuals' Jacobian with respect to the standard parameters at the truth, columns scaled to unit
/// norm, has singular values; those at or below `tolerance` times the largest span its near-null
/// space. The principal angles between that space and the regressor's null space (base parameters)
/// show whether the GC error is blind to the same parameter combinations as the torques.
struct NullSpaces {
  int standard = 0;        // p
  int regressor_null = 0;  // p - num_base
  int gc_near_null = 0;    // singular values <= tolerance * largest
  double tolerance = 1e-7;
  std::vector<double> gc_singular_values;    // descending, of the column-scaled Jacobian
  std::vector<double> principal_angles_deg;  // ascending, min(dimensions) of them
};

class Study {
 public:
  /// Simulates the data and finds the base parameters. Throws InputError for a bad setting (an
  /// unknown robot, a non-positive duration, neither search budget set).
  explicit Study(const StudySettings& settings, RunControl control = {});
  Study(const Study&) = delete;
  Study& operator=(const Study&) = delete;

  /// Runs one method and measures its estimate. The refined methods refine the search's result,
  /// searching first when that search has not run.
  MethodMetrics run(Method method);

  /// The search `method` (nlo, ga, hybrid) when it has run, else null. Its `evaluated` holds
  /// (GC error, parameter error) of every candidate.
  const SearchResult* searchResult(Method method) const { return runner_->searchResult(method); }
  /// The base-parameter error of the search's best candidate after each of its history entries.
  const std::vector<double>* searchBaseErrors(Method method) const {
    const auto it = search_base_errors_.find(method);
    return it == search_base_errors_.end() ? nullptr : &it->second;
  }
  /// The null spaces of the GC residuals and of the regressor, compared at the truth.
  NullSpaces nullSpaces();
  /// The OLS estimate's relative standard deviations [%], per base parameter, once OLS has run.
  const Eigen::VectorXd& olsRelativeStdDev() const { return ols_relative_std_dev_; }
  /// The initial guess's GC error on the held-out data.
  double initialTestGc() const { return initial_test_gc_; }
  /// `samples` configurations near the truth (seeded by the setting's seed), compared with the
  /// held-out GC error `estimate_gc` of `estimate`.
  NearTruth nearTruth(int samples, double range, const std::string& estimate, double estimate_gc);
  const StudySettings& settings() const { return settings_; }
  const Model& truth() const { return truth_; }
  const BaseParameters& base() const { return base_; }
  const Observation& observation() const { return observation_; }

 private:
  StudySettings settings_;
  RunControl control_;
  Model truth_, initial_;
  Trajectory train_data_, test_data_;
  GcProblem train_, test_;
  BaseParameters base_;
  Observation observation_;
  std::unique_ptr<MethodRunner> runner_;  // every estimate
  std::unique_ptr<Comparison> comparison_;
  double initial_gc_ = 0.0;
  Eigen::VectorXd truth_full_;
  std::map<Method, std::vector<double>> search_base_errors_;
  Eigen::VectorXd beta_true_;
  double initial_test_gc_ = 0.0;
  Eigen::VectorXd ols_relative_std_dev_;
};

}  // namespace dynid
