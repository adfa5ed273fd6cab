// excite_standing (`dynid excite --floating-base --stance`): a standing robot's sway designed for
// identification (analysis/floating/standing_design.hpp), its document as a dict and, with
// `out`, written as standing_excitation.json for simulate_floating(trajectory=...).
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/standing_design.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "python/run_support.hpp"
#include "reports/standing_design_report.hpp"

namespace dynid::python {

namespace {

py::dict exciteStanding(const PathLike& robot, const std::vector<std::string>& contacts,
                        const std::vector<double>& stance, const OptionalPathLike& out,
                        const std::optional<std::string>& sensors, double period, int harmonics,
                        double max_sway, double max_turn, double max_swing, double joint_margin,
                        double friction_cone, const SoleLike& sole, int starts, int evaluations,
                        double grid_rate, double check_rate,
                        const std::optional<double>& budget_seconds, std::uint64_t seed,
                        const TermsLike& drive_terms, const ProgressLike& progress) {
  const FloatingModel model = floatingRobot(robot, drive_terms);
  StandingDesignRequest request;
  request.contacts = contactsOf(model, contacts);
  request.stance =
      Eigen::Map<const Eigen::VectorXd>(stance.data(), static_cast<Eigen::Index>(stance.size()));
  if (sensors) request.set = parseSensorSet(*sensors);
  request.period = period;
  request.harmonics = harmonics;
  request.max_sway = max_sway;
  request.max_turn = max_turn;
  request.max_swing = max_swing;
  request.joint_margin = joint_margin;
  request.friction_cone = friction_cone;
  if (!sole.is_none()) request.sole = soleOf(sole);
  request.starts = starts;
  request.evaluations = evaluations;
  request.grid_rate = grid_rate;
  request.check_rate = check_rate;
  if (budget_seconds) request.max_seconds = *budget_seconds;
  request.seed = seed;
  request.structural.seed = seed;
  const std::string path = out.is_none() ? std::string() : pathArg(out, "out");
  // Ctrl-C (KeyboardInterrupt) stops the starts at their next evaluation, keeping the best so far.
  Interrupt interrupt;
  interrupt.connect(request.control, progress);
  const PythonRun call("excite_standing", {pathArg(robot, "robot")}, seed);
  StandingDesign design;
  {
    py::gil_scoped_release release;
    design = designStandingSway(model, request);
  }
  interrupt.raiseIfFailed();
  interrupt.warnIfStopped();
  design.baseline_problem = pythonText(design.baseline_problem);
  const nlohmann::json document = withCall(
      standingDesignJson(request, design, {pathArg(robot, "robot"), contacts}), call.finish());
  if (!path.empty()) writeFileAtomically(path, jsonText(document, 2) + "\n");
  return parsedJson(document).cast<py::dict>();
}

}  // namespace

void bindStanding(py::module_& m) {
  const StandingDesignRequest d;
  m.def(
      "excite_standing", &exciteStanding, py::arg("robot"), py::arg("contacts"), py::arg("stance"),
      py::arg("out") = py::none(), py::arg("sensors") = py::none(), py::arg("period") = d.period,
      py::arg("harmonics") = d.harmonics, py::arg("max_sway") = d.max_sway,
      py::arg("max_turn") = d.max_turn, py::arg("max_swing") = d.max_swing,
      py::arg("joint_margin") = d.joint_margin, py::arg("friction_cone") = d.friction_cone,
      py::arg("sole") = py::none(), py::arg("starts") = d.starts,
      py::arg("evaluations") = d.evaluations, py::arg("grid_rate") = d.grid_rate,
      py::arg("check_rate") = d.check_rate, py::arg("budget_seconds") = py::none(),
      py::arg("seed") = 1, py::arg("drive_terms") = py::none(), py::arg("progress") = py::none(),
      "`dynid excite --floating-base --stance`: a standing robot's sway designed for "
      "identification (docs/FLOATING.md): a floating-base robot (a URDF path), its feet "
      "(contacts: link names, each optionally ':point' or ':frame') and its joints at rest "
      "(stance [rad]); the base's six coordinates (x, y, z, roll, pitch, yaw) as Fourier series "
      "over `period` [s] from rest at the stance, chosen (COBYLA, `starts` seeded starts) to "
      "lower the condition number of one sensor set's base regressor (sensors: wrenches, "
      "torques_wrenches or torques_contacts, the default), within max_sway [m], max_turn "
      "[rad], the joints no foot depends on (a humanoid's arms) moved too within max_swing [rad] "
      "of the stance, joint_margin [rad] from the joints' limits, their velocity limits and, with "
      "friction_cone (mu), forces the feet carry within their cones, and with sole ((length, "
      "width) [m] or corners [(x, y), ...], as simulate_floating's) every frame contact's "
      "centre of pressure within its sole. Returns "
      "standing_excitation.json as a dict (every set's determined count and condition number "
      "beside the default sway's), written to `out` when given: simulate_floating(robot, "
      "DATA, trajectory=out) simulates along it. Ctrl-C stops it with its best sway so far "
      "(a UserWarning).");
}

}  // namespace dynid::python
