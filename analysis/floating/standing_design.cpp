#include "analysis/floating/standing_design.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <memory>
#include <numbers>
#include <random>

#include <Eigen/Geometry>

#include "analysis/floating/standing.hpp"
#include "core/errors.hpp"
#include "core/floating/floating_data.hpp"
#include "core/floating/floating_regressor.hpp"
#include "core/format.hpp"
#include "search/cobyla.hpp"

namespace dynid {

namespace {
std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> p);
}  // namespace

void StandingDesignRequest::check() const {
  const auto need = [](bool ok, const std::string& what) {
    if (!ok) throw InputError(what);
  };
  need(!contacts.empty(), "`contacts`: a standing robot holds on at least one");
  need(stance.allFinite(), "`stance` is finite");
  need(period >= 0.5 && period <= 120.0, "`period` is 0.5 to 120 s, not " + formatNumber(period));
  need(harmonics >= 2 && harmonics <= 10,
       "`harmonics` is 2 to 10, not " + std::to_string(harmonics));
  need(max_sway > 0.0 && max_sway <= 1.0,
       "`max_sway` is in (0, 1] m, not " + formatNumber(max_sway));
  need(max_turn > 0.0 && max_turn <= std::numbers::pi / 4,
       "`max_turn` is in (0, pi/4] rad, not " + formatNumber(max_turn));
  need(max_swing >= 0.0 && max_swing <= std::numbers::pi,
       "`max_swing` is 0 to pi rad, not " + formatNumber(max_swing));
  need(joint_margin >= 0.0 && joint_margin <= 1.0,
       "`joint_margin` is 0 to 1 rad, not " + formatNumber(joint_margin));
  need(friction_cone >= 0.0 && friction_cone <= 10.0,
       "`friction_cone` is 0 (none) to 10, not " + formatNumber(friction_cone));
  need(sole.empty() || (sole.size() >= 3 && sole.size() <= 32),
       "`sole` has 3 to 32 corners, not " + std::to_string(sole.size()));
  for (const Eigen::Vector2d& corner : sole)
    need(corner.allFinite() && corner.cwiseAbs().maxCoeff() <= 10.0,
         "`sole`'s corners are finite, within 10 m of the frame");
  need(sole.empty() || convexHull(sole).size() >= 3, "`sole`'s corners enclose an area");
  need(
      sole.empty() || std::any_of(contacts.begin(), contacts.end(),
                                  [](const Contact& c) { return c.kind == Contact::Kind::kFrame; }),
      "`sole` is under a frame contact (NAME:frame), and every contact is a point");
  need(grid_rate >= 1.0 && grid_rate <= 1000.0,
       "`grid_rate` is 1 to 1000 samples a second, not " + formatNumber(grid_rate));
  need(check_rate >= grid_rate && check_rate <= 10000.0,
       "`check_rate` is `grid_rate` to 10000 samples a second, not " + formatNumber(check_rate));
  need(period * check_rate <= 1e5, "`period` times `check_rate` is at most 100000 samples");
  need(starts >= 1 && starts <= 64, "`starts` is 1 to 64, not " + std::to_string(starts));
  need(evaluations >= 10 && evaluations <= 100000,
       "`evaluations` is 10 to 100000, not " + std::to_string(evaluations));
  need(max_seconds > 0.0, "`max_seconds` is positive (infinity: no budget)");
  structural.check();
}

