// The benchmarks' GC-error problem: the PUMA 560 tracking sinusoids around qn (0.5 rad, 0.15 to
// 0.5 Hz), `segments` segments of 50 RK4 steps (0.05 s at 1 kHz).
#pragma once

#include "core/controllers.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "search/gc_error.hpp"

namespace dynid::bench {

inline GcProblem pumaProblem(int segments) {
  const Model model = makePuma560();
  SinusoidalReference r;
  r.q0 = puma560Pose("qn");
  r.amplitude = Eigen::VectorXd::Constant(6, 0.5);
  r.frequency = Eigen::VectorXd::LinSpaced(6, 0.15, 0.5);
  r.phase = Eigen::VectorXd::Zero(6);
  TrackingController controller(model, r, defaultGains(model, r.q0),
                                Eigen::VectorXd::Constant(6, 1e9));
  SimulationOptions options;
  options.duration = segments * 0.05 + 0.001;
  return makeGcProblem(simulate(model, controller, options), {.num_segments = segments});
}

}  // namespace dynid::bench
