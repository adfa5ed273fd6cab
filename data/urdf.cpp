#include "data/urdf.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <queue>
#include <sstream>
#include <string_view>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>
#include <Eigen/Geometry>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/parameters.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

/// Where each <link> and <joint> is defined: document order and line, by name.
struct ElementIndex {
  std::map<std::string, int> joint_order, joint_line, link_line;
};

ElementIndex indexElements(const std::string& text) {
  ElementIndex index;
  int order = 0;
  for (const std::string tag : {"<joint", "<link"}) {
    // Lines counted incrementally (positions only grow within a tag's scan): linear in the text.
    int line = 1;
    std::size_t counted = 0;
    for (std::size_t pos = text.find(tag); pos != std::string::npos;
         pos = text.find(tag, pos + 1)) {
      const char next = pos + tag.size() < text.size() ? text[pos + tag.size()] : '\0';
      if (next != ' ' && next != '\t' && next != '\n' && next != '\r') continue;
      const std::size_t end = std::min(text.find('>', pos), text.size());
      const std::string_view element(text.data() + pos, end - pos);
      const std::size_t name_at = element.find("name=");
      if (name_at == std::string::npos || name_at + 6 > element.size()) continue;
      const char quote = element[name_at + 5];
      const std::size_t close = element.find(quote, name_at + 6);
      if (close == std::string::npos) continue;
      const std::string name(element.substr(name_at + 6, close - name_at - 6));
      line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(counted),
                                          text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
      counted = pos;
      auto& lines = tag == "<joint" ? index.joint_line : index.link_line;
      if (lines.count(name)) continue;  // <transmission> repeats joint names later
      lines[name] = line;
      if (tag == "<joint") index.joint_order[name] = order++;
    }
  }
  return index;
}

/// Refuses a document nested deeper than kMaxXmlDepth elements before any XML parser sees it: the
/// parser under urdfdom recurses once per level and overflows the stack on deep nesting (a URDF
/// is about 5 levels deep). Linear in the text; comments, CDATA, declarations and quoted
/// attribute values are skipped.
constexpr int kMaxXmlDepth = 100;
void checkXmlDepth(const std::string& text, const std::string& file) {
  int depth = 0;
  const std::size_t n = text.size();
  for (std::size_t i = text.find('<'); i < n; i = text.find('<', i)) {
    const auto skipTo = [&](const char* end) {
      const std::size_t at = text.find(end, i);
      return at == std::string::npos ? n : at + std::strlen(end);
    };
    if (text.compare(i, 4, "<!--") == 0) {
      i = skipTo("-->");
    } else if (text.compare(i, 9, "<![CDATA[") == 0) {
      i = skipTo("]]>");
    } else if (text.compare(i, 2, "<?") == 0 || text.compare(i, 2, "<!") == 0) {
      i = skipTo(">");
    } else if (text.compare(i, 2, "</") == 0) {
      --depth;
      i = skipTo(">");
    } else {
      const std::size_t j = xmlTagEnd(text, i + 1);
      if (j < n && text[j - 1] != '/' && ++depth > kMaxXmlDepth) {
        const auto at = text.begin() + static_cast<std::ptrdiff_t>(i);
        const int line = 1 + static_cast<int>(std::count(text.begin(), at, '\n'));
        throw ParseError(file, line, "",
                         "XML elements nested deeper than " + std::to_string(kMaxXmlDepth) +
                             " levels (a URDF needs about 5): not a robot description");
      }
      i = j;
    }
  }
}

/// Collects urdfdom's console_bridge error messages while parsing (console_bridge is global state).
/// urdfdom 3.0 logs some errors (a bad <inertial>: missing or unparsable mass) and still returns a
/// model with those values zeroed, so any logged error fails the load.
class CapturingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    if (!errors.empty()) errors += "; ";
    errors += text;
  }
  std::string errors;
};
std::mutex console_mutex;

