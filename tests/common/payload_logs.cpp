#include "tests/common/payload_logs.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "analysis/payload/body.hpp"
#include "analysis/payload/payload.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::test {

Eigen::Matrix<double, 10, 1> toolBody() {
  PrincipalBody body;
  body.mass = 1.2;
  body.com = Eigen::Vector3d(0.03, -0.02, 0.08);
  body.moments = Eigen::Vector3d(4e-3, 6e-3, 3e-3);
  body.axes = rotationFromKukaAbc(Eigen::Vector3d(0.3, -0.2, 0.4));
  return standardFromPrincipal(body);
}

Pose<double> pumaFlange() {
  Pose<double> p;
  p.translation = Eigen::Vector3d(0.0, 0.0, 0.05);
  p.rotation = rotationFromRpy(0.0, 0.0, M_PI / 4);
  return p;
}

Model withPayload(const Model& arm, int link, const Pose<double>& tool,
                  const Eigen::Matrix<double, 10, 1>& body) {
  Model out = arm;
  RigidInertia<double> inertia = arm.inertias()[link];
  inertia += fromStandardVector(body).transformedBy(tool);
  out.setLinkInertia(link, inertia);
  return out;
}

Trajectory payloadMotion(const Model& model, double seconds, double rate,
                         const std::vector<int>& still) {
  const int n = model.numJoints(), samples = static_cast<int>(seconds * rate) + 1;
  Trajectory t;
  t.resize(n, samples);
  for (int k = 0; k < samples; ++k) t.time[k] = k / rate;
  for (int j = 0; j < n; ++j) {
    if (std::find(still.begin(), still.end(), j) != still.end()) {
      t.q.row(j).setConstant(0.3);
      continue;
    }
    const double w = 2.0 * M_PI * (0.11 + 0.037 * j);
    for (int h = 1; h <= 3; ++h) {
      const double a = 0.5 / h, phase = 0.7 * j + h;
      for (int k = 0; k < samples; ++k) {
        const double x = h * w * t.time[k] + phase;
        t.q(j, k) += a * std::sin(x);
        t.dq(j, k) += a * h * w * std::cos(x);
        t.ddq(j, k) -= a * h * w * h * w * std::sin(x);
      }
    }
  }
  return t;
}

std::string payloadLog(const Model& model, Trajectory t, const std::string& name, double noise,
                       std::uint64_t seed, Eigen::VectorXd gain) {
  Data data(model);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, noise > 0.0 ? noise : 1.0);
  if (gain.size() == 0) gain = Eigen::VectorXd::Ones(model.numJoints());
  for (int k = 0; k < t.numSamples(); ++k) {
    t.tau.col(k) = rnea(model, data, t.q.col(k), t.dq.col(k), t.ddq.col(k));
    t.tau.col(k).array() /= gain.array();
    if (noise > 0.0)
      for (int j = 0; j < model.numJoints(); ++j) t.tau(j, k) += normal(rng);
  }
  const std::string path = tempPath(name);
  writeDatasetCsv(path, t);
  return path;
}

}  // namespace dynid::test
