#include "data/urdf_writeback.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/parameters.hpp"
#include "data/io.hpp"
#include "data/urdf.hpp"

namespace dynid {

namespace {

/// One XML element's extent in the text: [begin, end) from '<' to past its closing '>', and for
/// elements with content, [inner_begin, inner_end) between the tags.
struct Element {
  std::string tag, name;  // tag name and the value of its name="" attribute ("" if none)
  int depth = 0;          // 0: the root element
  int parent = -1;        // index into the element list
  std::size_t begin = 0, end = 0, inner_begin = 0, inner_end = 0;
  bool self_closing = false;
};

/// A small scanner over the URDF text: elements, attributes' quotes, comments, CDATA,
/// processing instructions and declarations. It finds extents only; urdfdom has already
/// validated the document.
class Scanner {
 public:
  Scanner(const std::string& text, const std::string& file) : text_(text), file_(file) {}

  std::vector<Element> scan() {
    std::vector<Element> out;
    std::vector<int> open;
    std::size_t pos = 0;
    while ((pos = text_.find('<', pos)) != std::string::npos) {
      if (startsWith(pos, "<!--")) {
        pos = skipPast(pos, "-->");
      } else if (startsWith(pos, "<![CDATA[")) {
        pos = skipPast(pos, "]]>");
      } else if (startsWith(pos, "<?")) {
        pos = skipPast(pos, "?>");
      } else if (startsWith(pos, "<!")) {
        pos = skipPast(pos, ">");
      } else if (startsWith(pos, "</")) {
        const std::size_t close = skipPast(pos, ">");
        if (open.empty()) fail(pos, "a closing tag without an opening one");
        Element& e = out[open.back()];
        e.inner_end = pos;
        e.end = close;
        open.pop_back();
        pos = close;
      } else {
        Element e;
        e.begin = pos;
        std::size_t i = pos + 1;
        while (i < text_.size() && !isSpace(text_[i]) && text_[i] != '>' && text_[i] != '/') ++i;
        e.tag = text_.substr(pos + 1, i - pos - 1);
        // Attributes up to the tag's '>' (quotes may contain '>').
        const std::size_t tag_end = xmlTagEnd(text_, i);
        if (tag_end >= text_.size()) fail(pos, "an unterminated tag");
        e.name = attribute(text_.substr(i, tag_end - i), "name");
        e.self_closing = text_[tag_end - 1] == '/';
        e.depth = static_cast<int>(open.size());
        e.parent = open.empty() ? -1 : open.back();
        e.inner_begin = tag_end + 1;
        out.push_back(e);
        if (e.self_closing)
          out.back().end = out.back().inner_end = tag_end + 1;
        else
          open.push_back(static_cast<int>(out.size()) - 1);
        pos = tag_end + 1;
      }
    }
    if (!open.empty()) fail(out[open.back()].begin, "an element that is never closed");
    return out;
  }

  /// The value of attribute `key` in an attribute list, "" when absent.
  static std::string attribute(const std::string& attributes, const std::string& key) {
    for (std::size_t at = attributes.find(key); at != std::string::npos;
         at = attributes.find(key, at + 1)) {
      if (at > 0 && !isSpace(attributes[at - 1])) continue;
      std::size_t i = at + key.size();
      while (i < attributes.size() && isSpace(attributes[i])) ++i;
      if (i >= attributes.size() || attributes[i] != '=') continue;
      ++i;
      while (i < attributes.size() && isSpace(attributes[i])) ++i;
      if (i >= attributes.size() || (attributes[i] != '"' && attributes[i] != '\'')) continue;
      const std::size_t close = attributes.find(attributes[i], i + 1);
      if (close == std::string::npos) return "";
      return attributes.substr(i + 1, close - i - 1);
    }
    return "";
  }

 private:
  static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
  bool startsWith(std::size_t pos, const char* prefix) const {
    return text_.compare(pos, std::char_traits<char>::length(prefix), prefix) == 0;
  }
  std::size_t skipPast(std::size_t pos, const char* terminator) const {
    const std::size_t at = text_.find(terminator, pos);
    if (at == std::string::npos) fail(pos, std::string("no closing '") + terminator + "'");
    return at + std::char_traits<char>::length(terminator);
  }
  [[noreturn]] void fail(std::size_t pos, const std::string& message) const {
    const int line = 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + pos, '\n'));
    throw ParseError(file_, line, "", message);
  }

  const std::string& text_;
  const std::string& file_;
};

/// Indentation of the line holding `pos` (its leading blanks).
std::string indentAt(const std::string& text, std::size_t pos) {
  const std::size_t line = text.rfind('\n', pos);
  const std::size_t start = line == std::string::npos ? 0 : line + 1;
  std::size_t i = start;
  while (i < pos && (text[i] == ' ' || text[i] == '\t')) ++i;
  return text.substr(start, i - start);
}