namespace {

constexpr double kInfeasible = 1.0;  // every constraint's value where the legs cannot follow
constexpr double kUnranked = 20.0;   // the objective (log10) of rows below the class's rank

/// A candidate: the base's six coordinates and, where some joint is free, the free joints'.
struct SwayDesign {
  FourierSeries base;
  std::optional<FourierSeries> joints;
};

/// The free variables, scaled so that 1 is about a bound: per coordinate (the base's six, then
/// each joint no foot depends on) a_1..a_(H-1) and b_1..b_(H-1) as fractions of the bound times
/// the base frequency; a_H and b_H follow from rest at t = 0, and the offset from the stance's
/// pose there.
class Coding {
 public:
  Coding(const StandingDesignRequest& r, const std::vector<int>& free) : r_(r), free_(free) {}
  int perCoordinate() const { return 2 * (r_.harmonics - 1); }
  int size() const { return static_cast<int>(6 + free_.size()) * perCoordinate(); }
  SwayDesign decode(const double* x, double shrink = 1.0) const {
    SwayDesign out;
    out.base = series(6);
    for (int i = 0; i < 6; ++i)
      row(x + i * perCoordinate(), shrink * (i < 3 ? r_.max_sway : r_.max_turn), i, out.base);
    if (free_.empty()) return out;
    out.joints = series(static_cast<int>(r_.stance.size()));
    out.joints->offset = r_.stance;
    for (std::size_t f = 0; f < free_.size(); ++f)
      row(x + (6 + static_cast<int>(f)) * perCoordinate(), shrink * r_.max_swing, free_[f],
          *out.joints);
    return out;
  }

 private:
  FourierSeries series(int rows) const {
    FourierSeries d;
    d.period = r_.period;
    d.offset.setZero(rows);
    d.a.setZero(rows, r_.harmonics);
    d.b.setZero(rows, r_.harmonics);
    return d;
  }
  /// Row i of d from the variables u for a coordinate bounded by `bound`: at rest at t = 0, where
  /// its value is the offset it had.
  void row(const double* u, double bound, int i, FourierSeries& d) const {
    const int h = r_.harmonics;
    const double w = 2.0 * std::numbers::pi / r_.period, scale = bound * w;
    double sum_a = 0.0, sum_kb = 0.0;
    for (int k = 0; k < h - 1; ++k) {
      d.a(i, k) = scale * u[k];
      d.b(i, k) = scale * u[h - 1 + k];
      sum_a += d.a(i, k);
      sum_kb += (k + 1) * d.b(i, k);
    }
    d.a(i, h - 1) = -sum_a;
    d.b(i, h - 1) = -sum_kb / h;
    for (int k = 0; k < h; ++k) d.offset[i] += d.b(i, k) / (w * (k + 1));  // c(0) as before
  }

