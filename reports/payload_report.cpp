#include "reports/payload_report.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analysis/estimation/streaming.hpp"
#include "analysis/payload/body.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/document.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"
#include "reports/plots.hpp"
#include "reports/prediction_report.hpp"

namespace dynid {

using nlohmann::json;

namespace {

constexpr double kDegrees = 180.0 / M_PI;

/// A name from a file (robot, link) as it may appear in a controller's comment: letters, digits,
/// '_', '-' and '.', anything else as '_' (no input reaches a controller program as code).
std::string commentSafe(const std::string& text) {
  std::string out;
  for (char c : text)
    out +=
        (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.') ? c : '_';
  return out.substr(0, 80);
}

/// A number as a controller takes it: 7 significant digits (their fields are single precision).
/// Below 1e-12 (in kg, m, mm, degrees or kg m^2) a value is round-off: written as 0 (never -0).
std::string vendorNumber(double v) { return formatNumber(std::abs(v) < 1e-12 ? 0.0 : v, 7); }
std::string vendorNumbers(std::initializer_list<double> values, const char* separator = ", ") {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : separator) + vendorNumber(v);
  return out;
}

json poseJson(const Pose<double>& pose) {
  const Eigen::Vector3d rpy = rpyFromRotation(pose.rotation);
  return {{"xyz", numbersOrNull(pose.translation)}, {"rpy", numbersOrNull(rpy)}};
}

json matrixJson(const Eigen::Matrix3d& m) {
  json out = json::array();
  for (int r = 0; r < 3; ++r) out.push_back(numbersOrNull(m.row(r).transpose()));
  return out;
}

/// A determined quantity as "value ± half width"; one that is not as its resolution alone,
/// "not determined (± half width)": the log knows it no better than that, and its estimate is not
/// a number to use.
std::string interval(const PayloadQuantity& q, double scale = 1.0, int digits = 4) {
  if (!q.determined)
    return "not determined (± " + formatNumber(q.half_width * scale, 2, "unbounded") + ")";
  return formatNumber(q.value * scale, digits) + " ± " + formatNumber(q.half_width * scale, 2);
}

std::string verdict(const PayloadOutcome& o) {
  std::ostringstream text;
  const PayloadQuantity& m = o.quantities[0];
  text << "Mass " << interval(m) << " kg"
       << "; centre of mass (" << formatNumber(1e3 * o.com.x(), 4) << ", "
       << formatNumber(1e3 * o.com.y(), 4) << ", " << formatNumber(1e3 * o.com.z(), 4)
       << ") mm in the attachment frame";
  bool com = true, inertia = true;
  for (const PayloadQuantity& q : o.quantities) {
    if (q.group == "centre of mass" && !q.determined) com = false;
    if (q.group == "principal moments" && !q.determined) inertia = false;
  }
  text << (com ? ", determined to ±5 mm" : ", not determined to ±5 mm") << "; inertia about it "
       << (inertia ? "determined" : "not determined") << " (95 % intervals, docs/PAYLOAD.md). ";
  text << (o.mode == "difference" ? "From the torque difference of the loaded and the unloaded run."
                                  : "From one log, the arm model's torques subtracted.");
  return text.str();
}

/// The report's verdict box: what was estimated, how well, what the log leaves undetermined,
/// where the torques came from, and what to do next.
std::vector<std::pair<std::string, std::string>> verdictBox(const PayloadOutcome& o) {
  const PayloadQuantity& m = o.quantities[0];
  std::vector<std::string> undetermined;
  for (const PayloadQuantity& q : o.quantities)
    if (!q.determined && q.group != "standard parameters" && q.group != "principal axes")
      undetermined.push_back(q.name);
  bool com = true;
  for (const PayloadQuantity& q : o.quantities)
    if (q.group == "centre of mass" && !q.determined) com = false;
  std::string missing;
  for (std::size_t i = 0; i < undetermined.size(); ++i)
    missing += (i ? ", " : "") + undetermined[i];
  return {{"Estimated",
           "mass " + interval(m) + " kg, centre of mass (" + formatNumber(1e3 * o.com.x(), 4) +
               ", " + formatNumber(1e3 * o.com.y(), 4) + ", " + formatNumber(1e3 * o.com.z(), 4) +
               ") mm in the attachment frame of " + o.link_name},
          {"How well", std::string("95 % intervals; mass ") +
                           (m.determined ? "determined" : "not determined by this log") +
                           ", centre of mass " + (com ? "within" : "not within") + " ±5 mm"},
          {"Not determined", missing.empty() ? "nothing: every quantity is determined" : missing},
          {"Torque source", o.mode == "difference"
                                ? "the torque difference of the loaded and the unloaded run"
                                : "one log, the arm model's torques subtracted"},
          {"Next", !o.advice.empty() ? o.advice.front()
                   : missing.empty()
                       ? "write the payload into the model (--write-urdf) and check it with dynid "
                         "predict on another log"
                       : "record a motion that excites what is missing (dynid excite --payload)"}};
}

}  // namespace

const std::vector<std::string>& payloadFormats() {
  static const std::vector<std::string> names = {"ur", "franka", "kuka", "abb", "json"};
  return names;
}

std::vector<std::string> payloadFormatList(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const std::string& item : items)
    for (std::size_t from = 0; from <= item.size();) {
      const std::size_t comma = std::min(item.find(',', from), item.size());
      const std::string f = item.substr(from, comma - from);
      if (std::find(payloadFormats().begin(), payloadFormats().end(), f) ==
          payloadFormats().end()) {
        std::string accepted;
        for (const std::string& a : payloadFormats())
          accepted += (accepted.empty() ? "" : ", ") + a;
        throw InputError("unknown payload format '" + f + "' (accepted: " + accepted + ")");
      }
      if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
      from = comma + 1;
    }
  return out;
}