std::string inertialXml(const RigidInertia<double>& link, const std::string& indent,
                        const std::string& step) {
  const double m = link.mass;
  const Eigen::Vector3d c =
      m > 0.0 ? Eigen::Vector3d(link.first_moment / m) : Eigen::Vector3d::Zero();
  const Eigen::Matrix3d ic = inertiaAboutCom(link);
  std::ostringstream out;
  out << "<inertial>\n"
      << indent << step << "<origin xyz=\"" << formatNumber(c.x()) << " " << formatNumber(c.y())
      << " " << formatNumber(c.z()) << "\" rpy=\"0 0 0\"/>\n"
      << indent << step << "<mass value=\"" << formatNumber(m) << "\"/>\n"
      << indent << step << "<inertia ixx=\"" << formatNumber(ic(0, 0)) << "\" ixy=\""
      << formatNumber(ic(0, 1)) << "\" ixz=\"" << formatNumber(ic(0, 2)) << "\" iyy=\""
      << formatNumber(ic(1, 1)) << "\" iyz=\"" << formatNumber(ic(1, 2)) << "\" izz=\""
      << formatNumber(ic(2, 2)) << "\"/>\n"
      << indent << "</inertial>";
  return out.str();
}

/// A replacement of text [begin, end) by `with`.
struct Edit {
  std::size_t begin, end;
  std::string with;
};

/// Where a child element `tag` of `parent` is, or -1.
int childOf(const std::vector<Element>& elements, int parent, const std::string& tag) {
  for (int k = parent + 1; k < static_cast<int>(elements.size()); ++k) {
    if (elements[k].begin >= elements[parent].end) break;
    if (elements[k].parent == parent && elements[k].tag == tag) return k;
  }
  return -1;
}

/// An edit that puts `xml` as element `tag` of `parent`: replacing the existing one, or inserted
/// before the parent's closing tag (a self-closing parent is opened).
Edit placeChild(const std::string& text, const std::vector<Element>& elements, int parent,
                const std::string& tag, const std::string& xml_for_indent_of_child) {
  const Element& p = elements[parent];
  const int existing = childOf(elements, parent, tag);
  if (existing >= 0)
    return {elements[existing].begin, elements[existing].end, xml_for_indent_of_child};
  const std::string indent = indentAt(text, p.begin);
  if (p.self_closing) {
    // <link name="x"/> -> <link name="x">\n  child\n</link>
    std::size_t slash = p.end - 2;
    return {slash, p.end,
            ">\n" + indent + "  " + xml_for_indent_of_child + "\n" + indent + "</" + p.tag + ">"};
  }
  return {p.inner_end, p.inner_end, "  " + xml_for_indent_of_child + "\n" + indent};
}

}  // namespace