  const StandingDesignRequest& r_;
  std::vector<int> free_;
};

/// The convex hull of points, counter-clockwise (Andrew's monotone chain).
std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> p) {
  if (p.size() < 3) return p;
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {  // lower hull
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {  // upper hull
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

/// How far a frame contact's centre of pressure lies outside its sole [m] (negative: inside, the
/// distance to the nearest edge): its moment n and force f about and in the frame (z its normal),
/// the centre (-n_y / f_z, n_x / f_z); a force that does not press the sole counts as 1 m out.
double outsideSole(const Eigen::Vector3d& n, const Eigen::Vector3d& f,
                   const std::vector<Eigen::Vector2d>& hull) {
  if (!(f.z() > 0.0)) return 1.0;
  const Eigen::Vector2d p(-n.y() / f.z(), n.x() / f.z());
  double out = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d a = hull[i], edge = hull[(i + 1) % hull.size()] - a;
    const Eigen::Vector2d outward(edge.y(), -edge.x());  // right of a counter-clockwise edge
    out = std::max(out, outward.dot(p - a) / outward.norm());
  }
  return out;
}

/// How a motion keeps the bounds: each value <= 0 where it does (COBYLA's constraints).
struct Margins {
  double sway = kInfeasible, turn = kInfeasible, joints = kInfeasible, speeds = kInfeasible,
         cones = kInfeasible, soles = kInfeasible, swing = kInfeasible;
  // Reported in the request's units.
  double largest_sway = 0.0, largest_turn = 0.0, clearance = 0.0, cone_use = 0.0;
  double largest_swing = 0.0, sole_clearance = std::numeric_limits<double>::infinity();
  bool feasible() const {
    return sway <= 0.0 && turn <= 0.0 && joints <= 0.0 && speeds <= 0.0 && cones <= 0.0 &&
           soles <= 0.0 && swing <= 0.0;
  }
  double worst() const { return std::max({sway, turn, joints, speeds, cones, soles, swing}); }
  bool followed() const { return !(sway == kInfeasible && cones == kInfeasible); }
  /// The bound broken most, in the request's words.
  std::string broken() const {
    const double w = worst();
    if (w == joints)
      return "`joint_margin` (a joint " + formatNumber(clearance, 3) + " rad from a limit)";
    if (w == cones) return "`friction_cone` (a foot's force outside its cone)";
    if (w == soles) return "`sole` (a centre of pressure outside its sole)";
    if (w == speeds) return "the joints' velocity limits (a longer `period` slows the sway)";
    if (w == sway) return "`max_sway`";
    if (w == swing) return "`max_swing`";
    return "`max_turn`";
  }
};

/// A sway's samples with each sample's regressor (at the model's own parameters) and its feet's
/// stacked Jacobian, made once: the criterion, the cones and the class all read them.
struct SampledSway {
  std::shared_ptr<const FloatingDataset> data;
  std::vector<Eigen::MatrixXd> Y, J;
};

/// A sway's motion, its rows for every set and its margins.
class Evaluator {
 public:
  Evaluator(const FloatingModel& model, const StandingDesignRequest& request)
      : model_(model),
        request_(request),
        data_(model),
        theta_(model.standardParameters()),
        hull_(convexHull(request.sole)),
        held_(heldJoints(model, request.contacts)) {
    FloatingStructuralOptions options;
    options.structural = request.structural;
    options.contacts = request.contacts;
    options.motion = FloatingMotion::kHolding;
    holding_ =
        floatingStructuralBase(model, {std::begin(kSensorSets), std::end(kSensorSets)}, options);
  }
  const FloatingModel& model() const { return model_; }
  const std::vector<SensorSetBase>& holding() const { return holding_; }
  /// Per set, the holding base parameters any sway of the stance excites (column indices).
  const std::vector<std::vector<int>>& standing() const { return standing_; }
  /// Adds a sway's rows to the standing class's pool (settle() reads it).
  void pool(const SampledSway& m) {
    pooled_.resize(holding_.size());
    for (std::size_t s = 0; s < holding_.size(); ++s) {
      const Eigen::MatrixXd block = rows(s, m);
      pooled_[s].conservativeResize(pooled_[s].rows() + block.rows(), block.cols());
      pooled_[s].bottomRows(block.rows()) = block;
    }
  }
  /// The standing class of every set from the pool: the holding base parameters its rows excite
  /// by identify's rule (measureExcitation: a pivot of the unit-column rows above 1e-8 of the
  /// largest), so that a count here is the count identify gives the same motion.
  void settle() {
    standing_.clear();
    for (std::size_t s = 0; s < holding_.size(); ++s) {
      const Excitation seen = measureExcitation(pooled_[s]);
      std::vector<int> columns;
      for (int j = 0; j < pooled_[s].cols(); ++j)
        if (std::find(seen.unexcited.begin(), seen.unexcited.end(), j) == seen.unexcited.end())
          columns.push_back(j);
      standing_.push_back(std::move(columns));
    }
  }

  /// The motion at `rate` over one period, or none where the legs cannot follow it.
  std::optional<SampledSway> motion(const SwayDesign& design, double rate) {
    StandingMotionRequest r;
    r.contacts = request_.contacts;
    r.stance = request_.stance;
    r.base_design = design.base;
    r.joint_design = design.joints;
    r.check_limits = false;  // measured as a margin
    r.rate = rate;
    r.samples = std::max(2, static_cast<int>(std::lround(design.base.period * rate)));
    std::shared_ptr<FloatingDataset> m;
    try {
      m = standingMotion(model_, r);
    } catch (const InputError&) {
      return std::nullopt;
    }
    return sampled(std::move(m));
  }
  /// The motion's samples with their regressors and Jacobians.
  SampledSway sampled(std::shared_ptr<const FloatingDataset> m) {
    SampledSway out;
    for (int k = 0; k < m->numSamples(); ++k) {
      out.Y.push_back(regressor(*m, k));
      out.J.push_back(stackedContactJacobian(model_, data_, request_.contacts, m->q.col(k)));
    }
    out.data = std::move(m);
    return out;
  }
  /// Set s's rows over the motion in the holding class's base parameters.
  Eigen::MatrixXd rows(std::size_t s, const SampledSway& m) const {
    Eigen::MatrixXd out;
    const auto N = static_cast<Eigen::Index>(m.Y.size());
    for (std::size_t k = 0; k < m.Y.size(); ++k) {
      const Eigen::MatrixXd block =
          holding_[s].base.baseRegressor(sensorRows(holding_[s].set, m.Y[k], m.J[k]));
      if (out.size() == 0) out.resize(block.rows() * N, block.cols());
      out.middleRows(block.rows() * static_cast<Eigen::Index>(k), block.rows()) = block;
    }
    return out;
  }
  Margins margins(const SwayDesign& design, const SampledSway& sway) {
    const FloatingDataset& m = *sway.data;
    Margins out;
    Eigen::VectorXd c, dc, ddc;
    for (int k = 0; k < m.numSamples(); ++k) {
      evaluateReference(design.base, m.time[k], c, dc, ddc);
      out.largest_sway = std::max(out.largest_sway, c.head<3>().cwiseAbs().maxCoeff());
      out.largest_turn = std::max(out.largest_turn, c.tail<3>().cwiseAbs().maxCoeff());
    }
    for (int j = 0; j < model_.numJoints() && design.joints; ++j)
      if (!held_[static_cast<std::size_t>(j)])
        out.largest_swing =
            std::max(out.largest_swing, (m.q.row(j).array() - request_.stance[j]).abs().maxCoeff());
    out.swing = request_.max_swing > 0.0 ? out.largest_swing / request_.max_swing - 1.0 : 0.0;
    out.sway = out.largest_sway / request_.max_sway - 1.0;
    out.turn = out.largest_turn / request_.max_turn - 1.0;
    out.clearance = std::numeric_limits<double>::infinity();
    double speed = 0.0;
    for (int j = 0; j < model_.numJoints(); ++j) {
      const JointLimits& limits = model_.limbs().limits[static_cast<std::size_t>(j)];
      for (int k = 0; k < m.numSamples(); ++k) {
        out.clearance =
            std::min({out.clearance, m.q(j, k) - limits.lower, limits.upper - m.q(j, k)});
        if (std::isfinite(limits.velocity) && limits.velocity > 0.0)
          speed = std::max(speed, std::abs(m.dq(j, k)) / limits.velocity);
      }
    }
    out.joints = request_.joint_margin - out.clearance;
    out.speeds = speed - 1.0;
    out.cones = out.soles = 0.0;
    if (request_.friction_cone > 0.0 || !request_.sole.empty()) conesOf(sway, out);
    return out;
  }

 private:
  /// Sample k's regressor.
  Eigen::MatrixXd regressor(const FloatingDataset& m, int k) {
    BaseMotion base;
    const Eigen::Vector4d o = m.orientation.col(k);
    base.rotation = Eigen::Quaterniond(o[0], o[1], o[2], o[3]).toRotationMatrix();
    base.twist = m.twist.col(k);
    base.acceleration = m.acceleration.col(k);
    return floatingRegressor(model_, data_, base, m.q.col(k), m.dq.col(k), m.ddq.col(k));
  }
  /// The least-norm forces that hold each sample, against the cones: each foot's (a sole's
  /// force, after its moment) |tangential| - mu normal, over the force the contacts carry; and
  /// against the soles: each frame contact's centre of pressure outside its sole [m].
  void conesOf(const SampledSway& sway, Margins& out) {
    const FloatingDataset& m = *sway.data;
    const double mu = request_.friction_cone;
    out.cones = mu > 0.0 ? -std::numeric_limits<double>::infinity() : 0.0;
    out.soles = request_.sole.empty() ? 0.0 : -std::numeric_limits<double>::infinity();
    for (int k = 0; k < m.numSamples(); ++k) {
      const auto at = static_cast<std::size_t>(k);
      const Eigen::VectorXd wrench = (sway.Y[at] * theta_).head<6>();
      const Eigen::MatrixXd map = sway.J[at].leftCols<6>().transpose();
      const Eigen::VectorXd f = map.completeOrthogonalDecomposition().solve(wrench);
      const Eigen::Vector4d o = m.orientation.col(k);
      const Eigen::Matrix3d R = Eigen::Quaterniond(o[0], o[1], o[2], o[3]).toRotationMatrix();
      const Eigen::Vector3d up = -(R.transpose() * model_.gravity()).normalized();
      const double carried = std::max(wrench.tail<3>().norm(), 1e-12);
      int row = 0;
      for (const Contact& c : request_.contacts) {
        const bool frame = c.kind == Contact::Kind::kFrame;
        const Eigen::Vector3d force = f.segment<3>(row + (frame ? 3 : 0));
        row += c.dimension();
        if (frame && !request_.sole.empty()) {
          const Eigen::Matrix3d Rc = contactPose(model_, data_, c, m.q.col(k)).rotation;
          const double outside =
              outsideSole(Rc.transpose() * f.segment<3>(row - 6), Rc.transpose() * force, hull_);
          out.soles = std::max(out.soles, outside);
          out.sole_clearance = std::min(out.sole_clearance, -outside);
        }
        if (mu <= 0.0) continue;
        const double normal = force.dot(up), tangential = (force - normal * up).norm();
        out.cones = std::max(out.cones, (tangential - mu * normal) / carried);
        out.cone_use =
            std::max(out.cone_use, normal > 0.0 ? tangential / (mu * normal)
                                                : std::numeric_limits<double>::infinity());
      }
    }
  }

  const FloatingModel& model_;
  const StandingDesignRequest& request_;
  FloatingData data_;
  Eigen::VectorXd theta_;
  std::vector<SensorSetBase> holding_;
  std::vector<std::vector<int>> standing_;  // per set, in holding_'s order
  std::vector<Eigen::Vector2d> hull_;       // the sole's convex hull, counter-clockwise
  std::vector<char> held_;                  // the joints some foot depends on
  std::vector<Eigen::MatrixXd> pooled_;     // per set: the sways' rows (holding base parameters)
};

/// log10 of the unit-column condition number of the rows in the standing class's base parameters
/// (kUnranked below its rank).
/// W's columns of the standing class.
Eigen::MatrixXd classColumns(const std::vector<int>& standing, const Eigen::MatrixXd& W) {
  Eigen::MatrixXd out(W.rows(), static_cast<Eigen::Index>(standing.size()));
  for (std::size_t j = 0; j < standing.size(); ++j)
    out.col(static_cast<Eigen::Index>(j)) = W.col(standing[j]);
  return out;
}

double criterionOf(const std::vector<int>& standing, const Eigen::MatrixXd& W) {
  const Eigen::MatrixXd W1 = classColumns(standing, W);
  const double condition = scaledConditionNumber(W1);
  return std::isfinite(condition) ? std::log10(condition) : kUnranked;
}

/// Random coefficients of start k (N(0, 0.3 / harmonic) for the base's coordinates, 0.1 for the
/// free joints', the lower harmonics carrying more).
std::vector<double> startPoint(const StandingDesignRequest& r, const Coding& coding, int k) {
  std::mt19937_64 rng(r.seed * 1000003ULL + static_cast<std::uint64_t>(k));
  std::normal_distribution<double> normal;
  std::vector<double> x(static_cast<std::size_t>(coding.size()));
  const auto base = static_cast<std::size_t>(6 * coding.perCoordinate());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const int harmonic = static_cast<int>(i % static_cast<std::size_t>(r.harmonics - 1)) + 1;
    // The free joints start smaller: each of many may break its bound, and COBYLA starts best
    // where none does.
    x[i] = (i < base ? 0.3 : 0.1) * normal(rng) / harmonic;
  }
  return x;
}

/// The standing class's base parameters of every set: the rows of random sways of the stance
/// pooled (at the bounds, else at a half or a quarter of them where the legs cannot follow), read
/// as the structural analysis reads random states.
void standingClass(Evaluator& evaluator, const StandingDesignRequest& r, const Coding& coding) {
  int followed = 0;
  for (int k = 0; k < 18 && followed < 6; ++k) {
    const std::vector<double> x = startPoint(r, coding, 1000 + k);
    const std::optional<SampledSway> m =
        evaluator.motion(coding.decode(x.data(), std::ldexp(1.0, -(k / 6))), r.grid_rate);
    if (!m) continue;
    ++followed;
    evaluator.pool(*m);
  }
  if (followed < 2)
    throw InputError(
        "`stance`: the legs cannot follow random sways of it (a contact out of reach): bend the "
        "stance, or lower `max_sway` and `max_turn`");
  evaluator.settle();
}

/// Every set's counts and condition number on a motion.
std::vector<StandingSetScore> scoresOf(const Evaluator& evaluator, const SampledSway& m) {
  std::vector<StandingSetScore> out;
  for (std::size_t s = 0; s < evaluator.holding().size(); ++s) {
    const Eigen::MatrixXd W = evaluator.rows(s, m);
    StandingSetScore score;
    score.set = evaluator.holding()[s].set;
    score.holding = evaluator.holding()[s].base.numBase();
    score.standing = static_cast<int>(evaluator.standing()[s].size());
    score.determined = measureExcitation(W).rank;
    const Eigen::MatrixXd W1 = classColumns(evaluator.standing()[s], W);
    score.condition = measureExcitation(W1).rank == score.standing
                          ? scaledConditionNumber(W1)
                          : std::numeric_limits<double>::infinity();
    out.push_back(score);
  }
  return out;
}

/// The best design checked at check_rate (shrunk by a tenth at a time while it breaks a bound
/// between the optimiser's samples), scored with every set, beside `dynid simulate --stance`'s
/// default sway over the same period.
void finishStandingDesign(Evaluator& evaluator, const StandingDesignRequest& r,
                          const Coding& coding, const std::vector<double>& x, StandingDesign& out) {
  std::optional<SampledSway> m;
  Margins margins;
  for (int tries = 0; tries < 30; ++tries, out.shrink *= 0.9) {
    const SwayDesign sway = coding.decode(x.data(), out.shrink);
    out.base = sway.base;
    out.joints = sway.joints;
    m = evaluator.motion(sway, r.check_rate);
    if (m && (margins = evaluator.margins(sway, *m)).feasible()) break;
  }
  if (!m || !margins.feasible())
    throw Error("the best design breaks its bounds between the optimiser's samples even at " +
                formatNumber(out.shrink, 2) + " of its size: raise `grid_rate`");
  // The design is a sway of the stance too: what it determines is in the class by definition
  // (random sways that the legs could follow only at a fraction of the bounds can show less).
  evaluator.pool(*m);
  evaluator.settle();
  out.scores = scoresOf(evaluator, *m);
  out.largest_sway = margins.largest_sway;
  out.largest_turn = margins.largest_turn;
  out.joint_clearance = margins.clearance;
  out.cone_use = margins.cone_use;
  out.largest_swing = margins.largest_swing;
  out.sole_clearance = margins.sole_clearance;
  StandingMotionRequest sway;
  sway.contacts = r.contacts;
  sway.stance = r.stance;
  sway.period = r.period;
  sway.rate = r.check_rate;
  sway.samples = m->data->numSamples();
  try {
    out.baseline = scoresOf(evaluator, evaluator.sampled(standingMotion(evaluator.model(), sway)));
  } catch (const InputError& e) {
    out.baseline_problem = e.what();
  }
}

}  // namespace

