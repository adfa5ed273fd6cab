#include "analysis/floating/stand_tilts.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>

#include "core/errors.hpp"
#include "core/floating/floating_data.hpp"
#include "core/floating/floating_regressor.hpp"
#include "core/format.hpp"
#include "core/spatial.hpp"

namespace dynid {

void StandTiltRequest::check() const {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InputError(message);
  };
  require(stands >= 1 && stands <= kMaxStandChoices,
          "`stands` is 1 to " + std::to_string(kMaxStandChoices) + " orientations, not " +
              std::to_string(stands));
  require(max_tilt > 0.0 && max_tilt <= M_PI / 2,
          "`max_tilt` is in (0, pi/2] rad, not " + formatNumber(max_tilt));
  require(tilt_grid >= 3 && tilt_grid <= 21 && tilt_grid % 2 == 1,
          "`tilt_grid` is odd, 3 to 21 (upright among the candidates), not " +
              std::to_string(tilt_grid));
  require(stands <= tilt_grid * tilt_grid,
          "`stands`: " + std::to_string(stands) + " orientations of " +
              std::to_string(tilt_grid * tilt_grid) + " candidates (a finer `tilt_grid`)");
  require(samples >= 10 && samples <= 10000,
          "`samples` is 10 to 10000 states per orientation, not " + std::to_string(samples));
  require(design.period > 0.0 && std::isfinite(design.period),
          "`design` has no period (a design of `dynid excite`)");
  structural.check();
}

namespace {

/// Every set's structural base parameters and its rows over the design at any orientation.
class StandRows {
 public:
  StandRows(const FloatingModel& model, const StandTiltRequest& request)
      : model_(model), request_(request), data_(model) {
    FloatingStructuralOptions options;
    options.structural = request.structural;
    options.motion = FloatingMotion::kSuspended;
    sets_ =
        floatingStructuralBase(model, {std::begin(kSensorSets), std::end(kSensorSets)}, options);
  }
  const std::vector<SensorSetBase>& sets() const { return sets_; }
  /// Set s's base regressor over the design's states at the stand orientation (roll, pitch).
  Eigen::MatrixXd rows(std::size_t s, const Eigen::Vector2d& tilt) {
    const SensorSetBase& set = sets_[s];
    const int n = model_.numJoints();
    // The support holds the base: its own Jacobian (identity on the base twist) is what holds.
    Eigen::MatrixXd held = Eigen::MatrixXd::Zero(6, 6 + n);
    held.leftCols<6>().setIdentity();
    BaseMotion base;
    base.rotation = rotationFromRpy(tilt[0], tilt[1], 0.0);
    Eigen::VectorXd q(n), dq(n), ddq(n);
    Eigen::MatrixXd out;
    for (int k = 0; k < request_.samples; ++k) {
      evaluateReference(request_.design, request_.design.period * k / request_.samples, q, dq, ddq);
      const Eigen::MatrixXd Y = floatingRegressor(model_, data_, base, q, dq, ddq);
      const Eigen::MatrixXd block = set.base.baseRegressor(sensorRows(set.set, Y, held));
      if (out.size() == 0) out.resize(block.rows() * request_.samples, block.cols());
      out.middleRows(block.rows() * k, block.rows()) = block;
    }
    return out;
  }