Pose<double> toPose(const urdf::Pose& p) {
  Pose<double> out;
  const Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  out.rotation = q.normalized().toRotationMatrix();
  out.translation = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return out;
}

/// A name as it may be shown in a message: bytes that are not printable UTF-8 as \xNN.
std::string shownName(const std::string& name) {
  if (isPrintableUtf8(name)) return name;
  std::string out;
  for (char c : name) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      out += c;
    } else {
      static const char* const kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    }
  }
  return out;
}

const char* const kNotPrintable =
    "is not UTF-8 text without control characters: names appear in dynid's JSON, XML and HTML "
    "outputs (save the file as UTF-8)";

/// Finite, with a position within +-kMaxModelLength (a unit slip or garbage otherwise).
bool finitePose(const urdf::Pose& p) {
  return std::isfinite(p.rotation.x) && std::isfinite(p.rotation.y) &&
         std::isfinite(p.rotation.z) && std::isfinite(p.rotation.w) &&
         std::abs(p.position.x) <= kMaxModelLength && std::abs(p.position.y) <= kMaxModelLength &&
         std::abs(p.position.z) <= kMaxModelLength;
}

class UrdfBuilder {
 public:
  UrdfBuilder(const urdf::ModelInterface& urdf, const std::string& file, const ElementIndex& index,
              const UrdfOptions& options, std::vector<std::string>* warnings, bool floating = false)
      : urdf_(urdf),
        file_(file),
        index_(index),
        options_(options),
        warnings_(warnings),
        floating_(floating) {}

  /// After build() with `floating`: the base body's inertia (the root link and the links fixed to
  /// it), its name, and every link's frame.
  RigidInertia<double> base_inertia;
  std::string base_name;
  std::vector<BodyFrame> frames;

  Model build() {
    model_.name = urdf_.getName();
    if (!isPrintableUtf8(model_.name))
      throw ParseError(file_, 0, "robot name '" + shownName(model_.name) + "'", kNotPrintable);
    if (options_.drives) model_.setDriveTerms(DriveTerms::rotorAndFriction());
    for (const std::string& name : options_.fixed_joints) {
      const urdf::JointConstSharedPtr joint = urdf_.getJoint(name);
      if (!joint)
        throw ParseError(file_, 0, "joint '" + shownName(name) + "'",
                         "is not in the file: `fix_joints` names moving joints of the URDF");
      if (joint->type == urdf::Joint::FIXED)
        failJoint(name, "is fixed already: `fix_joints` names moving joints");
    }
    for (const auto& [name, joint] : urdf_.joints_) checkJoint(*joint);
    for (const auto& [name, link] : urdf_.links_) checkLink(*link);
    walk(floatingRoot());
    addBodies();
    if (model_.numJoints() == 0)
      throw ParseError(file_, 0, "robot '" + model_.name + "'", "has no moving joint");
    try {
      model_.finalize();
    } catch (const InputError& e) {
      throw ParseError(file_, 0, "", e.what());
    }
    return std::move(model_);
  }

 private:
  [[noreturn]] void failJoint(const std::string& name, const std::string& message) const {
    const auto it = index_.joint_line.find(name);
    throw ParseError(file_, it == index_.joint_line.end() ? 0 : it->second,
                     "joint '" + shownName(name) + "'", message);
  }
  [[noreturn]] void failLink(const std::string& name, const std::string& message) const {
    const auto it = index_.link_line.find(name);
    throw ParseError(file_, it == index_.link_line.end() ? 0 : it->second,
                     "link '" + shownName(name) + "'", message);
  }