json payloadJson(const PayloadOutcome& o) {
  json out = documentHeader(kPayloadDocument);
  static const char* names[10] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
  json standard = json::object(), least_squares = json::object(), prior = json::object();
  for (int k = 0; k < 10; ++k) {
    standard[names[k]] = numberOrNull(o.standard[k]);
    least_squares[names[k]] = numberOrNull(o.least_squares[k]);
    prior[names[k]] = numberOrNull(o.prior[k]);
  }
  json quantities = json::array();
  for (const PayloadQuantity& q : o.quantities)
    quantities.push_back({{"name", q.name},
                          {"group", q.group},
                          {"unit", q.unit},
                          {"value", q.determined ? numberOrNull(q.value) : json(nullptr)},
                          {"estimate", numberOrNull(q.value)},
                          {"std_dev", numberOrNull(q.std_dev)},
                          {"half_width_95", numberOrNull(q.half_width)},
                          {"determined", q.determined}});
  json friction = json::array();
  for (const FrictionChange& c : o.friction)
    friction.push_back({{"name", c.name},
                        {"arm", numberOrNull(c.arm)},
                        {"with_payload", numberOrNull(c.with_payload)},
                        {"std_dev", numberOrNull(c.std_dev)}});
  out.update({{"robot", o.robot},
              {"arm", o.arm_source},
              {"data", o.data_file},
              {"unloaded", o.unloaded_file.empty() ? json(nullptr) : json(o.unloaded_file)},
              {"mode", o.mode},
              {"link", o.link_name},
              {"attachment_frame", poseJson(o.tool)},
              {"samples", o.samples},
              {"mass", numberOrNull(o.mass)},
              {"com", numbersOrNull(o.com)},
              {"inertia_about_com", matrixJson(o.inertia_com)},
              {"principal_moments", numbersOrNull(o.principal_moments)},
              {"principal_axes", matrixJson(o.principal_axes)},
              {"standard", standard},
              {"least_squares", least_squares},
              {"least_squares_consistent", o.least_squares_consistent},
              {"quantities", quantities},
              {"unseen_combinations", o.unseen},
              {"combinations_determined", o.combined},
              {"smallest_mass_resolved", numberOrNull(o.smallest_mass)},
              {"smallest_moment_resolved", numberOrNull(o.smallest_moment)},
              {"advice", o.advice},
              {"warnings", o.warnings},
              {"prior", {{"given", o.prior_given}, {"weight", o.prior_weight}, {"body", prior}}},
              {"solver", {{"converged", o.converged}, {"termination", o.termination}}},
              {"noise", numbersOrNull(o.noise)},
              {"residual_rms", numbersOrNull(o.residual_rms)},
              {"payload_torque_rms", numbersOrNull(o.target_rms)},
              {"covariance_batch", o.batch},
              {"friction", friction}});
  embedModel(out, o.arm, o.arm_model);  // the arm the payload was estimated on
  if (o.mode == "difference")
    out["alignment"] = {{"shift", numberOrNull(o.shift)},
                        {"position_rms_difference", numbersOrNull(o.motion_difference)}};
  if (o.gains) {
    json gains = json::array();
    for (Eigen::Index j = 0; j < o.gains->scale.size(); ++j)
      gains.push_back({{"joint", j + 1},
                       {"scale", numberOrNull(o.gains->scale[j])},
                       {"std_dev", numberOrNull(o.gains->scale_std[j])},
                       {"determined", o.gains->determined[j] != 0}});
    out["drive_gains"] = {
        {"meaning", "true torque / measured torque: multiply the torque constants by it"},
        {"joints", gains},
        {"torque_constants",
         o.gains->torque_constants.empty() ? json(nullptr) : json(o.gains->torque_constants)}};
  }
  return out;
}

