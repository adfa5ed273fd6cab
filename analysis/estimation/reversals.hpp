// Where a model's torque residual lies in velocity. Near zero velocity (reversals, rest) a joint's
// friction sticks, dithers and breaks away: Fv dq + Fc sign(dq) fits it worst, and on real arms a
// few percent of the samples there carry a large share of the residual (docs/MODEL.md, "Friction
// at reversals").
#pragma once

#include <vector>

#include <Eigen/Core>

#include "analysis/estimation/streaming.hpp"

namespace dynid {

/// The band around zero velocity is |dq_j| < kReversalSpeedFraction rms(dq_j): relative to each
/// joint's own motion, so that it means the same on a slow wrist and a fast shoulder.
inline constexpr double kReversalSpeedFraction = 0.1;
/// A joint is flagged when the band holds at least this share of its squared residual ...
inline constexpr double kReversalResidualShare = 0.25;
/// ... and at least this many times its share of the samples (a residual spread evenly over the
/// velocities gives 1).
inline constexpr double kReversalConcentration = 4.0;

/// A joint's residual "has the shape of friction" when Fc sign(dq) + Fv dq + Fo, fitted to it by
/// least squares, explains at least this share of its squared residual (a white residual: about
/// 3 / samples; a missing friction term: most of it).
inline constexpr double kFrictionResidualShare = 0.3;

/// No joint is flagged, for either shape, whose residual RMS is below this share of its measured
/// torque's RMS: a fit to noise-free data leaves round-off (1e-16 to 1e-13 relative), whose shape
/// means nothing; a real arm's or a noisy simulation's residual is 1e-3 relative or more.
inline constexpr double kResidualAboveRoundOff = 1e-9;

struct ReversalResidual {
  int samples = 0;                 // the samples measured (a Prediction's kept samples)
  Eigen::VectorXd speed;           // per joint: the band's half width [rad/s or m/s]
  Eigen::VectorXd sample_share;    // the share of the samples in the band (0..1)
  Eigen::VectorXd residual_share;  // the share of the joint's squared residual in it (0..1)
  std::vector<int> flagged;        // 0-based joints past both marks, in joint order
  /// Per joint: the share of its squared residual that a * sign(dq) + b dq + c, fitted to it,
  /// explains (0..1); joints at kFrictionResidualShare or more, in joint order.
  Eigen::VectorXd friction_share;
  std::vector<int> friction_flagged;
};

/// The shares over the prediction's kept samples (Prediction::velocity, measured, predicted):
/// every sample of a log up to 2 kMaxPlottedSamples long, evenly spaced ones beyond. A joint that
/// never moves (rms(dq) = 0) or has no residual gets shares of 0 and is not flagged, nor is one
/// whose residual is round-off (kResidualAboveRoundOff). Empty (samples
/// 0, no vectors) for a prediction without velocities.
/// With `fitted` (joints x kept samples), only the samples whose entry is true count for the joint
/// (the rows its fit took: a joint at rest has unknown static friction, not a residual).
using ReversalMask = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>;
ReversalResidual reversalResidual(const Prediction& prediction,
                                  const ReversalMask* fitted = nullptr);

/// The mask of `rows` on a prediction's kept samples (samples 0, stride, 2 stride, ... of the set
/// `rows` describes): whether each joint's row there is fitted.
ReversalMask fittedMask(const Prediction& prediction, const FitRows& rows);

}  // namespace dynid
