// A payload read back (dynid payload --prior): the body of a payload.json or of the payload_body
// document that `dynid payload --format json` writes.
#pragma once

#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace dynid {

/// The body's 10 standard parameters [m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz] in its
/// attachment frame, from the document's "standard" object. Throws ParseError naming `file` and
/// the field for another kind of document, a missing or non-finite value.
Eigen::Matrix<double, 10, 1> payloadBodyFrom(const nlohmann::json& document,
                                             const std::string& file);

}  // namespace dynid