StandingDesign designStandingSway(const FloatingModel& model,
                                  const StandingDesignRequest& request) {
  request.check();
  const auto started = std::chrono::steady_clock::now();
  if (request.stance.size() != model.numJoints())
    throw InputError("`stance` has " + std::to_string(request.stance.size()) +
                     " joints, the model " + std::to_string(model.numJoints()));
  const RunControl control = request.control.within(request.max_seconds, started);
  std::vector<int> free;  // the joints no foot depends on, which the design moves too
  const std::vector<char> held = heldJoints(model, request.contacts);
  for (int j = 0; j < model.numJoints() && request.max_swing > 0.0; ++j)
    if (!held[static_cast<std::size_t>(j)]) free.push_back(j);
  const Coding coding(request, free);
  Evaluator evaluator(model, request);
  standingClass(evaluator, request, coding);
  const auto chosen = static_cast<std::size_t>(
      std::find(std::begin(kSensorSets), std::end(kSensorSets), request.set) -
      std::begin(kSensorSets));
  StandingDesign out;
  Margins closest;  // of the points that broke a bound, the one that broke it least
  std::vector<double> best;
  double best_value = std::numeric_limits<double>::infinity();
  for (int k = 0; k < request.starts && !control.stopped(); ++k) {
    std::vector<double> x = startPoint(request, coding, k), start_best;
    double start_value = std::numeric_limits<double>::quiet_NaN();
    CobylaProblem problem;
    problem.dimension = coding.size();
    problem.inequalities = 5;
    Margins last;
    // COBYLA asks for the constraints right after the objective at the same point: the motion is
    // made once, by the objective, and its margins kept for the constraints.
    problem.objective = [&](const double* at) -> std::optional<double> {
      if (control.check()) return std::nullopt;
      ++out.evaluations;
      const SwayDesign design = coding.decode(at);
      const std::optional<SampledSway> m = evaluator.motion(design, request.grid_rate);
      if (!m) {
        last = Margins{};
        return kUnranked;
      }
      last = evaluator.margins(design, *m);
      if (!last.feasible() && last.worst() < closest.worst()) closest = last;
      const double value = criterionOf(evaluator.standing()[chosen], evaluator.rows(chosen, *m));
      if (last.feasible() && !(value >= start_value)) {
        start_value = value;
        start_best.assign(at, at + coding.size());
      }
      return value;
    };
    problem.inequality = [&](const double*, double* c) {
      c[0] = last.sway, c[1] = last.turn, c[2] = last.joints, c[3] = last.speeds, c[4] = last.cones;
    };
    problem.initial_step = {0.1};
    problem.max_evaluations = request.evaluations;
    problem.xtol_rel = 1e-6;
    runCobyla(problem, x);
    out.start_objectives.push_back(start_value);
    control.say("standing sway design: start " + std::to_string(k + 1) + " of " +
                std::to_string(request.starts) + ": " +
                (std::isnan(start_value)
                     ? std::string("no sway within the bounds")
                     : "condition number " + formatNumber(std::pow(10.0, start_value), 4)));
    if (!std::isnan(start_value) && start_value < best_value) {
      best_value = start_value;
      best = start_best;
      out.best_start = k;
    }
  }
  out.termination = request.control.interrupted() ? "interrupted"
                    : control.expired()           ? "seconds"
                                                  : "evaluations";
  if (best.empty() && !closest.followed())
    throw Error(
        "no start's sway could be followed (a contact out of the legs' reach at every point "
        "tried): move the `stance`, or lower `max_sway` and `max_turn`");
  if (best.empty())
    throw Error("no start met the bounds: the nearest broke " + closest.broken() +
                ": relax it, or move the `stance`");
  finishStandingDesign(evaluator, request, coding, best, out);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return out;
}

}  // namespace dynid