std::string urdfWithParameters(const std::string& urdf_text, const std::string& file,
                               const Model& identified) {
  const int n = identified.numJoints();
  for (int i = 0; i < n; ++i) {
    const auto violations =
        checkPhysicalConsistency(identified.inertias()[i], i, identified.link_names[i]);
    if (!violations.empty())
      throw InputError("link '" + identified.link_names[i] + "' is not physically consistent (" +
                       violations.front().condition + ": " + violations.front().detail +
                       "): a URDF cannot hold it");
  }
  const std::vector<Element> elements = Scanner(urdf_text, file).scan();
  std::map<std::string, int> link_at, joint_at;
  for (int k = 0; k < static_cast<int>(elements.size()); ++k) {
    if (elements[k].depth != 1) continue;
    if (elements[k].tag == "link") link_at.emplace(elements[k].name, k);
    if (elements[k].tag == "joint") joint_at.emplace(elements[k].name, k);
  }
  for (int i = 0; i < n; ++i) {
    if (!link_at.count(identified.link_names[i]))
      throw ParseError(file, 0, "link '" + identified.link_names[i] + "'",
                       "is not in the file: the model was not loaded from it");
    if (!joint_at.count(identified.joint_names[i]))
      throw ParseError(file, 0, "joint '" + identified.joint_names[i] + "'",
                       "is not in the file: the model was not loaded from it");
  }
  // The fixed children's share of each body: the file with the moving links' <inertial> removed.
  std::vector<Edit> removals;
  for (int i = 0; i < n; ++i) {
    const int inertial = childOf(elements, link_at[identified.link_names[i]], "inertial");
    if (inertial >= 0) removals.push_back({elements[inertial].begin, elements[inertial].end, ""});
  }
  const auto apply = [&](std::vector<Edit> edits) {
    std::sort(edits.begin(), edits.end(),
              [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
    std::string out = urdf_text;
    for (const Edit& e : edits) out.replace(e.begin, e.end - e.begin, e.with);
    return out;
  };
  const Model children = parseUrdf(apply(removals), file);
  if (children.numJoints() != n) throw ParseError(file, 0, "", "the file does not match the model");

  std::vector<Edit> edits;
  const DriveTerms terms = identified.driveTerms();
  for (int i = 0; i < n; ++i) {
    const int j =
        children.numJoints() > i && children.link_names[i] == identified.link_names[i] ? i : -1;
    if (j < 0)
      throw ParseError(file, 0, "link '" + identified.link_names[i] + "'",
                       "is not body " + std::to_string(i + 1) +
                           " of the file: the model was not "
                           "loaded from it");
    RigidInertia<double> own;
    const RigidInertia<double>& body = identified.inertias()[i];
    const RigidInertia<double>& rest = children.inertias()[j];
    own.mass = body.mass - rest.mass;
    own.first_moment = body.first_moment - rest.first_moment;
    own.inertia = body.inertia - rest.inertia;
    const auto violations = checkPhysicalConsistency(own, i, identified.link_names[i], 1e-9);
    if (!violations.empty())
      throw InputError("link '" + identified.link_names[i] +
                       "': the links fixed to it carry more than the identified body (" +
                       violations.front().condition + ": " + violations.front().detail +
                       "); move their <inertial> into it by hand or remove them");
    const int link = link_at[identified.link_names[i]];
    const std::string indent = indentAt(urdf_text, elements[link].begin) + "  ";
    edits.push_back(
        placeChild(urdf_text, elements, link, "inertial", inertialXml(own, indent, "  ")));
    // The URDF-mapped terms the model carries; the file's own value for those it does not (the
    // loader always reads them).
    DriveParameters<double> dynamics = children.drives()[j];
    bool carried = false;
    for (const DriveTermInfo& row : kDriveTermTable)
      if (!row.urdf_dynamics.empty() && terms.has(row.term)) {
        dynamics[row.term] = identified.drives()[i][row.term];
        carried = true;
      }
    if (carried)
      edits.push_back(placeChild(urdf_text, elements, joint_at[identified.joint_names[i]],
                                 "dynamics", urdfDynamicsElement(dynamics)));
  }
  return apply(edits);
}

}  // namespace dynid

namespace dynid {

std::string urdfWithFixedBody(const std::string& urdf_text, const std::string& file,
                              const std::string& parent_link, const std::string& name,
                              const Pose<double>& origin, const RigidInertia<double>& body) {
  const auto violations = checkPhysicalConsistency(body, 0, name);
  if (!violations.empty() || !(body.mass > 0.0))
    throw InputError("the body '" + name + "' is not physically consistent" +
                     (violations.empty() ? std::string(" (mass <= 0)")
                                         : " (" + violations.front().condition + ": " +
                                               violations.front().detail + ")") +
                     ": a URDF cannot hold it");
  const std::vector<Element> elements = Scanner(urdf_text, file).scan();
  std::set<std::string> links, joints;
  int root = -1;
  for (int k = 0; k < static_cast<int>(elements.size()); ++k) {
    if (elements[k].depth == 0 && elements[k].tag == "robot") root = k;
    if (elements[k].depth != 1) continue;
    if (elements[k].tag == "link") links.insert(elements[k].name);
    if (elements[k].tag == "joint") joints.insert(elements[k].name);
  }
  if (root < 0 || elements[root].self_closing)
    throw ParseError(file, 0, "robot", "no <robot> element to add the body to");
  if (!links.count(parent_link))
    throw ParseError(file, 0, "link '" + parent_link + "'", "is not in the file");
  // Names not taken yet: name, name_2, ...
  std::string link = name, joint = name + "_joint";
  for (int suffix = 2; links.count(link) || joints.count(joint); ++suffix) {
    link = name + "_" + std::to_string(suffix);
    joint = link + "_joint";
  }
  const Eigen::Vector3d rpy = rpyFromRotation(origin.rotation);
  const std::string indent = indentAt(urdf_text, elements[root].inner_end) + "  ";
  std::ostringstream xml;
  xml << indent << "<!-- added by dynid payload: the identified payload -->\n"
      << indent << "<link name=\"" << escapeXml(link) << "\">\n"
      << indent << "  " << inertialXml(body, indent + "  ", "  ") << "\n"
      << indent << "</link>\n"
      << indent << "<joint name=\"" << escapeXml(joint) << "\" type=\"fixed\">\n"
      << indent << "  <parent link=\"" << escapeXml(parent_link) << "\"/>\n"
      << indent << "  <child link=\"" << escapeXml(link) << "\"/>\n"
      << indent << "  <origin xyz=\"" << formatNumber(origin.translation.x()) << " "
      << formatNumber(origin.translation.y()) << " " << formatNumber(origin.translation.z())
      << "\" rpy=\"" << formatNumber(rpy.x()) << " " << formatNumber(rpy.y()) << " "
      << formatNumber(rpy.z()) << "\"/>\n"
      << indent << "</joint>\n";
  std::string out = urdf_text;
  out.insert(elements[root].inner_end, xml.str());
  return out;
}

}  // namespace dynid