std::pair<std::string, std::string> payloadVendorFile(const PayloadOutcome& o,
                                                      const std::string& format) {
  const Eigen::Matrix3d& ic = o.inertia_com;
  const std::string where =
      "dynid payload: robot " + commentSafe(o.robot) + ", link " + commentSafe(o.link_name) +
      "; the attachment frame must be the controller's flange/tool frame (docs/PAYLOAD.md)";
  if (format == "ur") {
    // URScript set_target_payload(m, cog [m], inertia [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] about the
    // centre of gravity, tool flange axes [kg m^2]).
    return {"payload.urscript",
            "# " + where + "\nset_target_payload(" + vendorNumber(o.mass) + ", [" +
                vendorNumbers({o.com.x(), o.com.y(), o.com.z()}) + "], [" +
                vendorNumbers({ic(0, 0), ic(1, 1), ic(2, 2), ic(0, 1), ic(0, 2), ic(1, 2)}) +
                "])\n"};
  }
  if (format == "franka") {
    // libfranka Robot::setLoad(load_mass, F_x_Cload [m], load_inertia [kg m^2], column-major).
    json doc = {{"comment", where},
                {"load_mass", o.mass},
                {"F_x_Cload", {o.com.x(), o.com.y(), o.com.z()}},
                {"load_inertia", json::array()}};
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) doc["load_inertia"].push_back(ic(r, c));
    return {"payload.franka.json", jsonText(doc, 2) + "\n"};
  }
  if (format == "kuka") {
    // KRL LOAD: M [kg], CM {X, Y, Z [mm], A, B, C [deg]: principal axes, Rz(A) Ry(B) Rx(C)},
    // J {X, Y, Z [kg m^2]: principal moments}.
    const Eigen::Vector3d abc = kukaAbc(o.principal_axes) * kDegrees;
    const Eigen::Vector3d mm = o.com * 1e3;
    return {"payload.kuka.dat",
            "; " + where + "\nLOAD_DATA[1]={M " + vendorNumber(o.mass) + ",CM {X " +
                vendorNumber(mm.x()) + ",Y " + vendorNumber(mm.y()) + ",Z " + vendorNumber(mm.z()) +
                ",A " + vendorNumber(abc.x()) + ",B " + vendorNumber(abc.y()) + ",C " +
                vendorNumber(abc.z()) + "},J {X " + vendorNumber(o.principal_moments.x()) + ",Y " +
                vendorNumber(o.principal_moments.y()) + ",Z " +
                vendorNumber(o.principal_moments.z()) + "}}\n"};
  }
  if (format == "abb") {
    // RAPID loaddata [mass [kg], cog [mm], aom (quaternion q1..q4 of the principal axes), ix, iy,
    // iz [kg m^2]].
    const Eigen::Vector4d q = abbQuaternion(o.principal_axes);
    const Eigen::Vector3d mm = o.com * 1e3;
    return {
        "payload.abb.mod",
        "! " + where + "\nPERS loaddata dynid_payload := [" + vendorNumber(o.mass) + ",[" +
            vendorNumbers({mm.x(), mm.y(), mm.z()}, ",") + "],[" +
            vendorNumbers({q[0], q[1], q[2], q[3]}, ",") + "]," +
            vendorNumbers(
                {o.principal_moments.x(), o.principal_moments.y(), o.principal_moments.z()}, ",") +
            "];\n"};
  }
  if (format == "json") {
    json doc = documentHeader(kPayloadBodyDocument);
    static const char* names[10] = {"m",   "mx",  "my",  "mz",  "Ixx",
                                    "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
    json standard = json::object();
    for (int k = 0; k < 10; ++k) standard[names[k]] = o.standard[k];
    doc.update({{"robot", o.robot},
                {"link", o.link_name},
                {"attachment_frame", poseJson(o.tool)},
                {"mass", o.mass},
                {"com", {o.com.x(), o.com.y(), o.com.z()}},
                {"inertia_about_com", matrixJson(ic)},
                {"standard", standard}});
    return {"payload.body.json", jsonText(withProvenance(doc), 2) + "\n"};
  }
  std::string accepted;
  for (const std::string& f : payloadFormats()) accepted += (accepted.empty() ? "" : ", ") + f;
  throw InputError("unknown payload format '" + format + "' (accepted: " + accepted + ")");
}