  void checkJoint(const urdf::Joint& joint) const {
    if (!isPrintableUtf8(joint.name)) failJoint(joint.name, kNotPrintable);
    switch (joint.type) {
      case urdf::Joint::FLOATING:
        if (!floating_)
          failJoint(
              joint.name,
              "is a floating joint: a floating-base robot is loaded as one (`floating_base`)");
        if (joint.parent_link_name != urdf_.getRoot()->name)
          failJoint(joint.name, "is a floating joint below the root: only the root's can be");
        break;
      case urdf::Joint::PLANAR:
        failJoint(joint.name, "planar joints are not supported (1-dof joints only)");
      case urdf::Joint::UNKNOWN:
        failJoint(joint.name, "unknown joint type");
      default:
        break;
    }
    if (!finitePose(joint.parent_to_joint_origin_transform))
      failJoint(joint.name, "<origin> has a non-finite number or one beyond +-1e6 m");
    if (!std::isfinite(joint.axis.x) || !std::isfinite(joint.axis.y) ||
        !std::isfinite(joint.axis.z))
      failJoint(joint.name, "<axis> has a non-finite number");
    if (joint.type != urdf::Joint::FIXED && joint.type != urdf::Joint::FLOATING &&
        std::sqrt(joint.axis.x * joint.axis.x + joint.axis.y * joint.axis.y +
                  joint.axis.z * joint.axis.z) < 1e-12)
      failJoint(joint.name, "<axis> is the zero vector");
    if (joint.limits && (std::isnan(joint.limits->lower) || std::isnan(joint.limits->upper) ||
                         std::isnan(joint.limits->effort) || std::isnan(joint.limits->velocity)))
      failJoint(joint.name, "<limit> has a non-finite number");
    if (joint.limits && joint.type != urdf::Joint::CONTINUOUS &&
        joint.limits->lower > joint.limits->upper)
      failJoint(joint.name, "<limit> lower " + formatNumber(joint.limits->lower) +
                                " is above upper " + formatNumber(joint.limits->upper));
    if (joint.limits && (joint.limits->effort < 0.0 || joint.limits->velocity < 0.0))
      failJoint(joint.name, "<limit> effort and velocity must be >= 0");
    if (joint.dynamics &&
        (!std::isfinite(joint.dynamics->damping) || !std::isfinite(joint.dynamics->friction)))
      failJoint(joint.name, "<dynamics> has a non-finite number");
    if (joint.mimic && joint.type != urdf::Joint::FIXED && !fixedByOption(joint.name)) {
      // A gripper finger that mimics another: dynid has no coupled joints.
      const std::string message =
          "has <mimic joint=\"" + joint.mimic->joint_name +
          "\">: treated as an independent joint (its coordinate must be "
          "in the data); make it fixed to merge the finger into its parent (dynid model "
          "export `fix_joints` " +
          joint.name + " writes such a URDF)";
      if (options_.strict) failJoint(joint.name, message);
      if (warnings_) warnings_->push_back(file_ + ": joint '" + joint.name + "' " + message);
    }
  }

  /// Whether UrdfOptions::fixed_joints names the joint.
  bool fixedByOption(const std::string& name) const {
    return std::find(options_.fixed_joints.begin(), options_.fixed_joints.end(), name) !=
           options_.fixed_joints.end();
  }

  void checkLink(const urdf::Link& link) const {
    if (!isPrintableUtf8(link.name)) failLink(link.name, kNotPrintable);
    if (!link.inertial) return;
    const urdf::Inertial& in = *link.inertial;
    for (double x : {in.mass, in.ixx, in.ixy, in.ixz, in.iyy, in.iyz, in.izz})
      if (!std::isfinite(x)) failLink(link.name, "<inertial> has a non-finite number");
    if (!finitePose(in.origin))
      failLink(link.name, "<inertial><origin> has a non-finite number or one beyond +-1e6 m");
    if (in.mass < 0.0)
      failLink(link.name, "negative mass " + formatNumber(in.mass) + " kg in <inertial><mass>");
  }

