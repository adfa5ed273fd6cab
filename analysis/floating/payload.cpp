#include "analysis/floating/payload.hpp"

#include "core/errors.hpp"

namespace dynid {

std::vector<FloatingPayload> floatingPayloads(const FloatingModel& model,
                                              const FloatingIdentifyOutcome& estimate,
                                              const FloatingDataset& data,
                                              const std::string& link) {
  const BodyFrame* frame = model.findFrame(link);
  if (frame == nullptr)
    throw InputError("`payload_link`: '" + link + "' is no link of '" + model.name() + "'");
  // The ten columns of the body the link belongs to (a merged link's payload is its body's).
  const int first =
      frame->body < 0
          ? 0
          : FloatingModel::limbColumn(model.limbs().parameterLayout().linkIndex(frame->body, 0));
  const std::string body = frame->body < 0
                               ? model.baseName()
                               : model.limbs().link_names[static_cast<std::size_t>(frame->body)];
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