namespace {

/// The report's payload section: the derived quantities and the standard parameters.
void payloadTables(Document& report, const PayloadOutcome& o) {
  report.heading("The payload");
  DocumentTable table;
  table.header = {"quantity", "value", "± 95 %", "unit", "determined"};
  for (const PayloadQuantity& q : o.quantities) {
    if (q.group == "standard parameters") continue;
    table.rows.push_back({q.name, q.determined ? formatNumber(q.value, 5) : "—",
                          formatNumber(q.half_width, 2, "∞"), q.unit,
                          q.determined ? "yes" : "no (estimate " + formatNumber(q.value, 3) + ")"});
  }
  table.caption =
      "Mass, centre of mass and inertia about the centre of mass in the attachment frame's axes "
      "(_c), and the principal moments I1..I3 (axes in payload.json). Determined: the 95 % "
      "interval's half-width is at most 20 % of the value (mass, moments), 5 mm (centre of mass), "
      "20 % of the largest principal moment (inertia entries) or 10 degrees (axis1..axis3: each "
      "principal axis's angle from the attachment axis of its index, and its 95 % angle). A "
      "quantity that is not determined has no value: the log resolves it to its ± 95 % and no "
      "finer, and its estimate (in brackets) is the prior's as much as the data's.";
  report.table(table);
  DocumentTable standard;
  standard.header = {"parameter", "consistent", "least squares", "± 95 %", "determined"};
  for (int k = 0; k < 10; ++k) {
    const PayloadQuantity& q = o.quantities[13 + k];
    standard.rows.push_back({q.name, formatNumber(q.value, 5), formatNumber(o.least_squares[k], 5),
                             formatNumber(q.half_width, 2, "∞"), q.determined ? "yes" : "no"});
  }
  standard.caption = "The 10 standard parameters in the attachment frame (docs/PAYLOAD.md).";
  report.table(standard);
}

/// What the motion determines: the smallest payload resolved, what it does not see, and what it
/// sees only in combination.
void determinedSection(Document& report, const PayloadOutcome& o) {
  report.heading("What this motion determines");
  std::ostringstream ident;
  ident << "The smallest mass this log resolves to ±20 % (95 %) is "
        << formatNumber(o.smallest_mass, 3) << " kg; the smallest principal moment, "
        << formatNumber(o.smallest_moment, 3) << " kg m^2.";
  if (o.unseen.empty())
    ident << " Every combination of the 10 parameters is excited.";
  else
    ident << " Not seen at all by this motion (only the other combinations are): "
          << o.unseen.size() << " direction(s), listed below.";
  report.paragraph(ident.str());
  report.bullets(o.unseen);
  if (!o.combined.empty()) {
    report.paragraph("Determined only in combination (each part alone is not):");
    report.bullets(o.combined);
  }
}

/// Friction with the payload, and the drive gains from a known mass (when estimated).
void frictionAndGains(Document& report, const PayloadOutcome& o) {
  if (!o.friction.empty()) {
    report.heading("Friction with the payload");
    DocumentTable f;
    f.header = {"parameter", "arm model", "with the payload", "± 95 %"};
    for (const FrictionChange& c : o.friction)
      f.rows.push_back({c.name, formatNumber(c.arm, 4), formatNumber(c.with_payload, 4),
                        formatNumber(1.959963984540054 * c.std_dev, 2)});
    report.table(f);
  }
  if (o.gains) {
    report.heading("Drive gains from the known mass");
    DocumentTable g;
    g.header = {"joint", "scale (true / measured torque)", "± 95 %", "determined",
                "torque constant"};
    for (Eigen::Index j = 0; j < o.gains->scale.size(); ++j)
      g.rows.push_back(
          {std::to_string(j + 1), formatNumber(o.gains->scale[j], 5),
           formatNumber(1.959963984540054 * o.gains->scale_std[j], 2, "∞"),
           o.gains->determined[j] ? "yes" : "no (the joint feels too little of the load)",
           o.gains->torque_constants.empty() ? "-"
                                             : formatNumber(o.gains->torque_constants[j], 6)});
    g.caption =
        "Multiply each joint's torque constant by its scale (prepare --torque-constants); a "
        "joint whose scale is not determined to ±0.5 % (95 %) keeps its constant.";
    report.table(g);
  }
}

}  // namespace

