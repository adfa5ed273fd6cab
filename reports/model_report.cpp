#include "reports/model_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/mjcf.hpp"
#include "data/model_json.hpp"
#include "data/urdf.hpp"

namespace dynid {

namespace {

/// printf into a string, whatever the length (names come from the user's files).
void appendf(std::string& out, const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int length = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (length > 0) {
    const std::size_t at = out.size();
    out.resize(at + static_cast<std::size_t>(length) + 1);
    std::vsnprintf(out.data() + at, static_cast<std::size_t>(length) + 1, format, again);
    out.resize(at + static_cast<std::size_t>(length));
  }
  va_end(again);
}

/// The width of a column: its heading's, or the longest entry's.
int columnWidth(const char* heading, const std::vector<std::string>& entries) {
  std::size_t width = std::char_traits<char>::length(heading);
  for (const std::string& e : entries) width = std::max(width, e.size());
  return static_cast<int>(width);
}

nlohmann::json toJson(const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); }

void appendVector(std::string& out, const char* name, const char* unit, const Eigen::VectorXd& v) {
  appendf(out, "%-4s [%s]:", name, unit);
  for (double x : v) appendf(out, " % .10g", x);
  out += "\n";
}

}  // namespace

std::string modelShowText(const Model& model) {
  std::string out;
  appendf(out, "robot %s: %d joints, gravity (%g, %g, %g) m/s^2, drive terms %s\n",
          model.name.c_str(), model.numJoints(), model.gravity().x(), model.gravity().y(),
          model.gravity().z(), driveTermsText(model.driveTerms()).c_str());
  // Columns as wide as their longest name (a URDF's "shoulder_pan_joint" included).
  std::vector<std::string> parents;
  for (int i = 0; i < model.numJoints(); ++i)
    parents.push_back(model.parents()[i] < 0 ? "(base)" : model.link_names[model.parents()[i]]);
  const int link_width = columnWidth("link", model.link_names),
            joint_width = columnWidth("joint", model.joint_names),
            parent_width = columnWidth("parent", parents);
  appendf(out, "\n%-4s %-*s %-*s %-11s %-*s %s\n", "#", link_width, "link", joint_width, "joint",
          "type", parent_width, "parent", "limits [rad or m]");
  for (int i = 0; i < model.numJoints(); ++i)
    appendf(out, "%-4d %-*s %-*s %-11s %-*s [%g, %g]\n", i + 1, link_width,
            model.link_names[i].c_str(), joint_width, model.joint_names[i].c_str(),
            jointTypeName(model.joint_types()[i]), parent_width, parents[i].c_str(),
            model.limits[i].lower, model.limits[i].upper);
  // The link frames at q = 0, to compare with the datasheet (roll-pitch-yaw: R = Rz Ry Rx).
  out += "\nlink frames at q = 0, in the base frame: origin [m], roll pitch yaw [rad]\n";
  const std::vector<Pose<double>> frames = linkFramesAtZero(model);
  for (int i = 0; i < model.numJoints(); ++i) {
    const Eigen::Matrix3d& r = frames[i].rotation;
    const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
    const double roll = std::atan2(r(2, 1), r(2, 2)), yaw = std::atan2(r(1, 0), r(0, 0));
    const Eigen::Vector3d& p = frames[i].translation;
    appendf(out, "  %-*s (% .6f, % .6f, % .6f)  rpy (% .6f, % .6f, % .6f)\n", link_width,
            model.link_names[i].c_str(), p.x(), p.y(), p.z(), roll, pitch, yaw);
  }
  const ParameterLayout layout = model.parameterLayout();
  const std::vector<std::string> names = standardParameterNames(layout);
  const Eigen::VectorXd theta = model.standardParameters();
  out += "\nstandard parameters (link frame origin; SI units):\n";
  // Five to a line, in columns as wide as the longest name and value.
  std::vector<std::string> values(names.size());
  int name_width = 0, value_width = 0;
  for (std::size_t index = 0; index < names.size(); ++index) {
    appendf(values[index], "% .6g", theta(static_cast<Eigen::Index>(index)));
    name_width = std::max(name_width, static_cast<int>(names[index].size()));
    value_width = std::max(value_width, static_cast<int>(values[index].size()));
  }
  for (int i = 0; i < model.numJoints(); ++i) {
    for (int k = 0; k < layout.perLink(); ++k) {
      const auto index = static_cast<std::size_t>(i * layout.perLink() + k);
      const bool last = (k + 1) % 5 == 0 || k + 1 == layout.perLink();
      appendf(out, "  %-*s %*s%s", name_width, names[index].c_str(), last ? 0 : value_width,
              values[index].c_str(), last ? "\n" : "");
    }
  }
  out += "\npaper parameters (m, centre of mass, principal inertia about it):\n";
  for (int i = 0; i < model.numJoints(); ++i) {
    double dropped = 0.0;
    const auto paper = standardToPaper(toStandardVector(model.inertias()[i]), &dropped);
    appendf(out, "  link %-3d m %-9.6g c (%.6g, %.6g, %.6g)  I (%.6g, %.6g, %.6g)%s\n", i + 1,
            paper(0), paper(1), paper(2), paper(3), paper(4), paper(5), paper(6),
            dropped > 1e-12 ? "  [has products of inertia]" : "");
  }
  return out;
}