  /// The link's inertia about its own frame origin, in its frame.
  RigidInertia<double> linkInertia(const urdf::Link& link, bool moving) const {
    RigidInertia<double> out;
    if (!link.inertial) {
      if (moving) {
        const std::string message =
            "has no <inertial>: treated as massless (a massless subtree makes the mass matrix "
            "singular)";
        if (options_.strict) failLink(link.name, message);
        if (warnings_) warnings_->push_back(file_ + ": link '" + link.name + "' " + message);
      }
      return out;
    }
    const urdf::Inertial& in = *link.inertial;
    if (moving && in.mass == 0.0 && in.ixx == 0.0 && in.ixy == 0.0 && in.ixz == 0.0 &&
        in.iyy == 0.0 && in.iyz == 0.0 && in.izz == 0.0) {
      const std::string message =
          "has a zero <mass> and <inertia>: treated as massless (a massless subtree makes the "
          "mass matrix singular)";
      if (options_.strict) failLink(link.name, message);
      if (warnings_) warnings_->push_back(file_ + ": link '" + link.name + "' " + message);
    }
    const Pose<double> origin = toPose(in.origin);
    // About the centre of mass in inertial-frame axes, rotated into link axes.
    Eigen::Matrix3d i_com;
    i_com << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    i_com = origin.rotation * i_com * origin.rotation.transpose();
    // Standard parameters: h = m c, I_origin = I_com - m [c]x [c]x.
    const Eigen::Matrix3d sc = skew(origin.translation);
    out.mass = in.mass;
    out.first_moment = in.mass * origin.translation;
    out.inertia = i_com - in.mass * sc * sc;
    const Eigen::Matrix<double, 10, 1> theta = toStandardVector(out);
    for (int k = 0; k < kLinkParameterCount; ++k)
      if (std::abs(theta(k)) > kMaxParameterMagnitude)
        failLink(link.name, "<inertial> gives " + std::string(kLinkParameterNames[k]) + " = " +
                                formatNumber(theta(k)) +
                                ", beyond +-1e6 (SI units: kg, m, kg m^2)");
    return out;
  }

  /// Where the robot starts: the root link, or for a floating base the child of the root's
  /// floating joint, if it has one (the root then is the world, and may hold nothing else).
  const urdf::Link& floatingRoot() const {
    const urdf::Link& root = *urdf_.getRoot();
    if (!floating_) return root;
    for (const urdf::JointSharedPtr& joint : root.child_joints) {
      if (joint->type != urdf::Joint::FLOATING) continue;
      if (root.child_joints.size() != 1)
        failLink(root.name, "holds the floating joint '" + joint->name +
                                "' and other joints: the world link holds the robot alone");
      const urdf::LinkConstSharedPtr child = urdf_.getLink(joint->child_link_name);
      if (!child) failJoint(joint->name, "unknown child link '" + joint->child_link_name + "'");
      if (root.inertial && root.inertial->mass != 0.0 && warnings_)
        warnings_->push_back(file_ + ": link '" + root.name + "' holds the floating joint '" +
                             joint->name +
                             "', so it is the world: its <inertial> is not part of the robot");
      return *child;
    }
    return root;
  }

  /// A moving joint found by the walk: its parent (another record, or -1 for the base) and its
  /// placement in that parent's link frame (fixed joints in between composed in).
  struct MovingJoint {
    const urdf::Joint* joint;
    const urdf::Link* child;
    int parent_record;
    Pose<double> placement;
  };
  /// A link merged by a fixed joint into a record's body (-1: the base) at a placement.
  struct Merge {
    const urdf::Link* link;
    int record;
    Pose<double> placement;
  };

