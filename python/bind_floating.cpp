// The floating wing: what each sensor set of a floating-base robot determines
// (analysis/floating/identifiability.hpp, `dynid identifiability --floating-base`), its document
// as a dict.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "analysis/floating/identifiability.hpp"
#include "data/robots.hpp"
#include "python/run_support.hpp"
#include "reports/floating_report.hpp"

namespace dynid::python {
namespace {

py::object floatingIdentifiability(const PathLike& robot,
                                   const std::optional<std::vector<std::string>>& contacts,
                                   const std::optional<std::vector<std::string>>& sensors,
                                   const std::optional<std::string>& motion,
                                   const TermsLike& drive_terms, int samples, std::uint64_t seed) {
  FloatingIdentifiabilityRequest request;
  request.contacts = contacts.value_or(std::vector<std::string>{});
  for (const std::string& name : sensors.value_or(std::vector<std::string>{}))
    request.sensors.push_back(parseSensorSet(name));
  request.motion = motion                     ? parseFloatingMotion(*motion)
                   : request.contacts.empty() ? FloatingMotion::kFree
                                              : FloatingMotion::kHolding;
  request.structural.samples = samples;
  request.structural.seed = seed;
  RobotOptions options;
  if (!drive_terms.is_none()) options.drive_terms = driveTermsArg(drive_terms, "drive_terms");
  const FloatingModel model = loadFloatingRobot(pathArg(robot, "robot"), options);
  FloatingIdentifiabilityOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = floatingIdentifiabilityRun(model, request);
  }
  return parsedJson(floatingIdentifiabilityJson(model, outcome));
}

}  // namespace

void bindFloating(py::module_& m) {
  m.def("floating_identifiability", &floatingIdentifiability, py::arg("robot"),
        py::arg("contacts") = py::none(), py::arg("sensors") = py::none(),
        py::arg("motion") = py::none(), py::arg("drive_terms") = py::none(), py::arg("samples") = 0,
        py::arg("seed") = 1,
        "`dynid identifiability --floating-base`: a floating-base robot (a URDF path) and its "
        "contacts (link names, each optionally ':point' or ':frame'); what each sensor set "
        "(wrenches, torques_wrenches, torques_contacts; default all) determines in the motion "
        "(holding, the default with contacts; free, without; suspended). Returns "
        "floating_identifiability.json as a dict (docs/FLOATING.md).");
}

}  // namespace dynid::python