std::string writePayload(const std::string& dir, const PayloadOutcome& o,
                         const std::vector<std::string>& formats, const std::string& urdf_path) {
  std::vector<std::pair<std::string, std::string>> vendor;
  for (const std::string& f : formats) vendor.push_back(payloadVendorFile(o, f));

  Document report("Payload: " + o.robot + ", link " + o.link_name);
  report.verdict(verdictBox(o));
  report.paragraph(verdict(o));
  if (!o.advice.empty() || !o.warnings.empty()) {
    std::vector<std::string> items = o.advice;
    for (const std::string& w : o.warnings) items.push_back("warning: " + w);
    report.bullets(items);
  }
  payloadTables(report, o);
  determinedSection(report, o);
  frictionAndGains(report, o);

  report.heading("Torques");
  DocumentTable fit;
  fit.header = {"joint", "payload torque RMS", "residual RMS", "noise"};
  for (Eigen::Index j = 0; j < o.noise.size(); ++j)
    fit.rows.push_back({std::to_string(j + 1), formatNumber(o.target_rms[j], 3),
                        formatNumber(o.residual_rms[j], 3), formatNumber(o.noise[j], 3)});
  fit.caption = std::string("N m. The payload torque is the ") +
                (o.mode == "difference" ? "loaded run's torque minus the unloaded run's"
                                        : "measured torque minus the arm model's") +
                " (" + std::to_string(o.samples) +
                " samples); the residual what the payload estimate leaves of it.";
  report.table(fit);
  std::string warning;
  Prediction p;
  p.time = o.plot_time;
  p.measured = o.plot_measured;
  p.predicted = o.plot_predicted;
  if (const auto svg = torqueFigure(p, "payload torque: measured and estimated"))
    report.figure({"payload_torques",
                   "The payload's torque per joint, measured (the difference) and the estimate's.",
                   *svg});
  else
    warning = "warning: gnuplot is not available: the report has no figure\n";
  report.heading("Method");
  report.paragraph(
      "The payload's torques are linear in its 10 standard parameters (the attachment link's "
      "regressor columns moved into the attachment frame); weighted least squares per joint, then "
      "the physically consistent estimate (entropic divergence from " +
      std::string(o.prior_given ? "the given prior" : "an uninformative prior") + ", weight " +
      formatNumber(o.prior_weight) +
      "). Intervals: the least-squares covariance from batch means of " + std::to_string(o.batch) +
      " samples (correlated residuals widen them), propagated to every quantity. Solver: " +
      o.termination + ".");

  OutputSet set(dir);
  set.add("payload.json", jsonText(withProvenance(payloadJson(o)), 2) + "\n");
  set.add("report.md", report.markdown());
  set.add("report.html", report.html());
  for (const Figure& f : report.figures()) set.add(f.name + ".svg", f.svg);
  for (const auto& [name, content] : vendor) set.add(name, content);
  set.publish();
  std::ostringstream summary;
  summary << verdict(o) << "\n";
  for (const std::string& a : o.advice) summary << "advice: " << a << "\n";
  for (const std::string& w : o.warnings) summary << "warning: " << w << "\n";
  summary << warning << "wrote " << dir << "/payload.json, report.md, report.html";
  for (const auto& [name, content] : vendor) summary << ", " << name;
  summary << "\n";
  if (o.urdf && !urdf_path.empty()) {
    if (writeOutput(urdf_path, *o.urdf)) summary << "wrote " << urdf_path << "\n";
  }
  return summary.str();
}

}  // namespace dynid
