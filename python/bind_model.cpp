// Models (load_model, Model) and datasets (Dataset, read_dataset, write_dataset), and the array
// helpers of common.hpp.
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include <pybind11/stl.h>

#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "core/parallel.hpp"
#include "core/parameters.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/robots.hpp"
#include "data/urdf.hpp"
#include "python/common.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"

namespace dynid::python {

// ---- array helpers ----

std::string shapeText(const py::array& a) {
  std::string out = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) out += (d ? ", " : "") + std::to_string(a.shape(d));
  return out + (a.ndim() == 1 ? ",)" : ")");
}

DoubleArray realArray(const py::handle& value, const char* name, std::vector<int> ndims) {
  if (value.is_none()) throw py::type_error(std::string(name) + ": expected an array, got None");
  py::array any = py::array::ensure(value);
  if (!any) throw py::type_error(std::string(name) + ": expected an array of numbers");
  const char kind = any.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected real numbers, got dtype " +
                         std::string(py::str(any.dtype())));
  bool ndim_ok = false;
  std::string expected;
  for (int d : ndims) {
    ndim_ok = ndim_ok || any.ndim() == d;
    expected += (expected.empty() ? "" : " or ") + std::to_string(d);
  }
  if (!ndim_ok)
    throw py::value_error(std::string(name) + ": expected " + expected + " dimensions, got shape " +
                          shapeText(any));
  return DoubleArray::ensure(any);  // float64, C order: a copy only when the input is not
}

Eigen::VectorXd vectorArg(const py::handle& value, const char* name, Eigen::Index n) {
  const DoubleArray a = realArray(value, name, {1});
  if (a.shape(0) != n)
    throw py::value_error(std::string(name) + ": expected shape (" + std::to_string(n) +
                          ",), got " + shapeText(a));
  return Eigen::Map<const Eigen::VectorXd>(a.data(), n);
}

py::array_t<double> toNumpy(const Eigen::VectorXd& v) {
  py::array_t<double> out(v.size());
  std::copy(v.data(), v.data() + v.size(), out.mutable_data());
  return out;
}

py::array_t<double> toNumpy(const Eigen::MatrixXd& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  Eigen::Map<RowMatrix>(out.mutable_data(), m.rows(), m.cols()) = m;
  return out;
}

std::string pathArg(const py::handle& value, const char* name) {
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__"))
    return py::str(py::module_::import("os").attr("fspath")(value));
  throw py::type_error(std::string(name) + ": expected a path (str or os.PathLike)");
}

DriveTerms driveTermsArg(const py::handle& value, const char* name) {
  if (py::isinstance<py::str>(value)) return parseDriveTerms(value.cast<std::string>());
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::string joined;
    for (const py::handle& item : value) {
      if (!py::isinstance<py::str>(item))
        throw py::type_error(std::string(name) + ": expected names such as 'fv', not " +
                             std::string(py::repr(item)));
      if (!joined.empty()) joined += ',';
      joined += item.cast<std::string>();
    }
    return parseDriveTerms(joined.empty() ? "none" : joined);
  }
  throw py::type_error(std::string(name) +
                       ": expected 'fv,fc,fo' or a list of names such as ['fv', 'fc', 'fo']");
}

void checkThreads(int threads) { checkOption("", "threads", threads, "threads"); }

TorqueFilterChoice torqueFilterArg(const py::handle& given) {
  if (py::isinstance<py::str>(given)) {
    const std::string text = given.cast<std::string>();
    if (text == "auto") return std::nullopt;
    if (text == "none") return TorqueFilter{};
  } else if (!py::isinstance<py::bool_>(given)) {
    double cutoff = -1.0, order = 4.0;
    if (py::isinstance<py::tuple>(given) && py::len(given) == 2) {
      const py::tuple pair = py::reinterpret_borrow<py::tuple>(given);
      if (!py::isinstance<py::bool_>(pair[0]) && !py::isinstance<py::bool_>(pair[1]) &&
          (py::isinstance<py::float_>(pair[0]) || py::isinstance<py::int_>(pair[0])) &&
          py::isinstance<py::int_>(pair[1])) {
        cutoff = pair[0].cast<double>();
        order = pair[1].cast<double>();
      }
    } else if (py::isinstance<py::float_>(given) || py::isinstance<py::int_>(given)) {
      cutoff = given.cast<double>();
    }
    if (cutoff > 0.0 && std::isfinite(cutoff) && order >= 1.0 && order <= 12.0)
      return TorqueFilter{static_cast<int>(order), cutoff, 0.0};
  }
  throw py::value_error(
      "torque_filter: 'auto', 'none', a cutoff > 0 [Hz] or (cutoff, order) with an order of 1 to "
      "12");
}