  /// Depth first from the root, iteratively (a long chain must not exhaust the stack). A link
  /// reached twice has two parent joints: refused, not duplicated.
  void walk(const urdf::Link& root) {
    struct Pending {
      const urdf::Link* link;
      int record;
      Pose<double> link_in_body;
    };
    std::vector<Pending> stack = {{&root, -1, Pose<double>()}};
    if (floating_) {
      base_name = root.name;
      base_inertia = linkInertia(root, false);
      frames.push_back({root.name, -1, Pose<double>()});
    }
    std::map<const urdf::Link*, const urdf::Joint*> reached_by;
    while (!stack.empty()) {
      const Pending p = stack.back();
      stack.pop_back();
      std::vector<Pending> children;
      for (const urdf::JointSharedPtr& joint : p.link->child_joints) {
        const urdf::LinkConstSharedPtr child = urdf_.getLink(joint->child_link_name);
        if (!child) failJoint(joint->name, "unknown child link '" + joint->child_link_name + "'");
        const auto [seen, fresh] = reached_by.emplace(child.get(), joint.get());
        if (!fresh)
          failLink(child->name, "is the child of two joints ('" + seen->second->name + "' and '" +
                                    joint->name + "'): a link has one parent joint");
        const Pose<double> placement =
            p.link_in_body * toPose(joint->parent_to_joint_origin_transform);
        if (joint->type == urdf::Joint::FIXED || fixedByOption(joint->name)) {
          merges_.push_back({child.get(), p.record, placement});
          children.push_back({child.get(), p.record, placement});
        } else {
          moving_.push_back({joint.get(), child.get(), p.record, placement});
          children.push_back({child.get(), static_cast<int>(moving_.size()) - 1, Pose<double>()});
        }
      }
      // Reversed, so the first child is explored first, as the recursion did.
      stack.insert(stack.end(), children.rbegin(), children.rend());
    }
  }

  /// Bodies in topological order, choosing the joint defined first in the file whenever several
  /// are ready: a file that lists parents first keeps its joint order exactly.
  void addBodies() {
    const int count = static_cast<int>(moving_.size());
    std::vector<int> body_of(static_cast<std::size_t>(count), -1);
    std::vector<std::vector<int>> children(static_cast<std::size_t>(count));
    // Ready records (parent placed), smallest file order first: O(n log n).
    using Ready = std::pair<int, int>;  // (file order, record)
    std::priority_queue<Ready, std::vector<Ready>, std::greater<>> ready;
    for (int r = 0; r < count; ++r) {
      if (moving_[r].parent_record < 0)
        ready.emplace(order(moving_[r].joint->name), r);
      else
        children[static_cast<std::size_t>(moving_[r].parent_record)].push_back(r);
    }
    while (!ready.empty()) {
      const int best = ready.top().second;
      ready.pop();
      for (int c : children[static_cast<std::size_t>(best)])
        ready.emplace(order(moving_[c].joint->name), c);
      const MovingJoint& m = moving_[best];
      const urdf::Joint& joint = *m.joint;
      JointType type = JointType::kRevolute;
      if (joint.type == urdf::Joint::CONTINUOUS) type = JointType::kContinuous;
      if (joint.type == urdf::Joint::PRISMATIC) type = JointType::kPrismatic;
      const Eigen::Vector3d axis =
          Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z).normalized();
      JointLimits limits;
      if (joint.limits) {
        if (type != JointType::kContinuous) {
          limits.lower = joint.limits->lower;
          limits.upper = joint.limits->upper;
        }
        if (joint.limits->velocity > 0.0) limits.velocity = joint.limits->velocity;
        if (joint.limits->effort > 0.0) limits.effort = joint.limits->effort;
      }
      DriveParameters<double> drive;
      if (joint.dynamics)
        for (const DriveTermInfo& row : kDriveTermTable) {
          if (row.urdf_dynamics == "damping") drive[row.term] = joint.dynamics->damping;
          if (row.urdf_dynamics == "friction") drive[row.term] = joint.dynamics->friction;
        }
      const int parent_body = m.parent_record < 0 ? -1 : body_of[m.parent_record];
      body_of[best] =
          model_.addBody(parent_body, m.child->name, joint.name, type, m.placement, axis,
                         Pose<double>(), linkInertia(*m.child, true), limits, drive);
    }
    // Fixed children join their body (a fixed base ignores its inertia: it does not move; a
    // floating one keeps it).
    for (const Merge& merge : merges_) {
      const int body = merge.record < 0 ? -1 : body_of[merge.record];
      if (floating_) frames.push_back({merge.link->name, body, merge.placement});
      if (body < 0) {
        if (floating_)
          base_inertia += linkInertia(*merge.link, false).transformedBy(merge.placement);
        continue;
      }
      RigidInertia<double> merged = model_.inertias()[body];
      merged += linkInertia(*merge.link, false).transformedBy(merge.placement);
      model_.setLinkInertia(body, merged);
    }
    if (floating_)
      for (int r = 0; r < count; ++r) frames.push_back({moving_[r].child->name, body_of[r], {}});
  }

  int order(const std::string& joint) const {
    const auto it = index_.joint_order.find(joint);
    return it == index_.joint_order.end() ? 1 << 30 : it->second;
  }

  const urdf::ModelInterface& urdf_;
  const std::string& file_;
  const ElementIndex& index_;
  const UrdfOptions& options_;
  std::vector<std::string>* warnings_;
  bool floating_ = false;
  std::vector<MovingJoint> moving_;
  std::vector<Merge> merges_;
  Model model_;
};

