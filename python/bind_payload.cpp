// The payload wing: dynid payload (analysis/payload/payload.hpp) and its document as to_json().
#include <cmath>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/payload/attach.hpp"
#include "analysis/payload/body.hpp"
#include "analysis/payload/payload.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/payload_record.hpp"
#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "python/run_support.hpp"
#include "reports/payload_report.hpp"

namespace dynid::python {
namespace {

Eigen::Vector3d threeArg(const py::handle& value, const char* name) {
  return vectorArg(value, name, 3);
}

/// `tool_xyz` and `tool_rpy` as a pose in the link's frame (identity for None).
Pose<double> attachmentFrame(const OptionalArrayLike& tool_xyz, const OptionalArrayLike& tool_rpy) {
  Pose<double> frame = Pose<double>::Identity();
  if (!tool_xyz.is_none()) frame.translation = threeArg(tool_xyz, "tool_xyz");
  if (!tool_rpy.is_none()) {
    const Eigen::Vector3d rpy = threeArg(tool_rpy, "tool_rpy");
    frame.rotation = rotationFromRpy(rpy.x(), rpy.y(), rpy.z());
  }
  return frame;
}

/// A body's 10 standard parameters: a payload.json / payload.body.json path, or the values.
Vector10d bodyArg(const PriorLike& value, const char* name) {
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__")) {
    const std::string file = pathArg(value, name);
    return payloadBodyFrom(parseJson(readFile(file), file), file);
  }
  return vectorArg(value, name, 10);
}

/// What payload() returns: the outcome and the call that made it.
struct PayloadResult : PayloadOutcome {
  RunProvenance provenance;
};

PayloadResult payload(const Model& model, const DataLike& data, const OptionalDataLike& unloaded,
                      const std::string& link, const OptionalArrayLike& tool_xyz,
                      const OptionalArrayLike& tool_rpy, const PriorLike& prior,
                      double prior_weight, bool refit_friction, const OptionalFloat& payload_mass,
                      const OptionalArrayLike& payload_com, double max_motion_difference) {
  PayloadRequest request;
  request.arm = model;
  request.arm_source = model.name;
  request.arm_model = {model.name, "", ""};  // a model in memory: its name, no file
  const DataArg loaded = dataArg(data, "data", model);
  request.data_file = loaded.path;
  request.data = loaded.arrays;
  if (!unloaded.is_none()) {
    const DataArg u = dataArg(unloaded, "unloaded", model);
    request.unloaded_file = u.path;
    request.unloaded = u.arrays;
  }
  request.link = link;
  request.tool = attachmentFrame(tool_xyz, tool_rpy);
  if (!prior.is_none()) request.prior = bodyArg(prior, "prior");
  request.prior_weight = prior_weight;
  request.refit_friction = refit_friction;
  if (!payload_mass.is_none()) request.known_mass = payload_mass.cast<double>();
  if (!payload_com.is_none()) request.known_com = threeArg(payload_com, "payload_com");
  request.max_motion_difference = max_motion_difference;
  const PythonRun call(
      "payload",
      {request.data_file, request.unloaded_file,
       py::isinstance<py::str>(prior) || py::hasattr(prior, "__fspath__") ? pathArg(prior, "prior")
                                                                          : ""});
  py::gil_scoped_release release;  // the Datasets are kept alive by the caller's references
  PayloadResult out{payloadRun(request), {}};
  out.provenance = call.finish();
  pythonTexts(out.warnings);  // the fields they name, as keyword arguments
  pythonTexts(out.advice);
  return out;
}

/// dynid.Payload: what payload() returns.
void bindPayloadClass(py::module_& m) {
  py::class_<PayloadResult>(m, "Payload",
                            "What dynid payload finds: the payload in the attachment frame.")
      .def_readonly("mode", &PayloadOutcome::mode, "'single' (one log) or 'difference'")
      .def_readonly("link", &PayloadOutcome::link_name, "the link it is attached to")
      .def_readonly("mass", &PayloadOutcome::mass, "[kg]")
      .def_property_readonly(
          "com", [](const PayloadResult& o) { return toNumpy(Eigen::VectorXd(o.com)); },
          "centre of mass in the attachment frame, (3,) [m]")
      .def_property_readonly(
          "inertia_com",
          [](const PayloadResult& o) { return toNumpy(Eigen::MatrixXd(o.inertia_com)); },
          "inertia about the centre of mass, attachment axes, (3, 3) [kg m^2]")
      .def_property_readonly(
          "principal_moments",
          [](const PayloadResult& o) { return toNumpy(Eigen::VectorXd(o.principal_moments)); },
          "(3,) [kg m^2], about principal_axes' columns")
      .def_property_readonly(
          "principal_axes",
          [](const PayloadResult& o) { return toNumpy(Eigen::MatrixXd(o.principal_axes)); },
          "(3, 3) rotation whose columns are the principal axes")
      .def_property_readonly(
          "standard", [](const PayloadResult& o) { return toNumpy(Eigen::VectorXd(o.standard)); },
          "the 10 standard parameters m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz (consistent)")
      .def_property_readonly(
          "covariance",
          [](const PayloadResult& o) { return toNumpy(Eigen::MatrixXd(o.covariance)); },
          "(10, 10) of the least-squares standard parameters (inf: not seen)")
      .def_property_readonly(
          "quantities",
          [](const PayloadResult& o) {
            py::list out;
            for (const PayloadQuantity& q : o.quantities) {
              py::dict d;
              d["name"] = q.name;
              d["group"] = q.group;
              d["unit"] = q.unit;
              d["value"] = q.determined ? py::object(py::float_(q.value)) : py::object(py::none());
              d["estimate"] = q.value;
              d["std_dev"] = q.std_dev;
              d["half_width_95"] = q.half_width;
              d["determined"] = q.determined;
              out.append(d);
            }
            return out;
          },
          "every quantity with its 95 % interval and whether the log determines it: `value` is "
          "None when it does not (its resolution is half_width_95; `estimate` keeps the number)")
      .def_readonly("unseen", &PayloadOutcome::unseen,
                    "combinations the motion does not excite at all")
      .def_readonly("combined", &PayloadOutcome::combined,
                    "combinations determined where their parts are not")
      .def_readonly("smallest_mass", &PayloadOutcome::smallest_mass,
                    "the smallest mass this log resolves to +-20 % (95 %) [kg]")
      .def_readonly("advice", &PayloadOutcome::advice,
                    "What to do about quantities the log does not determine (may be empty).")
      .def_readonly("warnings", &PayloadOutcome::warnings,
                    "Warnings about the log or the fit (may be empty).")
      .def_property_readonly(
          "gains",
          [](const PayloadResult& o) -> std::optional<py::dict> {
            if (!o.gains) return std::nullopt;
            py::dict d;
            d["scale"] = toNumpy(o.gains->scale);
            d["scale_std"] = toNumpy(o.gains->scale_std);
            py::list determined;
            for (char c : o.gains->determined) determined.append(c != 0);
            d["determined"] = determined;
            d["torque_constants"] = o.gains->torque_constants;
            return d;
          },
          "With payload_mass, per joint true / measured torque as a dict (scale, scale_std, "
          "determined, torque_constants; multiply the torque constants by scale), else None.")
      .def(
          "to_json",
          [](const PayloadResult& o) {
            return jsonText(withCall(payloadJson(o), o.provenance), 2) + "\n";
          },
          "payload.json, as `dynid payload` writes it.")
      .def(
          "vendor",
          [](const PayloadResult& o, const std::string& format) {
            return payloadVendorFile(o, format).second;
          },
          py::arg("format"),
          "The payload in a controller's convention: 'ur', 'franka', 'kuka', 'abb' or 'json' "
          "(docs/PAYLOAD.md).");
}

void bindPayloadRun(py::module_& m) {
  m.def("payload", &payload, py::arg("model"), py::arg("data"), py::arg("unloaded") = py::none(),
        py::arg("link") = "", py::arg("tool_xyz") = py::none(), py::arg("tool_rpy") = py::none(),
        py::arg("prior") = py::none(), py::arg("prior_weight") = PayloadRequest{}.prior_weight,
        py::arg("refit_friction") = false, py::arg("payload_mass") = py::none(),
        py::arg("payload_com") = py::none(),
        py::arg("max_motion_difference") = PayloadRequest{}.max_motion_difference,
        "What was added at `link` (default: the last) of the identified arm `model`, from `data` "
        "(a path or Dataset with the payload attached) and optionally `unloaded` (the same "
        "motion without it: the torque difference is used). `tool_xyz`/`tool_rpy`: the "
        "attachment frame in the link's frame. `prior`: a payload.json / payload.body.json path "
        "or 10 standard parameters. With `payload_mass` (and `unloaded`): the drives' torque "
        "constant scale factors (`gains`). As `dynid payload`.");
}

Model attach(const Model& model, const OptionalFloat& mass, const OptionalArrayLike& com,
             const OptionalArrayLike& inertia, const PriorLike& body, const std::string& link,
             const OptionalArrayLike& tool_xyz, const OptionalArrayLike& tool_rpy) {
  const bool given = !mass.is_none() || !com.is_none() || !inertia.is_none();
  if (given == !body.is_none())
    throw py::value_error("give the body as mass (with com, inertia) or as body, one of them");
  Vector10d standard;
  if (!body.is_none()) {
    standard = bodyArg(body, "body");
  } else {
    if (mass.is_none()) throw py::value_error("com and inertia need mass");
    const Eigen::Vector3d c = com.is_none() ? Eigen::Vector3d::Zero() : threeArg(com, "com");
    Eigen::Matrix3d i = Eigen::Matrix3d::Zero();
    if (!inertia.is_none()) {
      const Eigen::VectorXd v = vectorArg(inertia, "inertia", 6);
      i << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
    }
    standard = bodyFromCentre(mass.cast<double>(), c, i);
  }
  return attachBody(model, linkIndex(model, link), attachmentFrame(tool_xyz, tool_rpy), standard);
}

}  // namespace

void bindPayload(py::module_& m) {
  bindPayloadClass(m);
  bindPayloadRun(m);
  m.def("attach", &attach, py::arg("model"), py::arg("mass") = py::none(),
        py::arg("com") = py::none(), py::arg("inertia") = py::none(), py::arg("body") = py::none(),
        py::arg("link") = "", py::arg("tool_xyz") = py::none(), py::arg("tool_rpy") = py::none(),
        "`model` with a known body fixed to `link` (default: the last): `mass` [kg], `com` (3) "
        "and `inertia` (Ixx, Ixy, Ixz, Iyy, Iyz, Izz about the centre of mass) in the frame "
        "`tool_xyz`/`tool_rpy` of the link, or `body`: a payload.json / payload.body.json path "
        "or 10 standard parameters. As `dynid model attach`.");
}

}  // namespace dynid::python
