#include "analysis/floating/payload.hpp"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {

namespace {
/// The body a link belongs to (a merged link's payload is its body's) and its ten columns' first.
struct PayloadBody {
  std::string name;
  int first = 0;
};
PayloadBody payloadBody(const FloatingModel& model, const std::string& link) {
  const BodyFrame* frame = model.findFrame(link);
  if (frame == nullptr)
    throw InputError("`payload_link`: '" + link + "' is no link of '" + model.name() + "'");
  if (frame->body < 0) return {model.baseName(), 0};
  return {model.limbs().link_names[static_cast<std::size_t>(frame->body)],
          FloatingModel::limbColumn(model.limbs().parameterLayout().linkIndex(frame->body, 0))};
}

/// Why a pair's set gives no payload, or empty.
std::string pairRefusal(const FloatingSetEstimate& l, const FloatingSetEstimate& u) {
  if (!l.refused.empty()) return "the loaded data: " + l.refused;
  if (!u.refused.empty()) return "the unloaded data: " + u.refused;
  if (l.base.base.numBase() != u.base.base.numBase() ||
      l.base.base.independent != u.base.base.independent)
    return "the two datasets' base parameters differ (other contacts or motion)";
  return "";
}

/// phi from the base parameters' difference: delta = P phi, weighted by S^-1.
void solvePair(const Eigen::MatrixXd& P, const Eigen::VectorXd& delta, const Eigen::MatrixXd& S,
               FloatingPayload& p) {
  // Noise-free estimates have no covariance: unweighted, and phi's covariance zero.
  const bool exact = !(S.trace() > 0.0);
  Eigen::MatrixXd A = P;
  Eigen::VectorXd b = delta;
  if (!exact) {
    const Eigen::LLT<Eigen::MatrixXd> llt(S);
    if (llt.info() != Eigen::Success) {
      p.refused = "the two estimates' covariance is not positive definite";
      return;
    }
    A = llt.matrixL().solve(P);
    b = llt.matrixL().solve(delta);
  }
  // The rank of the whitened P, its columns at unit norm (the rank rule's 1e-8).
  const Eigen::VectorXd norms = A.colwise().norm().transpose();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(
      A * norms.cwiseMax(1e-300).cwiseInverse().asDiagonal());
  qr.setThreshold(1e-8);
  if (qr.rank() < kLinkParameterCount) {
    p.refused = "the set's base parameters see " + std::to_string(qr.rank()) +
                " combinations of the payload's 10 parameters, not each one";
    return;
  }
  const Eigen::MatrixXd information = A.transpose() * A;
  p.covariance = information.inverse();
  p.phi = p.covariance * (A.transpose() * b);
  const Eigen::Index dof = A.rows() - kLinkParameterCount;
  p.residual_scale = dof > 0 && !exact ? std::sqrt((A * p.phi - b).squaredNorm() / dof) : 0.0;
  if (exact) p.covariance.setZero();
}
}  // namespace

std::vector<FloatingPayload> floatingPayloadsFromPair(const FloatingModel& model,
                                                      const FloatingIdentifyOutcome& loaded,
                                                      const FloatingIdentifyOutcome& unloaded,
                                                      const std::string& link) {
  const PayloadBody body = payloadBody(model, link);
  if (loaded.sets.size() != unloaded.sets.size())
    throw InputError("`unloaded`: its estimate has " + std::to_string(unloaded.sets.size()) +
                     " sensor sets, the loaded one's " + std::to_string(loaded.sets.size()) +
                     ": the two datasets must measure the same sensors");
  std::vector<FloatingPayload> out;
  for (std::size_t k = 0; k < loaded.sets.size(); ++k) {
    const FloatingSetEstimate& l = loaded.sets[k];
    const FloatingSetEstimate& u = unloaded.sets[k];
    if (l.base.set != u.base.set)
      throw InputError("`unloaded`: its sensor sets differ from the loaded data's");
    FloatingPayload p;
    p.link = link;
    p.body = body.name;
    p.refused = pairRefusal(l, u);
    if (p.refused.empty()) {
      // P's columns: the base parameters of each of the body's ten standard parameters alone.
      Eigen::MatrixXd P(l.base.base.numBase(), kLinkParameterCount);
      for (int j = 0; j < kLinkParameterCount; ++j)
        P.col(j) =
            l.base.base.project(Eigen::VectorXd::Unit(model.numParameters(), body.first + j));
      solvePair(P, l.fit.beta - u.fit.beta, l.fit.covariance + u.fit.covariance, p);
    }
    out.push_back(p);
  }
  return out;
}

std::vector<FloatingPayload> floatingPayloads(const FloatingModel& model,
                                              const FloatingIdentifyOutcome& estimate,
                                              const FloatingDataset& data,
                                              const std::string& link) {
  const PayloadBody payload_body = payloadBody(model, link);
  const int first = payload_body.first;
  const std::string& body = payload_body.name;
  const Eigen::VectorXd theta = model.standardParameters();
  FloatingData workspace(model);
  std::vector<FloatingPayload> out;
  for (const FloatingSetEstimate& s : estimate.sets) {
    FloatingPayload p;
    p.link = link;
    p.body = body;
    std::vector<FloatingMeasurement> samples;
    std::vector<Eigen::MatrixXd> W;
    std::vector<Eigen::VectorXd> y;
    for (int k = 0; k < data.numSamples(); ++k) {
      samples.push_back(
          floatingMeasurement(model, workspace, data, estimate.contacts, s.base.set, k));
      const FloatingMeasurement& m = samples.back();
      const Eigen::MatrixXd rows = sensorRows(s.base.set, m.Y, m.J);
      W.push_back(rows.middleCols(first, kLinkParameterCount));
      y.push_back(sensorMeasurements(s.base.set, m.tau, m.J, m.forces) - rows * theta);
    }
    try {
      const bool weighted = estimate.method != FloatingMethod::kOls && s.refused.empty();
      const FloatingFit fit =
          fitFloatingRows(s.base.set, samples, W, y, weighted ? &s.variances : nullptr);
      p.phi = fit.beta;
      p.covariance = fit.covariance;
      p.residual_scale = fit.residual_scale;
    } catch (const InputError& e) {
      p.refused = e.what();
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace dynid
