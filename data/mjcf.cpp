#include "data/mjcf.hpp"

#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "core/format.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

std::string numbers(std::initializer_list<double> values) {
  std::string out;
  for (double v : values) {
    if (!out.empty()) out += ' ';
    out += formatNumber(v);
  }
  return out;
}

/// Joint i's limits and drive terms as MJCF <joint> attributes (with drives_and_limits), or a
/// joint without either.
std::string jointAttributes(const Model& model, int i, bool drives_and_limits) {
  if (!drives_and_limits) return "limited=\"false\" damping=\"0\" armature=\"0\"";
  const JointLimits& l = model.limits[i];
  std::string out = std::isfinite(l.lower) && std::isfinite(l.upper)
                        ? "limited=\"true\" range=\"" + numbers({l.lower, l.upper}) + "\""
                        : std::string("limited=\"false\"");
  for (const DriveTermInfo& row : kDriveTermTable)
    if (!row.mjcf_joint.empty() && model.driveTerms().has(row.term))
      out += " " + std::string(row.mjcf_joint) + "=\"" +
             formatNumber(std::abs(model.drives()[i][row.term])) + "\"";
  return out;
}

void writeBody(const Model& model, const std::vector<std::vector<int>>& children, int i, int depth,
               bool drives_and_limits, std::ostringstream& out) {
  const std::string indent(2 * depth, ' ');
  const Pose<double>& placement = model.frame_placements()[i];
  const Eigen::Quaterniond quat(placement.rotation);
  const Eigen::Vector3d& p = placement.translation;
  out << indent << "<body name=\"" << escapeXml(model.link_names[i]) << "\" pos=\""
      << numbers({p.x(), p.y(), p.z()}) << "\" quat=\""
      << numbers({quat.w(), quat.x(), quat.y(), quat.z()}) << "\">\n";
  const Eigen::Vector3d& a = model.axes()[i];
  out << indent << "  <joint name=\"" << escapeXml(model.joint_names[i]) << "\" type=\""
      << (model.joint_types()[i] == JointType::kPrismatic ? "slide" : "hinge")
      << "\" pos=\"0 0 0\" axis=\"" << numbers({a.x(), a.y(), a.z()}) << "\" "
      << jointAttributes(model, i, drives_and_limits) << "/>\n";
  // Inertia in the joint frame, about the centre of mass.
  const RigidInertia<double>& inertia = model.frame_inertias()[i];
  const double m = inertia.mass;
  const Eigen::Vector3d c =
      m != 0.0 ? Eigen::Vector3d(inertia.first_moment / m) : Eigen::Vector3d::Zero();
  const Eigen::Matrix3d Ic =
      inertia.inertia - m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  out << indent << "  <inertial pos=\"" << numbers({c.x(), c.y(), c.z()}) << "\" mass=\""
      << formatNumber(m) << "\" fullinertia=\""
      << numbers({Ic(0, 0), Ic(1, 1), Ic(2, 2), Ic(0, 1), Ic(0, 2), Ic(1, 2)}) << "\"/>\n";
  for (int child : children[i])
    writeBody(model, children, child, depth + 1, drives_and_limits, out);
  out << indent << "</body>\n";
}

/// Each body's children and the roots, in dynid order.
std::pair<std::vector<std::vector<int>>, std::vector<int>> tree(const Model& model) {
  std::vector<std::vector<int>> children(model.numJoints());
  std::vector<int> roots;
  for (int i = 0; i < model.numJoints(); ++i)
    (model.parents()[i] < 0 ? roots : children[model.parents()[i]]).push_back(i);
  return {children, roots};
}

void depthFirst(const std::vector<std::vector<int>>& children, int i, std::vector<int>& order) {
  order.push_back(i);
  for (int child : children[i]) depthFirst(children, child, order);
}

}  // namespace

std::vector<int> mjcfJointOrder(const Model& model) {
  const auto [children, roots] = tree(model);
  std::vector<int> order;
  for (int root : roots) depthFirst(children, root, order);
  return order;
}

std::string modelToMjcf(const Model& model, const MjcfOptions& options) {
  const auto [children, roots] = tree(model);
  std::ostringstream out;
  const Eigen::Vector3d& g = model.gravity();
  out << "<mujoco model=\"" << escapeXml(model.name) << "\">\n"
      << (options.drives_and_limits
              ? "  <!-- written by dynid: bodies are dynid joint frames; no geoms; joints carry "
                "armature = Ia, damping = Fv, frictionloss = Fc and their ranges -->\n"
              : "  <!-- written by dynid: bodies are dynid joint frames; no geoms, limits or "
                "drives -->\n")
      << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "  <option timestep=\"" << formatNumber(options.timestep) << "\" integrator=\""
      << escapeXml(options.integrator) << "\" gravity=\"" << numbers({g.x(), g.y(), g.z()})
      << "\">\n"
      << "    <flag contact=\"disable\"/>\n"
      << "  </option>\n"
      << "  <worldbody>\n";
  for (int root : roots) writeBody(model, children, root, 2, options.drives_and_limits, out);
  out << "  </worldbody>\n</mujoco>\n";
  return out.str();
}

std::vector<std::string> mjcfCannotCarry(const Model& model) {
  std::vector<std::string> out;
  for (const DriveTermInfo& row : kDriveTermTable)
    if (row.mjcf_joint.empty() && model.driveTerms().has(row.term))
      out.push_back("MJCF has no joint attribute for " + std::string(row.description) + " (" +
                    std::string(row.name) + "): the export goes without it; a dynid JSON model " +
                    "keeps it");
  for (int i = 0; i < model.numJoints(); ++i)
    if (!(model.frame_inertias()[i].mass > 0.0))
      out.push_back("link " + model.link_names[i] + " has mass " +
                    formatNumber(model.frame_inertias()[i].mass) +
                    ": MuJoCo's compiler rejects a body without a positive mass (`dynid model "
                    "check` lists what else is not physical)");
  return out;
}

}  // namespace dynid
