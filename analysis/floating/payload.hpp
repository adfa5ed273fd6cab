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

}  // namespace dynid