/// The line of the first "[name]" in urdfdom's message that names a known element.
int lineOfMessage(const std::string& message, const ElementIndex& index, std::string* element) {
  for (std::size_t open = message.find('['); open != std::string::npos;
       open = message.find('[', open + 1)) {
    const std::size_t close = message.find(']', open);
    if (close == std::string::npos) break;
    const std::string name = message.substr(open + 1, close - open - 1);
    if (auto it = index.joint_line.find(name); it != index.joint_line.end()) {
      *element = "joint '" + name + "'";
      return it->second;
    }
    if (auto it = index.link_line.find(name); it != index.link_line.end()) {
      *element = "link '" + name + "'";
      return it->second;
    }
  }
  return 0;
}

/// The document's first element (past the XML declaration, comments and a DOCTYPE): its name and
/// its line; ("", 0) when there is none.
std::pair<std::string, int> rootElement(const std::string& text) {
  std::size_t i = 0;
  while ((i = text.find('<', i)) != std::string::npos) {
    const bool comment = text.compare(i, 4, "<!--") == 0;
    if (comment || text.compare(i, 2, "<?") == 0 || text.compare(i, 2, "<!") == 0) {
      i = comment ? text.find("-->", i) : text.find('>', i);
      if (i == std::string::npos) break;
      ++i;
      continue;
    }
    std::size_t end = i + 1;
    while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) ||
                                 (text[end] != '\0' && std::strchr("_-:.", text[end]) != nullptr)))
      ++end;
    return {text.substr(i + 1, end - i - 1),
            1 + static_cast<int>(std::count(text.begin(), text.begin() + i, '\n'))};
  }
  return {"", 0};
}

}  // namespace

std::size_t xmlTagEnd(const std::string& text, std::size_t from) {
  char quote = 0;
  for (std::size_t j = from; j < text.size(); ++j) {
    const char c = text[j];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '>') {
      return j;
    }
  }
  return text.size();
}

