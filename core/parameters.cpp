#include "core/parameters.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

std::vector<std::string> standardParameterNames(const ParameterLayout& layout) {
  std::vector<std::string> names;
  names.reserve(layout.size());
  for (int i = 0; i < layout.num_links; ++i) {
    const std::string suffix = std::to_string(i + 1);
    for (auto n : kLinkParameterNames) names.push_back(std::string(n) + suffix);
    for (int k = 0; k < kDriveTermCount; ++k)
      if (layout.drives.has(k)) names.push_back(std::string(kDriveParameterNames[k]) + suffix);
  }
  return names;
}

std::vector<std::string> driveTermsKeys(DriveTerms terms) {
  std::vector<std::string> out;
  for (int k = 0; k < kDriveTermCount; ++k)
    if (terms.has(k)) out.emplace_back(kDriveTermKeys[k]);
  return out;
}

std::string driveTermsText(DriveTerms terms) {
  std::string out;
  for (const std::string& key : driveTermsKeys(terms)) {
    if (!out.empty()) out += ',';
    out += key;
  }
  return out.empty() ? "none" : out;
}

std::string driveTermKeyList() {
  std::string out;
  for (std::string_view key : kDriveTermKeys) out += (out.empty() ? "" : ", ") + std::string(key);
  return out;
}

std::string driveTermHelp(std::string_view separator) {
  std::string out;
  for (const DriveTermInfo& row : kDriveTermTable) {
    if (!out.empty()) out += separator;
    out += std::string(row.key) + " " + std::string(row.description) + " (" + std::string(row.law) +
           ")";
  }
  return out;
}

DriveTerms parseDriveTerms(std::string_view text) {
  DriveTerms out;
  if (text == "none") return out;
  const std::string valid = "valid terms: " + driveTermKeyList() + ", or none";
  if (text.empty()) throw InputError("empty drive-term list (" + valid + ")");
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string_view key = text.substr(start, end - start);
    int found = -1;
    for (int k = 0; k < kDriveTermCount; ++k)
      if (key == kDriveTermKeys[k]) found = k;
    if (found < 0)
      throw InputError("unknown drive term '" + std::string(key) + "' (" + valid + ")");
    if (out.has(found)) throw InputError("drive term '" + std::string(key) + "' is listed twice");
    out.mask |= 1u << found;
    start = end + 1;
  }
  return out;
}

std::vector<std::string> paperParameterNames(int num_links) {
  std::vector<std::string> names;
  names.reserve(num_links * kPaperParameterCount);
  for (int i = 0; i < num_links; ++i)
    for (auto n : kPaperParameterNames) names.push_back(std::string(n) + std::to_string(i + 1));
  return names;
}

Eigen::Matrix3d inertiaAboutCom(const RigidInertia<double>& inertia) {
  if (inertia.mass == 0.0) return inertia.inertia;
  const Eigen::Matrix3d sh = skew(inertia.first_moment);
  return inertia.inertia + sh * sh / inertia.mass;
}

Eigen::Matrix<double, 7, 1> standardToPaper(const Eigen::Matrix<double, 10, 1>& standard,
                                            double* dropped_products) {
  const RigidInertia<double> inertia = fromStandardVector(standard);
  const double m = inertia.mass;
  const Eigen::Vector3d c =
      m != 0.0 ? Eigen::Vector3d(inertia.first_moment / m) : Eigen::Vector3d::Zero();
  const Eigen::Matrix3d ic = inertiaAboutCom(inertia);
  if (dropped_products != nullptr)
    *dropped_products = std::max({std::abs(ic(0, 1)), std::abs(ic(0, 2)), std::abs(ic(1, 2))});
  Eigen::Matrix<double, 7, 1> p;
  p << m, c.x(), c.y(), c.z(), ic(0, 0), ic(1, 1), ic(2, 2);
  return p;
}

std::vector<ConsistencyViolation> checkPhysicalConsistency(const RigidInertia<double>& inertia,
                                                           int link, const std::string& link_name,
                                                           double tolerance) {
  std::vector<ConsistencyViolation> out;
  auto add = [&](std::string condition, std::string detail) {
    out.push_back({link, link_name, std::move(condition), std::move(detail)});
  };
  const double m = inertia.mass;
  if (!(m >= 0.0)) add("mass >= 0", "m = " + formatNumber(m, 6));
  if (m == 0.0 && inertia.first_moment.norm() > 0.0)
    add("a massless link has no first moment",
        "|m c| = " + formatNumber(inertia.first_moment.norm(), 6));
  const Eigen::Matrix3d ic = inertiaAboutCom(inertia);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(ic, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d l = eig.eigenvalues();  // ascending
  const double tol = tolerance * std::max(std::abs(ic.trace()), 1e-300);
  if (l(0) < -tol)
    add("inertia about the centre of mass is positive semi-definite",
        "smallest principal moment = " + formatNumber(l(0), 6));
  // Triangle inequality: the two smaller principal moments sum to at least the largest.
  if (l(0) + l(1) < l(2) - tol)
    add("triangle inequality I1 + I2 >= I3 on the principal moments about the centre of mass",
        formatNumber(l(0), 6) + " + " + formatNumber(l(1), 6) + " < " + formatNumber(l(2), 6));
  return out;
}

}  // namespace dynid
