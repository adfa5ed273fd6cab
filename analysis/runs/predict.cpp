#include "analysis/runs/predict.hpp"

#include "analysis/records/document.hpp"
#include "analysis/records/upgrade.hpp"
#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"

namespace dynid {

PredictionFilter predictionFilter(const Model& model, const std::string& data_file,
                                  const Trajectory* data, const TorqueFilterChoice& choice) {
  PredictionFilter out;
  if (choice) {
    out.filter = *choice;
    out.source = out.filter.active() ? "given" : "none: given";
  } else if (data) {
    out.source = "data in memory: its torque is taken as unfiltered (give `torque_filter`)";
  } else {
    out.filter = torqueFilterOfPreparation(findPreparation(data_file), out.source);
  }
  if (!out.filter.active()) return out;
  if (!FitRows(model).leavesRowsOut()) {
    out.source += "; no friction term needs sign(dq): nothing to reproduce";
    return out;
  }
  try {
    Trajectory velocities;
    if (data) {
      velocities.time = data->time;
      velocities.dq = data->dq;
    }
    out.rows = trainingRows(model, data ? velocities : velocitiesOf(data_file, model.numJoints()),
                            out.filter);
  } catch (const InputError& e) {
    throw InputError((data ? std::string("data") : data_file) + ": " + e.what());
  }
  out.filter = out.rows->filter();
  out.reach = out.rows->reach();
  return out;
}

PredictOutcome predictRun(const PredictRequest& request) {
  PredictOutcome out;
  if (request.estimate_file.empty() == !request.model)
    throw InputError("predict needs an estimate.json or a robot model (one of them)");
  if (request.model) {
    out.model = *request.model;
    out.robot_spec = request.robot_spec;
    out.method = "model";
    if (!request.robot_spec.empty()) out.source = modelSourceOf(request.robot_spec);
  } else {
    out.model = estimateModel(request.estimate_file, request.robot_spec, &out.robot_spec,
                              &out.method, &out.band, &out.source);
    const int version =
        documentVersion(parseJson(readFile(request.estimate_file), request.estimate_file),
                        kEstimateDocument.schema_version);
    if (version < kEstimateDocument.schema_version)
      out.warnings.push_back(olderVersionNote(request.estimate_file, kEstimateDocument.kind,
                                              version, kEstimateDocument.schema_version));
  }
  {  // the rest velocities: a pass over the velocities before the streamed prediction
    const Trajectory data = restSamplesOf(request.data_file, out.model.numJoints());
    out.rest = request.rest_velocity.empty() ? measureRestVelocities(data.dq, data.time)
                                             : givenRestVelocities(request.rest_velocity, data.dq);
  }
  out.model.rest_velocities = restThresholds(out.rest);
  const PredictionFilter filter =
      predictionFilter(out.model, request.data_file, nullptr, request.torque_filter);
  out.torque_filter = filter.filter;
  out.torque_filter_source = filter.source;
  out.filter_reach = filter.reach;
  const std::optional<FitRows>& rows = filter.rows;
  const FitRows* filtered = rows ? &*rows : nullptr;
  const PredictionBand* band = out.band ? &*out.band : nullptr;
  ThreadPool pool(request.threads);
  const auto reversals = [&] {
    if (!rows) return reversalResidual(out.prediction);
    const ReversalMask compared = fittedMask(out.prediction, *rows);
    return reversalResidual(out.prediction, &compared);
  };
  if (request.raw_file.empty()) {
    out.prediction = predictFile(out.model, request.data_file, pool, request.sink,
                                 kStreamChunkSamples, band, filtered);
    out.reversals = reversals();
    return out;
  }
  const RawTorques raw = readRawTorques(request.raw_file, out.model.numJoints());
  RawTorqueComparison comparison(raw, request.sink);
  out.prediction = predictFile(out.model, request.data_file, pool, &comparison, kStreamChunkSamples,
                               band, filtered);
  out.reversals = reversals();
  out.raw = comparison.result();
  out.raw_file = request.raw_file;
  out.raw_skipped = comparison.skipped();
  return out;
}

}  // namespace dynid
