#include "data/panda.hpp"

#include <array>
#include <numbers>

namespace dynid {

namespace {
// Modified DH (Franka's documentation; Gaz et al. 2019): a_{i-1} [m], d_i [m], alpha_{i-1} [rad].
constexpr std::array<double, 7> kA = {0.0, 0.0, 0.0, 0.0825, -0.0825, 0.0, 0.088};
constexpr std::array<double, 7> kD = {0.333, 0.0, 0.316, 0.0, 0.384, 0.0, 0.0};
constexpr std::array<double, 7> kAlpha = {0.0,
                                          -std::numbers::pi / 2,
                                          std::numbers::pi / 2,
                                          std::numbers::pi / 2,
                                          -std::numbers::pi / 2,
                                          std::numbers::pi / 2,
                                          std::numbers::pi / 2};
// Franka's joint limits: position [rad], velocity [rad/s], acceleration [rad/s^2], torque [N m].
constexpr std::array<double, 7> kLower = {-2.8973, -1.7628, -2.8973, -3.0718,
                                          -2.8973, -0.0175, -2.8973};
constexpr std::array<double, 7> kUpper = {2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973};
constexpr std::array<double, 7> kVelocity = {2.1750, 2.1750, 2.1750, 2.1750,
                                             2.6100, 2.6100, 2.6100};
constexpr std::array<double, 7> kAcceleration = {15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0};
constexpr std::array<double, 7> kEffort = {87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0};
// Gaz et al. 2019, supplementary Tables VIII and IX: mass [kg], centre of mass in the link frame
// [m], inertia about the centre of mass in link axes (Ixx, Ixy, Ixz, Iyy, Iyz, Izz) [kg m^2].
constexpr std::array<double, 7> kMass = {4.970684, 0.646926, 3.228604,   3.587895,
                                         1.225946, 1.666555, 7.35522e-01};
constexpr std::array<std::array<double, 3>, 7> kCom = {{{3.875e-03, 2.081e-03, 0.0},
                                                        {-3.141e-03, -2.872e-02, 3.495e-03},
                                                        {2.7518e-02, 3.9252e-02, -6.6502e-02},
                                                        {-5.317e-02, 1.04419e-01, 2.7454e-02},
                                                        {-1.1953e-02, 4.1065e-02, -3.8437e-02},
                                                        {6.0149e-02, -1.4117e-02, -1.0517e-02},
                                                        {1.0517e-02, -4.252e-03, 6.1597e-02}}};
constexpr std::array<std::array<double, 6>, 7> kInertia = {
    {{7.0337e-01, -1.3900e-04, 6.7720e-03, 7.0661e-01, 1.9169e-02, 9.1170e-03},
     {7.9620e-03, -3.9250e-03, 1.0254e-02, 2.8110e-02, 7.0400e-04, 2.5995e-02},
     {3.7242e-02, -4.7610e-03, -1.1396e-02, 3.6155e-02, -1.2805e-02, 1.0830e-02},
     {2.5853e-02, 7.7960e-03, -1.3320e-03, 1.9552e-02, 8.6410e-03, 2.8323e-02},
     {3.5549e-02, -2.1170e-03, -4.0370e-03, 2.9474e-02, 2.2900e-04, 8.6270e-03},
     {1.9640e-03, 1.0900e-04, -1.1580e-03, 4.3540e-03, 3.4100e-04, 5.4330e-03},
     {1.2516e-02, -4.2800e-04, -1.1960e-03, 1.0027e-02, -7.4100e-04, 4.8150e-03}}};
}  // namespace

DhModel pandaDh(bool drives) {
  DhModel dh;
  dh.name = "panda";
  dh.convention = DhConvention::kModified;
  if (drives) dh.drive_terms = kPandaDriveTerms;
  for (int i = 0; i < 7; ++i) {
    DhRow r;
    r.joint_name = "joint" + std::to_string(i + 1);
    r.link_name = "link" + std::to_string(i + 1);
    r.a = kA[i];
    r.d = kD[i];
    r.alpha = kAlpha[i];
    r.limits = {kLower[i], kUpper[i], kVelocity[i], kAcceleration[i], kEffort[i]};
    const auto& I = kInertia[i];
    Eigen::Matrix3d about_com;
    about_com << I[0], I[1], I[2], I[1], I[3], I[4], I[2], I[4], I[5];
    r.inertia =
        inertiaFromCom(kMass[i], Eigen::Vector3d(kCom[i][0], kCom[i][1], kCom[i][2]), about_com);
    dh.rows.push_back(r);
  }
  return dh;
}

Model makePanda(bool drives) { return modelFromDh(pandaDh(drives)); }

}  // namespace dynid
