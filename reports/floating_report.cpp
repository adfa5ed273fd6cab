#include "reports/floating_report.hpp"

#include <algorithm>
#include <sstream>

#include "analysis/records/document.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"

namespace dynid {

using nlohmann::json;

namespace {
std::vector<std::string> namesOf(const BaseParameters& base, const std::vector<int>& columns) {
  std::vector<std::string> out;
  for (int k : columns) out.push_back(base.standard_names[static_cast<std::size_t>(k)]);
  return out;
}

json setJson(const SensorSetBase& s, const Eigen::VectorXd& beta) {
  const BaseParameters& base = s.base;
  json bases = json::array();
  for (int j = 0; j < base.numBase(); ++j)
    bases.push_back(
        {{"name", base.baseName(j)}, {"expression", base.expression(j)}, {"model_value", beta[j]}});
  return {{"sensors", sensorSetName(s.set)},
          {"description", sensorSetDescription(s.set)},
          {"num_base", base.numBase()},
          {"rank_gap", numberOrNull(base.rankGap())},
          {"base_parameters", bases},
          {"determined_alone", namesOf(base, s.determined_alone)},
          {"never_seen", namesOf(base, base.zero_columns)}};
}

/// "torques_wrenches adds 12 to wrenches" lines' words.
std::string gainText(const SensorGain& g) {
  const bool torques = g.from == SensorSet::kWrenches;
  return std::string(torques ? "the joint torques add " : "measuring the contact wrenches adds ") +
         std::to_string(g.gained) + " base parameters to " + sensorSetName(g.from);
}
}  // namespace

json floatingContactJson(const Contact& c) {
  return {{"name", c.name},
          {"kind", c.kind == Contact::Kind::kPoint ? "point" : "frame"},
          {"body", c.body}};
}

json floatingIdentifiabilityJson(const FloatingModel& model,
                                 const FloatingIdentifiabilityOutcome& outcome) {
  json sets = json::array(), contacts = json::array(), gains = json::array();
  for (std::size_t k = 0; k < outcome.sets.size(); ++k)
    sets.push_back(setJson(outcome.sets[k], outcome.model_beta[k]));
  for (const Contact& c : outcome.contacts) contacts.push_back(floatingContactJson(c));
  for (const SensorGain& g : outcome.gains)
    gains.push_back(
        {{"from", sensorSetName(g.from)}, {"to", sensorSetName(g.to)}, {"gained", g.gained}});
  json report = documentHeader(kFloatingIdentifiabilityDocument);
  report.update({{"robot", model.name()},
                 {"base_link", model.baseName()},
                 {"joints", model.numJoints()},
                 {"drive_terms", driveTermsKeys(model.limbs().driveTerms())},
                 {"num_standard", model.numParameters()},
                 {"standard_parameters", floatingParameterNames(model)},
                 {"contacts", contacts},
                 {"motion", floatingMotionName(outcome.motion)},
                 {"sets", sets},
                 {"gains", gains},
                 {"structural",
                  {{"method", "column-scaled Householder QR without pivoting (Gautier)"},
                   {"random_states", outcome.structural.samples},
                   {"seed", outcome.structural.seed}}}});
  return report;
}

std::string floatingIdentifiabilityMarkdown(const FloatingModel& model,
                                            const FloatingIdentifiabilityOutcome& outcome) {
  std::ostringstream md;
  md << "# What the sensors of " << model.name() << " determine\n\n";
  md << "- Floating base `" << model.baseName() << "`, " << model.numJoints() << " joints, "
     << model.numParameters() << " standard parameters (the base body's 10 first)\n";
  md << "- Motion: " << floatingMotionName(outcome.motion) << "; contacts:";
  if (outcome.contacts.empty()) md << " none";
  for (const Contact& c : outcome.contacts)
    md << " `" << c.name << "` (" << (c.kind == Contact::Kind::kPoint ? "point" : "frame") << ")";
  md << "\n\n| sensors | base parameters | determined alone | never seen | rank gap |\n"
        "|---|---|---|---|---|\n";
  for (const SensorSetBase& s : outcome.sets)
    md << "| " << sensorSetName(s.set) << " | " << s.base.numBase() << " | "
       << s.determined_alone.size() << " | " << s.base.zero_columns.size() << " | "
       << formatNumber(s.base.rankGap(), 3) << " |\n";
  md << "\n";
  for (const SensorGain& g : outcome.gains) md << "- " << gainText(g) << "\n";
  for (const SensorSetBase& s : outcome.sets) {
    md << "\n## " << sensorSetName(s.set) << "\n\n" << sensorSetDescription(s.set) << ".\n\n";
    md << "Determined alone: ";
    if (s.determined_alone.empty()) md << "(none)";
    for (const std::string& n : namesOf(s.base, s.determined_alone)) md << "`" << n << "` ";
    md << "\n\nBase parameters:\n\n| # | combination |\n|---|---|\n";
    for (int j = 0; j < s.base.numBase(); ++j)
      md << "| " << j + 1 << " | `" << s.base.expression(j) << "` |\n";
  }
  return md.str();
}

std::string floatingIdentifiabilitySummary(const FloatingModel& model,
                                           const FloatingIdentifiabilityOutcome& outcome,
                                           const std::string& dir) {
  std::ostringstream out;
  out << model.name() << " (floating base " << model.baseName() << ", "
      << floatingMotionName(outcome.motion) << "): " << model.numParameters()
      << " standard parameters\n";
  for (const SensorSetBase& s : outcome.sets)
    out << "  " << sensorSetName(s.set) << ": " << s.base.numBase() << " base parameters, "
        << s.determined_alone.size() << " determined alone\n";
  for (const SensorGain& g : outcome.gains) out << "  " << gainText(g) << "\n";
  out << "wrote " << dir << "/floating_identifiability.json and " << dir
      << "/floating_identifiability.md\n";
  return out.str();
}

namespace {
/// "L x W m" for a rectangle centred at the frame, else the corners.
std::string soleText(const std::vector<Eigen::Vector2d>& sole) {
  const Eigen::Vector2d half = sole[0].cwiseAbs();
  if (sole == rectangularSole(2.0 * half.x(), 2.0 * half.y()))
    return formatNumber(2.0 * half.x()) + " x " + formatNumber(2.0 * half.y()) + " m";
  std::string text = std::to_string(sole.size()) + " corners";
  for (std::size_t k = 0; k < sole.size(); ++k)
    text += (k == 0 ? " (" : ", (") + formatNumber(sole[k].x()) + ", " + formatNumber(sole[k].y()) +
            ")";
  return text + " m";
}
}  // namespace

std::string floatingSimulationSummary(const FloatingModel& model,
                                      const FloatingSimulationOptions& options,
                                      const FloatingDataset& dataset, int drawn,
                                      const std::string& motion_file, const std::string& out) {
  std::ostringstream text;
  text << model.name() << " (floating base " << model.baseName() << ", "
       << floatingMotionName(options.motion) << "): " << dataset.numSamples()
       << (options.motion_from ? " states of the motion of " + motion_file + ", to "
           : options.trajectory && !options.stand_tilts.empty()
               ? " states of the design, one period at each of " +
                     std::to_string(options.stand_tilts.size()) +
                     " stand orientations 1 s apart, the base held still in each, to "
           : options.trajectory
               ? " states of the design over one period, the base held still, to "
               : " random states, one a row (independent draws, not a trajectory), to ")
       << (out == "-" ? "standard output" : out) << "\n";
  if (options.friction_cone > 0.0 && !options.motion_from)
    text << "  the contacts' forces within friction cones of mu "
         << formatNumber(options.friction_cone) << ": " << drawn << " states drawn, "
         << drawn - dataset.numSamples()
         << " of them left out (no forces within the cones carry their base wrench)\n";
  if (!options.sole.empty())
    text << "  every frame contact on a sole of " << soleText(options.sole)
         << ": its wrench that of " << options.sole.size()
         << " corner forces within the cones, its centre of pressure in the sole\n";
  return text.str();
}

}  // namespace dynid