DataArg dataArg(const py::handle& value, const char* name, const Model& model) {
  DataArg out;
  if (py::isinstance<Trajectory>(value)) {
    out.arrays = &value.cast<const Trajectory&>();
    out.path = "<arrays>";
    if (out.arrays->numJoints() != model.numJoints())
      throw py::value_error(std::string(name) + ": the dataset has " +
                            std::to_string(out.arrays->numJoints()) + " joints, robot '" +
                            model.name + "' has " + std::to_string(model.numJoints()));
    return out;
  }
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__")) {
    out.path = pathArg(value, name);
    return out;
  }
  throw py::type_error(std::string(name) +
                       ": expected a dataset path (str or os.PathLike) or a dynid.Dataset");
}

namespace {

// ---- models ----

int parameterIndex(const Model& model, const std::string& name) {
  const std::vector<std::string> names = standardParameterNames(model.parameterLayout());
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  throw InputError("robot '" + model.name + "' has no parameter '" + name +
                   "' (its names: " + names.front() + " ... " + names.back() + ")");
}

void checkParameterValue(const std::string& name, double value) {
  if (!std::isfinite(value) || std::abs(value) > kMaxParameterMagnitude)
    throw InputError("parameter " + name + " = " + formatNumber(value) +
                     ": expected a finite number of magnitude at most 1e6");
}

void setParameters(Model& model, const py::handle& value) {
  const std::vector<std::string> names = standardParameterNames(model.parameterLayout());
  const Eigen::VectorXd theta =
      vectorArg(value, "parameters", static_cast<Eigen::Index>(names.size()));
  for (Eigen::Index i = 0; i < theta.size(); ++i) checkParameterValue(names[i], theta[i]);
  model.setStandardParameters(theta);
}

Eigen::VectorXd limitsOf(const Model& model, double JointLimits::*field) {
  Eigen::VectorXd out(model.numJoints());
  for (int i = 0; i < model.numJoints(); ++i) out[i] = model.limits[i].*field;
  return out;
}

py::list violationsList(const Model& model) {
  py::list out;
  for (const ConsistencyViolation& v : consistencyViolations(model)) {
    py::dict d;
    d["link"] = v.link;
    d["link_name"] = v.link_name;
    d["condition"] = v.condition;
    d["detail"] = v.detail;
    out.append(d);
  }
  return out;
}

Model loadModel(const PathLike& spec_arg, bool drives, const TermsLike& terms, bool strict,
                const std::vector<std::string>& fix_joints) {
  const std::string spec = pathArg(spec_arg, "spec");  // a built-in name, or a path
  RobotOptions options;
  options.drives = drives;
  options.strict = strict;
  options.fixed_joints = fix_joints;
  if (!terms.is_none()) options.drive_terms = driveTermsArg(terms, "drive_terms");
  std::vector<std::string> warnings;
  Model model;
  {
    py::gil_scoped_release release;  // a large URDF takes a while
    model = loadRobot(spec, options, &warnings);
  }
  for (const std::string& w : warnings)
    PyErr_WarnEx(PyExc_UserWarning, pythonText(spec + ": " + w).c_str(), 1);
  return model;
}

/// modelDocument(model, format), with what the format cannot carry (Ia in a URDF, say) as
/// UserWarnings, as `dynid model export` prints them as notes.
std::string exportedModel(const Model& model, const std::string& format) {
  for (const std::string& note : modelExportNotes(model, format))
    if (PyErr_WarnEx(PyExc_UserWarning, pythonText(note).c_str(), 1) < 0)
      throw py::error_already_set();  // warnings as errors
  return modelDocument(model, format);
}

// ---- datasets ----

/// Checks a dataset built from arrays as readDatasetCsv checks a file: finite values, strictly
/// increasing time, at least one sample; names the row (0-based) and the column.
void checkDataset(const Trajectory& t) {
  if (t.numSamples() == 0) throw InputError("the dataset has no samples");
  for (int k = 0; k < t.numSamples(); ++k) {
    if (!std::isfinite(t.time[k]))
      throw InputError("row " + std::to_string(k) + ": t is not finite");
    if (k > 0 && !(t.time[k] > t.time[k - 1]))
      throw InputError("row " + std::to_string(k) + ": t = " + formatNumber(t.time[k]) +
                       " is not after the previous row's " + formatNumber(t.time[k - 1]));
    const char* names[] = {"q", "dq", "ddq", "tau"};
    const Eigen::MatrixXd* ms[] = {&t.q, &t.dq, &t.ddq, &t.tau};
    for (int c = 0; c < 4; ++c)
      for (int j = 0; j < t.numJoints(); ++j)
        if (!std::isfinite((*ms[c])(j, k)))
          throw InputError("row " + std::to_string(k) + ": " + names[c] + std::to_string(j + 1) +
                           " is not finite");
  }
}

Trajectory makeDataset(const ArrayLike& time, const ArrayLike& q, const ArrayLike& dq,
                       const OptionalArrayLike& ddq, const OptionalArrayLike& tau) {
  const DoubleArray t = realArray(time, "time", {1});
  const py::ssize_t count = t.shape(0);
  const DoubleArray qa = realArray(q, "q", {2});
  const py::ssize_t n = qa.shape(1);
  if (count > std::numeric_limits<int>::max() / 2)
    throw py::value_error("time: more samples than dynid holds in memory (2^30)");
  Trajectory out;
  out.resize(static_cast<int>(n), static_cast<int>(count));
  out.time = Eigen::Map<const Eigen::VectorXd>(t.data(), count);
  const char* names[] = {"q", "dq", "ddq", "tau"};
  const py::handle values[] = {q, dq, ddq, tau};
  Eigen::MatrixXd* targets[] = {&out.q, &out.dq, &out.ddq, &out.tau};
  for (int c = 0; c < 4; ++c) {
    if (values[c].is_none()) continue;  // zeros
    const DoubleArray a = realArray(values[c], names[c], {2});
    if (a.shape(0) != count || a.shape(1) != n)
      throw py::value_error(std::string(names[c]) + ": expected shape (" + std::to_string(count) +
                            ", " + std::to_string(n) + ") like time and q, got " + shapeText(a));
    *targets[c] = Eigen::Map<const RowMatrix>(a.data(), count, n).transpose();
  }
  checkDataset(out);
  return out;
}

py::array_t<double> samplesOf(const Eigen::MatrixXd& m) {
  return toNumpy(Eigen::MatrixXd(m.transpose()));
}

/// Model's parameters by name: one, set one, all as a dict.
void bindModelParameters(py::class_<Model>& model) {
  model
      .def(
          "parameter",
          [](const Model& self, const std::string& name) {
            return self.standardParameters()[parameterIndex(self, name)];
          },
          py::arg("name"), "One standard parameter by name, e.g. model.parameter('m3').")
      .def(
          "set_parameter",
          [](Model& self, const std::string& name, double value) {
            const int i = parameterIndex(self, name);
            checkParameterValue(name, value);
            Eigen::VectorXd theta = self.standardParameters();
            theta[i] = value;
            self.setStandardParameters(theta);
          },
          py::arg("name"), py::arg("value"))
      .def(
          "parameters_dict",
          [](const Model& self) {
            py::dict out;
            const Eigen::VectorXd theta = self.standardParameters();
            const std::vector<std::string> names = standardParameterNames(self.parameterLayout());
            for (std::size_t i = 0; i < names.size(); ++i) out[py::str(names[i])] = theta[i];
            return out;
          },
          "{name: value} of the standard parameters, in order.");
}

/// Model's gravity and joint limits.
void bindModelLimits(py::class_<Model>& model) {
  model
      .def_property(
          "gravity", [](const Model& self) { return toNumpy(Eigen::VectorXd(self.gravity())); },
          [](Model& self, const ArrayLike& value) {
            self.setGravity(vectorArg(value, "gravity", 3));
          },
          "Gravity in the base frame, shape (3,) [m/s^2].")
      .def_property_readonly(
          "lower_limits", [](const Model& s) { return toNumpy(limitsOf(s, &JointLimits::lower)); },
          "Each joint's lower position limit, shape (n,) [rad].")
      .def_property_readonly(
          "upper_limits", [](const Model& s) { return toNumpy(limitsOf(s, &JointLimits::upper)); },
          "Each joint's upper position limit, shape (n,) [rad].")
      .def_property_readonly(
          "velocity_limits",
          [](const Model& s) { return toNumpy(limitsOf(s, &JointLimits::velocity)); },
          "Each joint's velocity limit, shape (n,) [rad/s].")
      .def_property_readonly(
          "effort_limits",
          [](const Model& s) { return toNumpy(limitsOf(s, &JointLimits::effort)); },
          "Each joint's torque limit, shape (n,) [N m].");
}

/// Model's consistency check, its documents (JSON, URDF, MJCF, show) and copies.
void bindModelOutput(py::class_<Model>& model) {
  model
      .def("check", &violationsList,
           "Physical-consistency violations of the links' parameters, as dicts {link, link_name, "
           "condition, detail}; empty when every link is realisable (as `dynid model check`).")
      .def("to_json", &modelToJson, "The model as dynid JSON (loadable by load_model).")
      // Pickled as its dynid JSON (what a Dask task, a multiprocessing pool or a file takes).
      .def(py::pickle([](const Model& self) { return modelToJson(self); },
                      [](const std::string& text) { return modelFromJson(text, "<pickle>"); }))
      .def("to_urdf", [](const Model& self) { return exportedModel(self, "urdf"); })
      .def("to_mjcf", [](const Model& self) { return exportedModel(self, "mjcf"); })
      .def(
          "export",
          [](const Model& self, const PathLike& path, const std::string& format) {
            writeOutput(pathArg(path, "path"), exportedModel(self, format));
          },
          py::arg("path"), py::arg("format"),
          "Writes the model as 'urdf', 'json' or 'mjcf' (atomically, as `dynid model export`).")
      .def("show", &modelShowText, "The text of `dynid model show`.")
      .def("copy", [](const Model& self) { return Model(self); })
      .def("__copy__", [](const Model& self) { return Model(self); })
      .def("__deepcopy__", [](const Model& self, py::dict) { return Model(self); })
      .def("__repr__", [](const Model& self) {
        return "<dynid.Model '" + self.name + "': " + std::to_string(self.numJoints()) +
               " joints, " + std::to_string(self.parameterLayout().size()) +
               " parameters, drives " + driveTermsText(self.driveTerms()) + ">";
      });
}

void bindModelClass(py::module_& m) {
  py::class_<Model> model(m, "Model",
                          "A robot: kinematic tree, inertial and drive parameters. Copies are "
                          "independent (Model.copy()); load one with dynid.load_model().");
  model
      .def_readwrite("name", &Model::name,
                     "The robot's name (the URDF's robot name, or the built-in's).")
      .def_property_readonly("num_joints", &Model::numJoints, "The number of moving joints n.")
      .def_property_readonly(
          "num_parameters", [](const Model& self) { return self.parameterLayout().size(); },
          "The length of the standard parameter vector (10 per link, then the enabled drive terms "
          "per joint).")
      .def_readonly("link_names", &Model::link_names, "The moving links' names, in joint order.")
      .def_readonly("joint_names", &Model::joint_names, "The moving joints' names, in order.")
      .def_property_readonly(
          "parameter_names",
          [](const Model& self) { return standardParameterNames(self.parameterLayout()); },
          "Names of the standard parameters (m1, mx1, ..., Izz1, then Ia1, Fv1, ... with drives).")
      .def_property_readonly(
          "paper_parameter_names",
          [](const Model& self) { return paperParameterNames(self.numJoints()); },
          "Names of the paper's 7 per link (m1, cx1, cy1, cz1, Ixx1, Iyy1, Izz1, ...).")
      .def_property_readonly(
          "drive_terms", [](const Model& self) { return driveTermsKeys(self.driveTerms()); },
          "The drive terms every joint carries, e.g. ['ia', 'fv', 'fc'] (set by load_model).")
      .def_property(
          "parameters", [](const Model& self) { return toNumpy(self.standardParameters()); },
          [](Model& self, const ArrayLike& value) { setParameters(self, value); },
          "The standard parameter vector, shape (num_parameters,) [kg, kg m, kg m^2, drive "
          "units]. Assigning checks the size and that every value is finite (|x| <= 1e6).");
  bindModelParameters(model);
  bindModelLimits(model);
  bindModelOutput(model);
}

void bindLoadingAndDatasets(py::module_& m) {
  m.def("load_model", &loadModel, py::arg("spec"), py::arg("drives") = false,
        py::arg("drive_terms") = py::none(), py::arg("strict") = false,
        py::arg("fix_joints") = std::vector<std::string>{},
        "Loads a robot as `--robot` does: 'puma560', 'puma560-consistent', 'panda', a .urdf or a "
        "dynid .json path (str or os.PathLike). drives=True adds the robot's own drive terms; "
        "drive_terms='fv,fc,fo' (or ['fv', 'fc', 'fo']) exactly those. URDF warnings become "
        "UserWarnings (errors with strict=True). fix_joints: a URDF's moving joints (a "
        "gripper's fingers) treated as fixed at zero, as `dynid model --fix-joints`.");

  py::class_<Trajectory>(m, "Dataset",
                         "Samples of a joint trajectory: time (N,) [s] strictly increasing; q, "
                         "dq, ddq, tau (N, n) [rad, rad/s, rad/s^2, N m]. A missing ddq or tau "
                         "is zeros.")
      .def(py::init(&makeDataset), py::arg("time"), py::arg("q"), py::arg("dq"),
           py::arg("ddq") = py::none(), py::arg("tau") = py::none())
      .def_property_readonly("num_samples", &Trajectory::numSamples, "The number of samples N.")
      .def_property_readonly("num_joints", &Trajectory::numJoints, "The number of joints n.")
      .def_property_readonly(
          "time", [](const Trajectory& t) { return toNumpy(t.time); },
          "Sample times, shape (N,) [s].")
      .def_property_readonly(
          "q", [](const Trajectory& t) { return samplesOf(t.q); },
          "Joint positions, shape (N, n) [rad].")
      .def_property_readonly(
          "dq", [](const Trajectory& t) { return samplesOf(t.dq); },
          "Joint velocities, shape (N, n) [rad/s].")
      .def_property_readonly(
          "ddq", [](const Trajectory& t) { return samplesOf(t.ddq); },
          "Joint accelerations, shape (N, n) [rad/s^2].")
      .def_property_readonly(
          "tau", [](const Trajectory& t) { return samplesOf(t.tau); },
          "Joint torques, shape (N, n) [N m].")
      .def("__len__", &Trajectory::numSamples)
      .def("__repr__", [](const Trajectory& t) {
        return "<dynid.Dataset: " + std::to_string(t.numSamples()) + " samples, " +
               std::to_string(t.numJoints()) + " joints>";
      });

  m.def(
      "read_dataset",
      [](const PathLike& path, int joints) {
        const std::string file = pathArg(path, "path");
        py::gil_scoped_release release;
        return readDatasetCsv(file, joints);
      },
      py::arg("path"), py::arg("joints") = -1,
      "Reads a dynid CSV (t, q1.., dq1.., ddq1.., tau1..) into a Dataset; joints=n insists on n. "
      "Raises ParseError naming the line and column at fault.");
  m.def(
      "write_dataset",
      [](const PathLike& path, const Trajectory& data) {
        const std::string file = pathArg(path, "path");
        py::gil_scoped_release release;
        writeDatasetCsv(file, data);
      },
      py::arg("path"), py::arg("data"),
      "Writes a Dataset as a dynid CSV, atomically, in shortest round-trip form (read_dataset "
      "gives back the same doubles).");
}

}  // namespace

void bindModel(py::module_& m) {
  bindModelClass(m);
  bindLoadingAndDatasets(m);
}

}  // namespace dynid::python