 private:
  const FloatingModel& model_;
  const StandTiltRequest& request_;
  FloatingData data_;
  std::vector<SensorSetBase> sets_;
};

/// The unit-column condition number of rows whose information matrix is A (sqrt of the scaled
/// information's eigenvalue ratio); inf where a column is not seen or the matrix is singular at
/// the rank rule (1e-8 on the rows' singular values, 1e-16 on A's eigenvalues).
double conditionOf(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd d = A.diagonal();
  if ((d.array() <= 0.0).any()) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd inv = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = inv.asDiagonal() * A * inv.asDiagonal();
  const Eigen::VectorXd ev =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(scaled, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(ev[0] > 1e-16 * ev[ev.size() - 1])) return std::numeric_limits<double>::infinity();
  return std::sqrt(ev[ev.size() - 1] / ev[0]);
}

/// Every set's determined count and condition number on the design at `tilts`.
std::vector<StandSetScore> scores(StandRows& rows, const std::vector<Eigen::Vector2d>& tilts) {
  std::vector<StandSetScore> out;
  for (std::size_t s = 0; s < rows.sets().size(); ++s) {
    Eigen::MatrixXd W;
    for (const Eigen::Vector2d& tilt : tilts) {
      const Eigen::MatrixXd block = rows.rows(s, tilt);
      W.conservativeResize(W.rows() + block.rows(), block.cols());
      W.bottomRows(block.rows()) = block;
    }
    StandSetScore score;
    score.set = rows.sets()[s].set;
    score.combinations = rows.sets()[s].base.numBase();
    score.determined = measureExcitation(W).rank;
    score.condition = score.determined == score.combinations
                          ? scaledConditionNumber(W)
                          : std::numeric_limits<double>::infinity();
    out.push_back(score);
  }
  return out;
}

/// The greedy choice and its exchanges, on the candidates' information matrices.
struct Chooser {
  std::vector<Eigen::Vector2d> candidates;
  std::vector<Eigen::MatrixXd> information;
  double criterion(const std::vector<int>& chosen) const {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(information[0].rows(), information[0].cols());
    for (int c : chosen) A += information[static_cast<std::size_t>(c)];
    return conditionOf(A);
  }
  /// The candidate that makes `chosen` with it (at `slot`, or appended when slot is its size) the
  /// best, and its criterion; ties keep the earliest candidate (the grid's order).
  std::pair<int, double> best(std::vector<int> chosen, std::size_t slot) const {
    if (slot == chosen.size()) chosen.push_back(0);
    std::pair<int, double> out{-1, std::numeric_limits<double>::infinity()};
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      if (std::find(chosen.begin(), chosen.end(), static_cast<int>(c)) != chosen.end()) continue;
      chosen[slot] = static_cast<int>(c);
      const double value = criterion(chosen);
      if (out.first < 0 || value < out.second) out = {static_cast<int>(c), value};
    }
    return out;
  }
};

/// The request checked, and its design against the model.
void checkFor(const FloatingModel& model, const StandTiltRequest& request) {
  request.check();
  if (request.design.offset.size() != model.numJoints())
    throw InputError("`design` moves " + std::to_string(request.design.offset.size()) +
                     " joints; the robot has " + std::to_string(model.numJoints()));
}

}  // namespace

std::vector<StandSetScore> scoreStandTilts(const FloatingModel& model,
                                           const StandTiltRequest& request,
                                           const std::vector<Eigen::Vector2d>& tilts) {
  checkFor(model, request);
  if (tilts.empty()) throw InputError("`tilts`: no orientation to score");
  for (const Eigen::Vector2d& tilt : tilts)
    if (!tilt.allFinite()) throw InputError("`tilts`: an orientation that is not finite");
  StandRows rows(model, request);
  return scores(rows, tilts);
}

StandTiltChoice chooseStandTilts(const FloatingModel& model, const StandTiltRequest& request) {
  checkFor(model, request);
  StandRows rows(model, request);
  const std::size_t wrenches = 0;  // kSensorSets' first: the support's six rows
  Chooser chooser;
  const int half = request.tilt_grid / 2;
  int upright = 0;
  for (int i = -half; i <= half; ++i)
    for (int j = -half; j <= half; ++j) {
      if (i == 0 && j == 0) upright = static_cast<int>(chooser.candidates.size());
      const Eigen::Vector2d tilt(request.max_tilt * i / half, request.max_tilt * j / half);
      chooser.candidates.push_back(tilt);
      const Eigen::MatrixXd W = rows.rows(wrenches, tilt);
      chooser.information.push_back(W.transpose() * W);
    }
  StandTiltChoice out;
  out.candidates = static_cast<int>(chooser.candidates.size());
  std::vector<int> chosen = {upright};
  out.condition_added.push_back(chooser.criterion(chosen));
  while (static_cast<int>(chosen.size()) < request.stands) {
    const auto [c, value] = chooser.best(chosen, chosen.size());
    chosen.push_back(c);
    out.condition_added.push_back(value);
  }
  // Exchanges (Fedorov's): each chosen tilt but upright replaced by the candidate that improves
  // the criterion most, until none does (each pass lowers it, over a finite set: it ends).
  double current = out.condition_added.back();
  for (bool improved = true; improved;) {
    improved = false;
    for (std::size_t slot = 1; slot < chosen.size(); ++slot) {
      const auto [c, value] = chooser.best(chosen, slot);
      if (c >= 0 && value < current * (1.0 - 1e-9)) {
        chosen[slot] = c;
        current = value;
        improved = true;
        ++out.exchanges;
      }
    }
  }
  out.condition = current;
  for (int c : chosen) out.tilts.push_back(chooser.candidates[static_cast<std::size_t>(c)]);
  out.upright = scores(rows, {out.tilts.front()});
  out.chosen = scores(rows, out.tilts);
  return out;
}

}  // namespace dynid
