// A payload on a floating robot (a box on a quadruped's back, a tool on a mobile manipulator's
// arm; docs/FLOATING.md, "Payloads"): its ten inertial parameters on the link that carries it, from
// a dataset of the loaded robot and the model of the unloaded one.
//
// Fixed to a link, the payload adds its parameters phi to that link's ten, so every sensor set's
// rows hold W_L phi = y - W theta_model: W_L the set's rows' ten columns of the link, theta_model
// the unloaded robot's parameters (the model read: an identified one, as its errors enter phi).
// Solved for each set by least squares, weighted by the channel noise the estimate found.
#pragma once

#include <string>

#include "analysis/floating/identify.hpp"

namespace dynid {

struct FloatingPayload {
  std::string link;     // the link the payload is fixed to (a frame of the model)
  std::string body;     // the body whose frame phi is in (the link, or the body it is fixed to)
  std::string refused;  // empty: estimated; else why the rows do not determine phi
  Eigen::Matrix<double, 10, 1> phi = Eigen::Matrix<double, 10, 1>::Zero();  // m, mx, ..., Izz
  Eigen::Matrix<double, 10, 10> covariance = Eigen::Matrix<double, 10, 10>::Zero();
  double residual_scale = 0.0;
};

/// The payload on `link` from each set of `estimate` (its sets and channel variances) on `data`.
/// Throws InputError naming `payload_link` for a link the model lacks.
std::vector<FloatingPayload> floatingPayloads(const FloatingModel& model,
                                              const FloatingIdentifyOutcome& estimate,
                                              const FloatingDataset& data, const std::string& link);

/// The payload on `link` from a loaded/unloaded pair, without the robot's parameters: each set's
/// base parameters estimated on both (`loaded`, `unloaded`: the same request's outcomes), whose
/// difference is P phi (P: how the link's ten parameters enter the set's base parameters; the
/// model's kinematics alone), solved by generalized least squares with the two estimates'
/// covariances summed. residual_scale is sqrt(r^T S^-1 r / (p - 10)) over the p base parameters:
/// about 1 when only the payload changed between the two, larger when something else did (another
/// link, friction). A set refused in either, with a structural base that differs between the two
/// (other contacts or motion), or whose P has rank below 10 (the payload's parameters the set's
/// rows cannot tell apart) is refused with the reason. Throws InputError naming `payload_link`
/// for a link the model lacks, and `unloaded` when the outcomes hold other sets.
std::vector<FloatingPayload> floatingPayloadsFromPair(const FloatingModel& model,
                                                      const FloatingIdentifyOutcome& loaded,
                                                      const FloatingIdentifyOutcome& unloaded,
                                                      const std::string& link);

}  // namespace dynid
