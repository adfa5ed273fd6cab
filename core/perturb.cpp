#include "core/perturb.hpp"

#include <cmath>
#include <random>

#include "core/errors.hpp"
#include "core/parameters.hpp"

namespace dynid {

Model perturbedModel(const Model& model, double fraction, std::uint64_t seed) {
  if (!(fraction >= 0.0 && fraction < 1.0))
    throw InputError("perturbation fraction must be in [0, 1), got " + std::to_string(fraction));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-fraction, fraction);
  Model out = model;
  for (int i = 0; i < out.numJoints(); ++i) {
    const RigidInertia<double>& inertia = out.inertias()[i];
    // Perturb in paper form (m, c, principal moments), keep the products about the COM.
    const Eigen::Matrix3d ic = inertiaAboutCom(inertia);
    Eigen::Matrix<double, 7, 1> paper = standardToPaper(toStandardVector(inertia));
    for (int k = 0; k < 7; ++k) paper(k) *= 1.0 + uniform(rng);
    RigidInertia<double> perturbed = fromStandardVector(paperToStandard(paper));
    Eigen::Matrix3d products = ic;
    products.diagonal().setZero();
    perturbed.inertia += products;
    out.setLinkInertia(i, perturbed);
    DriveParameters<double> d = out.drives()[i];
    // The drive-term table says how each term draws: the original terms always, in table order
    // (seeded results stay the same), then the newer ones only when the model carries them.
    for (const DriveTermInfo& row : kDriveTermTable)
      if (row.draw == DriveTermInfo::Draw::kAlways) d[row.term] *= 1.0 + uniform(rng);
    for (const DriveTermInfo& row : kDriveTermTable)
      if (row.draw == DriveTermInfo::Draw::kWhenEnabled && out.driveTerms().has(row.term))
        d[row.term] *= 1.0 + uniform(rng);
    out.setDrive(i, d);
  }
  return out;
}

}  // namespace dynid