std::string modelCheckText(const Model& model, const std::vector<ConsistencyViolation>& all) {
  std::string out;
  if (all.empty())
    appendf(out, "%s: all %d links are physically consistent\n", model.name.c_str(),
            model.numJoints());
  for (const auto& v : all)
    appendf(out, "%s: link %d (%s) violates %s: %s\n", model.name.c_str(), v.link + 1,
            v.link_name.c_str(), v.condition.c_str(), v.detail.c_str());
  return out;
}

nlohmann::json modelCheckJson(const Model& model, const std::vector<ConsistencyViolation>& all) {
  nlohmann::json violations = nlohmann::json::array();
  for (const auto& v : all)
    violations.push_back({{"link", v.link + 1},
                          {"link_name", v.link_name},
                          {"condition", v.condition},
                          {"detail", v.detail}});
  return {{"schema_version", kModelCheckDocument.schema_version},
          {"kind", kModelCheckDocument.kind},
          {"robot", model.name},
          {"consistent", all.empty()},
          {"violations", violations}};
}

std::string modelDocument(const Model& model, const std::string& format) {
  if (format == "urdf") return modelToUrdf(model);
  if (format == "mjcf") return modelToMjcf(model, {.drives_and_limits = true});
  if (format == "json") return modelToJson(model);
  throw InputError("the format must be urdf, json or mjcf, not '" + format + "'");
}

void embedModel(nlohmann::json& document, const Model& model, const ModelSource& source) {
  document["model"] = nlohmann::json::parse(modelToJson(model));
  document["model_source"] = modelSourceJson(source);
}

std::vector<std::string> modelExportNotes(const Model& model, const std::string& format) {
  if (format == "urdf") return urdfCannotCarry(model);
  if (format == "mjcf") return mjcfCannotCarry(model);
  return {};
}

nlohmann::json dynamicsJson(const Model& model, const DynamicsOutcome& o) {
  nlohmann::json m = nlohmann::json::array();
  for (int r = 0; r < model.numJoints(); ++r) m.push_back(toJson(o.M.row(r).transpose()));
  return {{"schema_version", kDynamicsDocument.schema_version},
          {"kind", kDynamicsDocument.kind},
          {"robot", model.name},
          {"drives", model.driveTerms().any()},
          {"drive_terms", driveTermsKeys(model.driveTerms())},
          {"q", toJson(o.q)},
          {"dq", toJson(o.dq)},
          {"tau", toJson(o.tau)},
          {"M", m},
          {"ddq", toJson(o.ddq)}};
}

std::string dynamicsText(const Model& model, const DynamicsOutcome& o) {
  std::string out;
  appendf(out, "robot %s (drive terms %s)\n", model.name.c_str(),
          driveTermsText(model.driveTerms()).c_str());
  appendVector(out, "q", "rad", o.q);
  appendVector(out, "dq", "rad/s", o.dq);
  appendVector(out, "ddq", "rad/s^2", o.ddq);
  appendVector(out, "tau", "N m", o.tau);
  out += "M(q) [kg m^2]:\n";
  for (int r = 0; r < model.numJoints(); ++r) {
    for (int c = 0; c < model.numJoints(); ++c) appendf(out, " % .6e", o.M(r, c));
    out += "\n";
  }
  return out;
}

std::string simulateSummary(const Model& model, const SimulateOutcome& o, const std::string& file) {
  const Trajectory& t = o.trajectory;
  std::string out;
  appendf(out,
          "wrote %s: %s, %d samples x %d joints, t = 0..%g s, tracking error RMS %.3g rad, "
          "peak |tau| %.4g N m\n",
          file.c_str(), model.name.c_str(), t.numSamples(), model.numJoints(),
          t.time[t.numSamples() - 1], o.tracking_rms, o.peak_torque);
  if (o.gains_rule == "effective inertia")
    out +=
        "note: default gains from the joints' effective inertias 1/(M^-1)_ii, the rule for "
        "strongly coupled joints (the mass-matrix diagonal's would put a closed-loop mode above "
        "3x `bandwidth`); not a fault\n";
  // A run farther from its reference than dynid payload allows between a loaded and an unloaded run
  // (0.05 rad RMS) cannot be expected to match another run of it.
  if (o.tracking_rms > 0.05)
    appendf(
        out,
        "warning: the motion tracks its reference %.3g rad RMS off: another run of it (a "
        "loaded/unloaded pair: dynid payload aligns them within 0.05 rad) will not match; raise "
        "`bandwidth` (stiffer default gains; 20 Hz for a payload pair) or give `kp`/`kd`\n",
        o.tracking_rms);
  // A tracking controller's torque changes little in one sample; a jump of a tenth of the peak
  // torque is chatter (gains too stiff for the rate), torque at the limit on more than 1 % of the
  // samples a reference that asks more than the drives give.
  if (o.saturated_share > 0.01)
    appendf(out,
            "warning: the torque is at its limit on %.3g %% of the samples: the reference asks "
            "more than the drives give; slow the motion (smaller `amplitude`, lower `frequency`) "
            "or give `tau_max`\n",
            100.0 * o.saturated_share);
  else if (o.max_torque_step > 0.1 * o.peak_torque)
    appendf(out,
            "warning: the torque jumps by up to %.4g N m between samples: the gains are too stiff "
            "for the rate; lower `bandwidth` or give `kp`/`kd`\n",
            o.max_torque_step);
  return out;
}

}  // namespace dynid