namespace {
/// urdfdom's model of the text, after dynid's own checks (UTF-8, depth, another format).
urdf::ModelInterfaceSharedPtr parseUrdfModel(const std::string& text, const std::string& file,
                                             const ElementIndex& index) {
  // XML is UTF-8 unless declared otherwise, and TinyXML, under urdfdom, reads past the end of a
  // document whose names hold broken UTF-8 (found by fuzzing, under AddressSanitizer).
  if (const std::size_t bad = firstInvalidUtf8(text); bad != std::string::npos) {
    static const char* const kHex = "0123456789abcdef";
    const auto byte = static_cast<unsigned char>(text[bad]);
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + bad, '\n'));
    throw ParseError(file, line, "",
                     std::string("byte 0x") + kHex[byte >> 4] + kHex[byte & 15] +
                         " is not UTF-8 text: dynid reads URDF files as UTF-8 (save the file "
                         "as UTF-8)");
  }
  checkXmlDepth(text, file);
  // Another robot format given where a URDF is read: say which, before urdfdom's "no robot".
  if (const auto [root, line] = rootElement(text); root == "mujoco")
    throw ParseError(file, line, root,
                     "an MJCF (MuJoCo) model, not a URDF: dynid reads robots from URDF files and "
                     "dynid JSON models (docs/MODEL.md); use the robot's URDF, or write its links "
                     "as a dynid JSON model (dynid writes MJCF from a model, it does not read it)");
  else if (root == "sdf")
    throw ParseError(file, line, root,
                     "an SDFormat (Gazebo) model, not a URDF: dynid reads robots from URDF files "
                     "and dynid JSON models (docs/MODEL.md)");
  urdf::ModelInterfaceSharedPtr urdf;
  std::string error;
  {
    std::lock_guard<std::mutex> lock(console_mutex);
    CapturingHandler handler;
    console_bridge::useOutputHandler(&handler);
    try {
      urdf = urdf::parseURDF(text);
    } catch (const std::exception& e) {
      handler.errors = e.what();
    }
    console_bridge::restorePreviousOutputHandler();
    error = handler.errors;
  }
  if (!urdf || !error.empty()) {
    if (error.empty()) error = "not a valid URDF document";
    std::string element;
    const int line = lineOfMessage(error, index, &element);
    throw ParseError(file, line, element, "urdfdom: " + error);
  }
  return urdf;
}
}  // namespace

Model parseUrdf(const std::string& text, const std::string& file, const UrdfOptions& options,
                std::vector<std::string>* warnings) {
  const ElementIndex index = indexElements(text);
  const urdf::ModelInterfaceSharedPtr urdf = parseUrdfModel(text, file, index);
  return UrdfBuilder(*urdf, file, index, options, warnings).build();
}

FloatingModel parseFloatingUrdf(const std::string& text, const std::string& file,
                                const UrdfOptions& options, std::vector<std::string>* warnings) {
  const ElementIndex index = indexElements(text);
  const urdf::ModelInterfaceSharedPtr urdf = parseUrdfModel(text, file, index);
  UrdfBuilder builder(*urdf, file, index, options, warnings, true);
  Model limbs = builder.build();
  try {
    FloatingModel out(std::move(limbs), builder.base_inertia, builder.base_name);
    out.frames = std::move(builder.frames);
    return out;
  } catch (const InputError& e) {
    throw ParseError(file, 0, "link '" + builder.base_name + "'", e.what());
  }
}

FloatingModel loadFloatingUrdf(const std::string& path, const UrdfOptions& options,
                               std::vector<std::string>* warnings) {
  return parseFloatingUrdf(readFile(path), path, options, warnings);
}

Model loadUrdf(const std::string& path, const UrdfOptions& options,
               std::vector<std::string>* warnings) {
  return parseUrdf(readFile(path), path, options, warnings);
}

namespace {
std::string vec(const Eigen::Vector3d& v) {
  return formatNumber(v.x()) + " " + formatNumber(v.y()) + " " + formatNumber(v.z());
}
std::string origin(const Pose<double>& pose) {
  return "<origin xyz=\"" + vec(pose.translation) + "\" rpy=\"" +
         vec(rpyFromRotation(pose.rotation)) + "\"/>";
}
}  // namespace

std::string urdfDynamicsElement(const DriveParameters<double>& drive) {
  std::string out = "<dynamics";
  for (const DriveTermInfo& row : kDriveTermTable)
    if (!row.urdf_dynamics.empty()) {
      // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on the concatenated form.
      out.append(" ").append(row.urdf_dynamics).append("=\"");
      out.append(formatNumber(drive[row.term])).append("\"");
    }
  return out + "/>";
}

