// The excitation wing: dynid excite (analysis/excitation/excite.hpp), its design as to_json().
#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/excitation/excite.hpp"
#include "analysis/floating/stand_tilts.hpp"
#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/robots.hpp"
#include "python/run_support.hpp"
#include "reports/excitation_report.hpp"
#include "reports/stand_tilts_report.hpp"

namespace dynid::python {
namespace {

// ---- excite ----

struct ExcitePy {
  Model robot;
  ExcitationSettings settings;
  ExciteOutcome outcome;
  RunProvenance provenance;  // the call that made it
};

/// excite's stands, max_tilt and tilt_grid: the stand request (its design set after the run) and
/// the robot's URDF loaded with a floating base, checked before the work; nothing without stands.
struct StandChoice {
  StandTiltRequest request;
  FloatingModel model;
};

std::optional<StandChoice> standChoice(const Model& robot, const std::string& robot_spec,
                                       const std::optional<int>& stands, double max_tilt,
                                       int tilt_grid, const StructuralOptions& structural,
                                       double period) {
  if (!stands &&
      (max_tilt != StandTiltRequest{}.max_tilt || tilt_grid != StandTiltRequest{}.tilt_grid))
    throw py::value_error("max_tilt and tilt_grid apply with stands");
  if (!stands) return std::nullopt;
  if (robot_spec.empty())
    throw py::value_error(
        "stands: give robot_spec, the robot's URDF (loaded with a floating base to choose the "
        "stand's orientations)");
  StandTiltRequest request;
  request.stands = *stands;
  request.max_tilt = max_tilt;
  request.tilt_grid = tilt_grid;
  request.structural = structural;
  request.design.period = period;  // the check's placeholder until the design is made
  request.check();
  RobotOptions options;
  options.drive_terms = robot.driveTerms();
  FloatingModel model = loadFloatingRobot(robot_spec, options);
  if (model.numJoints() != robot.numJoints())
    throw py::value_error("stands: robot_spec has " + std::to_string(model.numJoints()) +
                          " moving joints with a floating base, the robot " +
                          std::to_string(robot.numJoints()));
  return StandChoice{std::move(request), std::move(model)};
}

ExcitePy excitePy(const Model& robot, const std::string& criterion, double period, int harmonics,
                  int starts, int evaluations, double budget_seconds, double grid_rate,
                  double check_rate, double torque_noise, int segments, double horizon,
                  const OptionalArrayLike& offset, const OptionalArrayLike& q_min,
                  const OptionalArrayLike& q_max, const OptionalArrayLike& dq_max,
                  const OptionalArrayLike& ddq_max, const OptionalArrayLike& tau_max,
                  double torque_margin, const std::optional<double>& floor, double base_radius,
                  int samples, std::uint64_t seed, double tolerance, int threads,
                  const PathLike& robot_spec_arg, const ProgressLike& progress,
                  const std::optional<int>& stands, double max_tilt, int tilt_grid) {
  const std::string robot_spec = pathArg(robot_spec_arg, "robot_spec");
  const int n = robot.numJoints();
  // excite --stands: the robot's URDF loaded again with a floating base, checked before the work.
  std::optional<StandChoice> stand = standChoice(robot, robot_spec, stands, max_tilt, tilt_grid,
                                                 {samples, seed, tolerance}, period);
  ExciteRequest r;  // checked by exciteRun
  r.robot = robot;
  r.criterion = parseExcitationCriterion(criterion);
  r.period = period;
  r.harmonics = harmonics;
  r.starts = starts;
  r.evaluations = evaluations;
  if (budget_seconds > 0.0) r.max_seconds = budget_seconds;
  r.grid_rate = grid_rate;
  r.check_rate = check_rate;
  r.torque_noise = torque_noise;
  r.gc_segments = segments;
  r.gc_horizon = horizon;
  r.seed = seed;
  r.threads = threads;
  r.structural = {samples, seed, tolerance};
  r.offset = jointOption(offset, "offset", n);
  LimitOverrides overrides;
  overrides.q_min = jointOption(q_min, "q_min", n);
  overrides.q_max = jointOption(q_max, "q_max", n);
  overrides.dq_max = jointOption(dq_max, "dq_max", n);
  overrides.ddq_max = jointOption(ddq_max, "ddq_max", n);
  overrides.tau_max = jointOption(tau_max, "tau_max", n);
  overrides.torque_margin = torque_margin;
  overrides.floor = floor;
  overrides.base_radius = base_radius;
  r.limits = excitationLimits(robot, overrides);
  if (r.offset) checkOffsets(robot, r.limits, *r.offset);
  Interrupt interrupt;
  interrupt.connect(r.control, progress);
  ExcitePy out{robot, {}, {}, {}};
  out.settings.robot = robot_spec.empty() ? robot.name : robot_spec;
  if (!robot_spec.empty()) out.settings.source = modelSourceOf(robot_spec);
  out.settings.harmonics = harmonics;
  out.settings.evaluations = evaluations;
  out.settings.period = period;
  const PythonRun call("excite", {robot_spec}, seed, threads);
  {
    py::gil_scoped_release release;
    out.outcome = exciteRun(r);
  }
  if (stand && !interrupt.flag()->load()) {  // the orientations for the design, as the CLI's
    stand->request.design = out.outcome.design;
    py::gil_scoped_release release;
    StandDesign chosen;
    chosen.choice = chooseStandTilts(stand->model, stand->request);
    chosen.max_tilt = stand->request.max_tilt;
    chosen.grid = stand->request.tilt_grid;
    chosen.samples = stand->request.samples;
    out.settings.stand = std::move(chosen);
  }
  out.provenance = call.finish();
  out.settings.starts = static_cast<int>(out.outcome.starts.size());  // 0 resolved
  interrupt.raiseIfFailed();
  if (!interrupt.cancelled()) interrupt.warnIfStopped();
  return out;
}

void bindExcite(py::module_& m) {
  py::class_<ExcitePy>(m, "Excitation", "What `dynid excite` writes as excitation.json.")
      .def_property_readonly(
          "period", [](const ExcitePy& e) { return e.outcome.design.period; },
          "The motion's period [s].")
      .def_property_readonly(
          "offset", [](const ExcitePy& e) { return toNumpy(e.outcome.design.offset); },
          "Each joint's centre of motion, shape (n,) [rad].")
      .def_property_readonly(
          "a", [](const ExcitePy& e) { return toNumpy(e.outcome.design.a); },
          "The Fourier coefficients a_jk of the sine terms (q_j = offset_j + sum_k a_jk/(w k) "
          "sin(w k t) - b_jk/(w k) cos(w k t)), shape (n, harmonics) [rad/s].")
      .def_property_readonly(
          "b", [](const ExcitePy& e) { return toNumpy(e.outcome.design.b); },
          "The Fourier coefficients b_jk of the cosine terms, shape (n, harmonics) [rad/s].")
      .def_property_readonly(
          "condition_number", [](const ExcitePy& e) { return e.outcome.score.condition_unit; },
          "The designed motion's base regressor condition number (unit columns).")
      .def_property_readonly(
          "baseline_condition_number",
          [](const ExcitePy& e) { return e.outcome.baseline.condition_unit; },
          "The default sinusoid's, for comparison.")
      .def_property_readonly(
          "termination", [](const ExcitePy& e) { return e.outcome.termination; },
          "Why the design stopped (evaluations, seconds, tolerance or interrupted).")
      .def_property_readonly(
          "stand_tilts",
          [](const ExcitePy& e) -> std::optional<std::vector<std::pair<double, double>>> {
            if (!e.settings.stand) return std::nullopt;
            std::vector<std::pair<double, double>> out;
            for (const Eigen::Vector2d& t : e.settings.stand->choice.tilts)
              out.emplace_back(t[0], t[1]);
            return out;
          },
          "The stand orientations (roll, pitch) [rad] chosen for the design with stands, upright "
          "first (simulate_floating(trajectory=...) runs the design at them); None without.")
      .def(
          "sample",
          [](const ExcitePy& e, double rate) {
            py::gil_scoped_release release;
            return sampleFourier(e.outcome.design, e.robot, rate);
          },
          py::arg("rate") = ExcitationSettings{}.csv_rate,
          "One period of the motion at `rate` as a Dataset (tau: the model's inverse dynamics).")
      .def(
          "to_json",
          [](const ExcitePy& e) {
            return jsonText(withCall(excitationJson(e.robot, e.settings, e.outcome), e.provenance),
                            2) +
                   "\n";
          },
          "excitation.json, as `dynid excite` writes it (simulate(trajectory=...) reads it).");

  m.def(
      "excite", &excitePy, py::arg("robot"), py::arg("criterion") = "cond",
      py::arg("period") = ExciteRequest{}.period, py::arg("harmonics") = ExciteRequest{}.harmonics,
      py::arg("starts") = ExciteRequest{}.starts,
      py::arg("evaluations") = ExciteRequest{}.evaluations, py::arg("budget_seconds") = 0.0,
      py::arg("grid_rate") = ExciteRequest{}.grid_rate,
      py::arg("check_rate") = ExciteRequest{}.check_rate,
      py::arg("torque_noise") = ExciteRequest{}.torque_noise,
      py::arg("segments") = ExciteRequest{}.gc_segments,
      py::arg("horizon") = ExciteRequest{}.gc_horizon, py::arg("offset") = py::none(),
      py::arg("q_min") = py::none(), py::arg("q_max") = py::none(), py::arg("dq_max") = py::none(),
      py::arg("ddq_max") = py::none(), py::arg("tau_max") = py::none(),
      py::arg("torque_margin") = LimitOverrides{}.torque_margin, py::arg("floor") = py::none(),
      py::arg("base_radius") = LimitOverrides{}.base_radius,
      py::arg("samples") = StructuralOptions{}.samples, py::arg("seed") = StructuralOptions{}.seed,
      py::arg("tolerance") = StructuralOptions{}.tolerance, py::arg("threads") = kAllThreads,
      py::arg("robot_spec") = "", py::arg("progress") = py::none(), py::arg("stands") = py::none(),
      py::arg("max_tilt") = StandTiltRequest{}.max_tilt,
      py::arg("tilt_grid") = StandTiltRequest{}.tilt_grid,
      "`dynid excite`: a periodic Fourier motion within the limits that excites the base "
      "parameters (criterion 'cond', 'cond-unscaled', 'd-optimal', 'gc' or 'relative-sd'). "
      "stands=K (excite --stands, with robot_spec the robot's URDF): K orientations of a stand "
      "with a force-torque sensor under the base for the design (roll and pitch within "
      "max_tilt, tilt_grid candidates a side), in stand_tilts and to_json()'s stand. "
      "progress(info) is called as each start ends with a dict whose 'line' is the CLI's (the "
      "start, its criterion, the share done and the time left); returning False stops the "
      "design with the best start so far.");
}

}  // namespace

void bindExcitation(py::module_& m) { bindExcite(m); }

}  // namespace dynid::python
