#include "analysis/runs/predict.hpp"

#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"
#include "data/dataset_csv.hpp"

namespace dynid {

PredictOutcome predictRun(const PredictRequest& request) {
  PredictOutcome out;
  if (request.estimate_file.empty() == !request.model)
    throw InputError("predict needs an estimate.json or a robot model (one of them)");
  if (request.model) {
    out.model = *request.model;
    out.robot_spec = request.robot_spec;
    out.method = "model";
  } else {
    out.model = estimateModel(request.estimate_file, request.robot_spec, &out.robot_spec,
                              &out.method, &out.band);
  }
  {  // the rest velocities: a pass over the velocities before the streamed prediction
    const Trajectory data = restSamplesOf(request.data_file, out.model.numJoints());
    out.rest = request.rest_velocity.empty() ? measureRestVelocities(data.dq, data.time)
                                             : givenRestVelocities(request.rest_velocity, data.dq);
  }
  out.model.rest_velocities = restThresholds(out.rest);
  const PredictionBand* band = out.band ? &*out.band : nullptr;
  ThreadPool pool(request.threads);
  if (request.raw_file.empty()) {
    out.prediction =
        predictFile(out.model, request.data_file, pool, request.sink, kStreamChunkSamples, band);
    out.reversals = reversalResidual(out.prediction);
    return out;
  }
  const RawTorques raw = readRawTorques(request.raw_file, out.model.numJoints());
  RawTorqueComparison comparison(raw, request.sink);
  out.prediction =
      predictFile(out.model, request.data_file, pool, &comparison, kStreamChunkSamples, band);
  out.reversals = reversalResidual(out.prediction);
  out.raw = comparison.result();
  out.raw_file = request.raw_file;
  out.raw_skipped = comparison.skipped();
  return out;
}

}  // namespace dynid