std::vector<std::string> urdfCannotCarry(const Model& model) {
  std::vector<std::string> out;
  for (const DriveTermInfo& row : kDriveTermTable)
    if (row.urdf_dynamics.empty() && model.driveTerms().has(row.term))
      out.push_back("URDF has no element for " + std::string(row.description) + " (" +
                    std::string(row.name) + "): the export goes without it; a dynid JSON model " +
                    "keeps it");
  if (model.gravity() != Eigen::Vector3d(0.0, 0.0, -9.81))  // Model's default, URDF's assumption
    out.push_back("URDF has no gravity: the model's (" + formatNumber(model.gravity()[0], 6) +
                  ", " + formatNumber(model.gravity()[1], 6) + ", " +
                  formatNumber(model.gravity()[2], 6) +
                  ") m/s^2 is not in the export, whose readers assume -9.81 along z; a dynid JSON "
                  "model keeps it");
  return out;
}

std::string modelToUrdf(const Model& model) {
  std::string base = "base_link";
  while (std::find(model.link_names.begin(), model.link_names.end(), base) !=
         model.link_names.end())
    base = "_" + base;
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n";
  out << "<!-- Exported by dynid. Link frames are joint frames; inertial origins at the centre of "
         "mass. -->\n";
  out << "<robot name=\"" << escapeXml(model.name) << "\">\n";
  out << "  <link name=\"" << escapeXml(base) << "\"/>\n";
  for (int i = 0; i < model.numJoints(); ++i) {
    // The URDF link frame is the joint frame; re-express the body inertia there.
    const RigidInertia<double> in = model.inertias()[i].transformedBy(model.body_placements()[i]);
    const Eigen::Vector3d c =
        in.mass > 0.0 ? Eigen::Vector3d(in.first_moment / in.mass) : Eigen::Vector3d::Zero();
    const Eigen::Matrix3d ic = inertiaAboutCom(in);
    out << "  <link name=\"" << escapeXml(model.link_names[i]) << "\">\n"
        << "    <inertial>\n"
        << "      <origin xyz=\"" << vec(c) << "\" rpy=\"0 0 0\"/>\n"
        << "      <mass value=\"" << formatNumber(in.mass) << "\"/>\n"
        << "      <inertia ixx=\"" << formatNumber(ic(0, 0)) << "\" ixy=\""
        << formatNumber(ic(0, 1)) << "\" ixz=\"" << formatNumber(ic(0, 2)) << "\" iyy=\""
        << formatNumber(ic(1, 1)) << "\" iyz=\"" << formatNumber(ic(1, 2)) << "\" izz=\""
        << formatNumber(ic(2, 2)) << "\"/>\n"
        << "    </inertial>\n"
        << "  </link>\n";
    const int p = model.parents()[i];
    const Pose<double> placement = p < 0 ? model.joint_placements()[i]
                                         : model.body_placements()[p] * model.joint_placements()[i];
    const JointLimits& l = model.limits[i];
    out << "  <joint name=\"" << escapeXml(model.joint_names[i]) << "\" type=\""
        << jointTypeName(model.joint_types()[i]) << "\">\n"
        << "    <parent link=\"" << escapeXml(p < 0 ? base : model.link_names[p]) << "\"/>\n"
        << "    <child link=\"" << escapeXml(model.link_names[i]) << "\"/>\n"
        << "    " << origin(placement) << "\n"
        << "    <axis xyz=\"" << vec(model.axes()[i]) << "\"/>\n";
    if (model.joint_types()[i] != JointType::kContinuous || std::isfinite(l.effort) ||
        std::isfinite(l.velocity)) {
      auto finite_or = [](double x, double fallback) { return std::isfinite(x) ? x : fallback; };
      out << "    <limit lower=\"" << formatNumber(finite_or(l.lower, -1e9)) << "\" upper=\""
          << formatNumber(finite_or(l.upper, 1e9)) << "\" effort=\""
          << formatNumber(finite_or(l.effort, 0.0)) << "\" velocity=\""
          << formatNumber(finite_or(l.velocity, 0.0)) << "\"/>\n";
    }
    if (model.driveTerms().any()) out << "    " << urdfDynamicsElement(model.drives()[i]) << "\n";
    out << "  </joint>\n";
  }
  out << "</robot>\n";
  return out.str();
}

}  // namespace dynid
