// The front of consistent estimates between the best torque fit and the best motion prediction:
// the combined estimator (search/refinement/combined.hpp) at a sweep of its GC weight w, each
// point warm-started from the last. Every point minimises
//     Phi_w(theta) = F(theta) / T0 + w g(G(P theta)) / G0
// with the normalisers T0, G0 and the noise floor G_f of the pc estimate (the first start), so
// that a weight means the same at every point whichever point it started from; w = 0 is pc
// itself. Every point is physically consistent (F is +inf outside the physical set). Along the
// front the training GC error falls and the torque term rises; which point to use is the
// held-out data's question (analysis/studies/log_study.hpp). docs/REFINEMENT.md, "The front".
#pragma once

#include <limits>
#include <vector>

#include "analysis/estimation/pipeline.hpp"

namespace dynid {

/// The default sweep: 0.01, 0.03, 0.1, ..., 30, 100 (two points a decade): from a step barely off
/// pc to past where the GC term rules (w = 1 is the combined estimator's default).
std::vector<double> defaultFrontWeights();

/// Throws InputError unless `weights` is non-empty, each finite and > 0, increasing (naming
/// `front_weights` and the entry).
void checkFrontWeights(const std::vector<double>& weights);

struct FrontPoint {
  double weight = 0.0;
  LeastSquaresOutcome estimate;  // standard: the point's parameters; covariance: pc's
  CombinedResult detail;         // how it ended, its start and end criteria
};

/// The front from the pc outcome `pc` (a usable physically consistent estimate): `weights`
/// ascending and > 0 (InputError otherwise, naming `front_weights`), the combined estimator at
/// each with `options` (its budgets per point; gc_weight, given_gc and given_floor are set here),
/// each point from the previous one's estimate (the first from pc's). Stops early, keeping the
/// points so far, when the options' run control stops (interrupt or the run's deadline); a point
/// whose start's rollouts diverge ends the sweep there (NumericalError only for the first).
std::vector<FrontPoint> combinedFront(const Model& model, const BaseParameters& base,
                                      const LeastSquaresSource& source,
                                      const LeastSquaresOutcome& pc, const GcProblem& gc,
                                      const CombinedOptions& options,
                                      const std::vector<double>& weights);

/// An estimate's errors on held-out data: the relative torque error, the GC error, and the GC error
/// that the torque noise alone causes with this model (search/refinement/combined.hpp's
/// gcNoiseFloor on the held-out rollouts; 0: not measured).
struct HeldOutErrors {
  double torque = std::numeric_limits<double>::quiet_NaN();
  double gc = std::numeric_limits<double>::quiet_NaN();
  bool consistent = true;  // every link physically consistent
  double gc_floor = 0.0;
  /// The GC error the model's errors add above its noise floor: 0 within kAtNoiseFloor of the
  /// floor (there the rollouts cannot tell the model from the truth: a model that damps the torque
  /// noise more rolls out closer to the noisy states, however wrong), gc - gc_floor above it.
  double gcExcess() const;
};
/// A GC error at most this factor above its noise floor is "at the floor".
inline constexpr double kAtNoiseFloor = 1.1;
/// Which candidate the rule takes, and why.
struct FrontChoice {
  int index = -1;             // the chosen candidate; -1 when none qualifies
  int best_torque = -1;       // the candidate whose torque error sets the bound
  double torque_bound = 0.0;  // (1 + tolerance) x its torque error
  bool at_floor = false;  // the chosen one's GC error is at its noise floor (so were its rivals')
};
/// The choice on held-out data (a study's and an identify request's `front_weights`): among the
/// physically consistent candidates with finite errors whose torque error is at most (1 +
/// tolerance) times the least of theirs, the least GC excess above the noise floor (gcExcess;
/// without floors, the least GC error); candidates at their floors tie, and a tie goes to the least
/// torque error (the motion cannot tell them apart, the torques can), then to the earlier. Nothing
/// about any candidate is assumed: where the input model predicts the motion best within the bound,
/// it is chosen.
FrontChoice chooseByHeldOut(const std::vector<HeldOutErrors>& candidates, double tolerance);

}  // namespace dynid
