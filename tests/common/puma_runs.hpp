// The runs wing's tests' simulated PUMA logs (tests/runs/): the PUMA 560 with its drives' friction
// (whose joints stick at stops and reversals) on its Fourier motion, and such a log through
// prepare's defaults (its 10 Hz low-pass).
#pragma once

#include <cstdint>
#include <string>

#include "analysis/logs/prepare.hpp"
#include "analysis/runs/simulate.hpp"
#include "data/dataset_csv.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::test {

/// The PUMA with its drives on a Fourier motion of 0.5 rad, noise of noise_tau [N m] and noise_q
/// [rad], seeded.
inline SimulateRequest pumaFourier(double duration, double noise_tau, std::uint64_t seed,
                                   double noise_q = 1e-5) {
  SimulateRequest simulate;
  simulate.robot = makePuma560(true);
  simulate.fourier = true;
  simulate.amplitude = Eigen::VectorXd::Constant(6, 0.5);
  simulate.simulation.duration = duration;
  simulate.simulation.noise_q = noise_q;
  simulate.simulation.noise_tau = noise_tau;
  simulate.simulation.seed = seed;
  return simulate;
}

/// That log (0.5 N m of torque noise) written to tempPath(name) and prepared with prepare's
/// defaults, its last `validate_fraction` held out.
inline PrepareOutcome preparedPuma(double duration, std::uint64_t seed, double validate_fraction,
                                   const std::string& name) {
  const std::string raw = tempPath(name);
  writeDatasetCsv(raw, simulateRun(pumaFourier(duration, 0.5, seed)).trajectory);
  LogSource source;
  source.tables = {raw};
  source.time_column = "t";
  source.q_columns = "q*";
  source.tau_columns = "tau*";
  PrepareOptions options;
  options.validate_fraction = validate_fraction;
  return prepareLog(source, options);
}

}  // namespace dynid::test
