// Models and states shared by the tests, all built in code and seeded: random trees, a planar 2R
// arm with closed-form dynamics, and the PUMA 560.
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include <Eigen/Core>

#include "core/controllers.hpp"
#include "core/model.hpp"
#include "core/trajectory.hpp"

namespace dynid::test {

struct RandomTreeOptions {
  int num_bodies = 7;
  bool chain = false;           // each body's parent is the previous one
  bool prismatic = true;        // some joints prismatic
  bool general_axes = true;     // some axes not along x, y or z
  bool body_placements = true;  // some DH-style placements after the joint
  bool drives = false;          // random rotor inertia and friction (with offsets)
};

/// A random, physically consistent tree (masses 0.5..5 kg, centres within 0.2 m, principal moments
/// satisfying the triangle inequality), reproducible from the seed.
Model randomTree(std::uint64_t seed, const RandomTreeOptions& options = {});

/// A random tree (randomTree's inertias, drives when asked) whose 12 joints turn about z and whose
/// joint placements rotate by signed permutations, two joints for each of the six permutations
/// (the permuted paths of ABA and CRBA), with random signs and translations; joints 0 and 1 are
/// roots and every body below has two children.
Model permutedTree(std::uint64_t seed, bool drives);

/// Planar 2R arm in the x-y plane, joints about z, gravity -9.81 along y (in the plane):
/// link i of length l_i has mass m_i at distance lc_i along its x axis and inertia Izz_i about its
/// centre of mass.
struct Planar2R {
  double m1 = 1.3, m2 = 0.8, l1 = 0.7, lc1 = 0.35, lc2 = 0.25, I1 = 0.05, I2 = 0.02;
  double g = 9.81;
  Model model() const;
  /// Closed-form M(q), C(q, dq) dq and g(q) of the textbook (Spong, Hutchinson, Vidyasagar).
  Eigen::Matrix2d massMatrix(const Eigen::Vector2d& q) const;
  Eigen::Vector2d coriolis(const Eigen::Vector2d& q, const Eigen::Vector2d& dq) const;
  Eigen::Vector2d gravity(const Eigen::Vector2d& q) const;
};

/// The PUMA's GC sinusoidal controller around qn: every joint at `amplitude` [rad], frequencies
/// evenly spaced over [f_low, f_high] Hz, zero phase, default gains, no torque limit.
TrackingController pumaSinusoidController(const Model& model, double amplitude, double f_low,
                                          double f_high);
/// That controller simulated for `duration` s (RK4, 1 ms, recorded at 1 kHz, no noise).
Trajectory pumaSinusoidTrajectory(const Model& model, double duration, double amplitude,
                                  double f_low, double f_high);
/// The search tests' recording: the PUMA 560 tracking sinusoids of 0.5 rad at 0.2-0.6 Hz.
Trajectory pumaSearchTrajectory(double duration = 6.0);

/// Uniform random vector in [-scale, scale]^n.
Eigen::VectorXd randomVector(std::mt19937_64& rng, int n, double scale);

/// A unique file path under the build's test-tmp directory (the file is not created).
std::string tempPath(const std::string& name);
/// Writes `text` to a fresh tempPath(name) and returns the path.
std::string writeTemp(const std::string& name, const std::string& text);

}  // namespace dynid::test
