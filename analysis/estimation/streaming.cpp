#include "analysis/estimation/streaming.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <tuple>
#include <vector>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/friction.hpp"
#include "core/regressor.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "identifiability/observation.hpp"

namespace dynid {

void SampleKeeper::add(const Trajectory& chunk) {
  const int n = chunk.numJoints(), m = chunk.numSamples();
  if (kept_.numSamples() == 0) kept_.resize(n, 2 * kMaxPlottedSamples);
  if (kept_.numJoints() != n) throw InputError("SampleKeeper: samples of another joint count");
  for (int k = 0; k < m; ++k, ++seen_) {
    if (seen_ % stride_ != 0) continue;
    if (count_ == kept_.numSamples()) {  // full: keep every other sample, double the stride
      const int half = count_ / 2;
      for (int i = 0; i < half; ++i) {
        kept_.time[i] = kept_.time[2 * i];
        for (Eigen::MatrixXd* b : {&kept_.q, &kept_.dq, &kept_.ddq, &kept_.tau})
          b->col(i) = b->col(2 * i);
      }
      count_ = half;
      stride_ *= 2;
      if (seen_ % stride_ != 0) continue;
    }
    kept_.time[count_] = chunk.time[k];
    kept_.q.col(count_) = chunk.q.col(k);
    kept_.dq.col(count_) = chunk.dq.col(k);
    kept_.ddq.col(count_) = chunk.ddq.col(k);
    kept_.tau.col(count_) = chunk.tau.col(k);
    ++count_;
  }
}

Trajectory SampleKeeper::kept() const {
  Trajectory out = kept_;
  out.truncate(count_);
  return out;
}

namespace {

/// The statistics of `samples` samples from their per-joint sums of squares (residual and
/// measured) over `rows` rows per joint (each joint's compared rows); the measured RMS per joint to
/// `measured_rms` when given.
Validation validationOf(const Eigen::VectorXd& residual_squared,
                        const Eigen::VectorXd& measured_squared, long long samples,
                        const Eigen::VectorXd& rows, Eigen::VectorXd* measured_rms_out = nullptr) {
  Validation v;
  v.num_samples = static_cast<int>(samples);
  const Eigen::ArrayXd count = rows.array().max(1.0);
  v.torque_rms = (residual_squared.array() / count).sqrt().matrix();
  const Eigen::VectorXd measured_rms = (measured_squared.array() / count).sqrt().matrix();
  const double inf = std::numeric_limits<double>::infinity();
  v.relative_error = measured_rms.norm() > 0.0 ? v.torque_rms.norm() / measured_rms.norm() : inf;
  v.normalised_rms.resize(measured_rms.size());
  for (Eigen::Index j = 0; j < measured_rms.size(); ++j)
    v.normalised_rms[j] = measured_rms[j] > 0.0 ? v.torque_rms[j] / measured_rms[j] : inf;
  if (measured_rms_out != nullptr) *measured_rms_out = measured_rms;
  return v;
}

/// Per-joint sums of a prediction over every sample, and its series.
class PredictionAccumulator {
 public:
  PredictionAccumulator(const Model& model, int threads, const PredictionBand* band = nullptr,
                        const FitRows* filtered = nullptr)
      : model_(model), band_(band), filtered_(filtered), own_rows_(model) {
    work_.resize(static_cast<std::size_t>(threads));  // each made on its own thread, in add()
    const int n = model.numJoints();
    residual_squared_ = measured_squared_ = inside_ = compared_ = Eigen::VectorXd::Zero(n);
    rest_.setZero(n, kRestSums);
    band_lo_.resize(n);
    band_hi_.resize(n);
    for (int j = 0; j < n; ++j) std::tie(band_lo_[j], band_hi_[j]) = staticFrictionBand(model, j);
  }

  /// RNEA on a chunk (blocks of samples on the pool's threads), its sums, the kept samples.
  void add(const Trajectory& chunk, ThreadPool* pool, PredictionSink* sink) {
    const int m = chunk.numSamples();
    checkFiniteSamples(chunk);
    predicted_.resize(model_.numJoints(), m);
    constexpr int kBlock = 64;
    const auto body = [&](int block, int thread) {
      std::unique_ptr<Data>& own = work_[static_cast<std::size_t>(thread)];
      if (!own) own = std::make_unique<Data>(model_);  // this thread's arena: no shared lines
      Data& work = *own;
      for (int k = block * kBlock; k < std::min(m, (block + 1) * kBlock); ++k) {
        predicted_.col(k) = rnea(model_, work, chunk.q.col(k), chunk.dq.col(k), chunk.ddq.col(k));
        if (band_)
          half_width_.col(k) =
              band_->halfWidth(model_, work, chunk.q.col(k), chunk.dq.col(k), chunk.ddq.col(k));
      }
    };
    if (band_) half_width_.resize(model_.numJoints(), m);
    const int blocks = (m + kBlock - 1) / kBlock;
    if (pool)
      pool->parallelFor(blocks, body);
    else
      for (int b = 0; b < blocks; ++b) body(b, 0);
    // Against a filtered torque: the friction that needs sign(dq) through the same filter.
    matched_ = predicted_;
    if (filtered_ && filtered_->filtered())
      for (int k = 0; k < m; ++k)
        for (int j = 0; j < model_.numJoints(); ++j)
          matched_(j, k) +=
              filtered_->filteredDriveCorrection(model_, samples_ + k, j, chunk.dq(j, k));
    // Sample by sample, in order: the sums do not depend on how the data are chunked. The error
    // is over the rows a fit takes: a joint at rest whose friction needs sign(dq) holds a static
    // friction no model predicts (its rows are described apart, addRest).
    const FitRows& rows = filtered_ ? *filtered_ : own_rows_;
    for (int k = 0; k < m; ++k) {
      for (int j = 0; j < model_.numJoints(); ++j) {
        if (!rows.fitted(samples_ + k, j, chunk.dq(j, k))) continue;
        const double r = chunk.tau(j, k) - matched_(j, k);
        residual_squared_[j] += r * r;
        measured_squared_[j] += chunk.tau(j, k) * chunk.tau(j, k);
        compared_[j] += 1.0;
        if (band_ && std::abs(r) <= half_width_(j, k)) inside_[j] += 1.0;
      }
      addRest(chunk.dq.col(k), chunk.tau.col(k), matched_.col(k));
    }
    samples_ += m;
    keeper_.add(chunk);
    if (sink && band_) sink->bands(half_width_);
    if (sink) sink->samples(chunk.time, chunk.tau, predicted_);  // the model's own torque
  }

  Prediction finish() const {
    Eigen::VectorXd measured_rms;
    const Validation v =
        validationOf(residual_squared_, measured_squared_, samples_, compared_, &measured_rms);
    Prediction out = predictionOfKept(model_, keeper_, v, measured_rms);
    out.compared_rows = compared_;
    if (filtered_) addFilteredFriction(model_, *filtered_, out);
    out.rest = restPrediction();
    if (band_ && samples_ > 0) {
      // A joint with no row compared (the whole log at rest) has no coverage: NaN, not 0.
      out.band_coverage = (compared_.array() > 0.0)
                              .select(inside_.array() / compared_.array().max(1.0),
                                      std::numeric_limits<double>::quiet_NaN())
                              .matrix();
      const Trajectory kept = keeper_.kept();
      Data data(model_);
      out.band.resize(model_.numJoints(), kept.numSamples());
      for (int k = 0; k < kept.numSamples(); ++k)
        out.band.col(k) =
            band_->halfWidth(model_, data, kept.q.col(k), kept.dq.col(k), kept.ddq.col(k));
    }
    return out;
  }

 private:
  // rest_'s columns: at rest, count, residual sum and sum of squares, measured and predicted sums
  // and sums of squares, residuals inside the static band; in motion, count and residual sum of
  // squares.
  enum RestSum {
    kCount,
    kResidual,
    kResidual2,
    kMeasured,
    kMeasured2,
    kPredicted,
    kPredicted2,
    kInside,
    kMovingCount,
    kMoving2,
    kRestSums
  };

  void addRest(const Eigen::VectorXd& dq, const Eigen::VectorXd& measured,
               const Eigen::VectorXd& predicted) {
    for (Eigen::Index j = 0; j < dq.size(); ++j) {
      const double r = measured[j] - predicted[j];
      if (std::abs(dq[j]) > model_.restVelocity(static_cast<int>(j))) {
        rest_(j, kMovingCount) += 1.0;
        rest_(j, kMoving2) += r * r;
        continue;
      }
      const double lo = band_lo_[j], hi = band_hi_[j];
      const double sums[] = {1.0,
                             r,
                             r * r,
                             measured[j],
                             measured[j] * measured[j],
                             predicted[j],
                             predicted[j] * predicted[j],
                             (r >= lo && r <= hi) ? 1.0 : 0.0};
      for (int c = 0; c <= kInside; ++c) rest_(j, c) += sums[c];
    }
  }

  RestPrediction restPrediction() const {
    const Eigen::Index n = rest_.rows();
    RestPrediction out;
    out.rest_velocity.resize(n);
    for (Eigen::Index j = 0; j < n; ++j)
      out.rest_velocity[j] = model_.restVelocity(static_cast<int>(j));
    out.band_lo = band_lo_;
    out.band_hi = band_hi_;
    const Eigen::ArrayXd count = rest_.col(kCount).array().max(1.0);
    const auto spread = [&](int sum, int sum2) {
      const Eigen::ArrayXd mean = rest_.col(sum).array() / count;
      return Eigen::VectorXd((rest_.col(sum2).array() / count - mean * mean).max(0.0).sqrt());
    };
    out.samples = rest_.col(kCount);
    out.residual_mean = rest_.col(kResidual).array() / count;
    out.residual_std = spread(kResidual, kResidual2);
    out.measured_std = spread(kMeasured, kMeasured2);
    out.predicted_std = spread(kPredicted, kPredicted2);
    out.within_band = rest_.col(kInside).array() / count;
    out.moving_rms =
        (rest_.col(kMoving2).array() / rest_.col(kMovingCount).array().max(1.0)).sqrt();
    return out;
  }

  const Model& model_;
  Eigen::MatrixXd rest_;               // n x kRestSums
  Eigen::VectorXd band_lo_, band_hi_;  // each joint's static friction band
  std::vector<std::unique_ptr<Data>> work_;
  Eigen::MatrixXd predicted_;
  Eigen::VectorXd residual_squared_, measured_squared_;
  const PredictionBand* band_;
  Eigen::MatrixXd half_width_;
  Eigen::VectorXd inside_;  // per joint, compared rows inside the band
  long long samples_ = 0;
  const FitRows* filtered_ = nullptr;
  FitRows own_rows_;          // unfiltered: each row by its own sample's velocity
  Eigen::VectorXd compared_;  // per joint, the rows the statistics compare
  Eigen::MatrixXd matched_;   // predicted_ as the filtered measurement sees it
  SampleKeeper keeper_;
};

void requireJoints(const Model& model, int joints, const std::string& what) {
  if (joints != model.numJoints())
    throw InputError(what + " has " + std::to_string(joints) + " joints, robot '" + model.name +
                     "' has " + std::to_string(model.numJoints()));
}

}  // namespace

RawTorqueComparison::RawTorqueComparison(const RawTorques& raw, PredictionSink* next)
    : raw_(raw),
      next_(next),
      residual_squared_(Eigen::VectorXd::Zero(raw.tau.rows())),
      measured_squared_(Eigen::VectorXd::Zero(raw.tau.rows())) {}

void RawTorqueComparison::samples(const Eigen::VectorXd& time, const Eigen::MatrixXd& measured,
                                  const Eigen::MatrixXd& predicted) {
  if (next_ != nullptr) next_->samples(time, measured, predicted);
  const Eigen::Index n = raw_.tau.rows();
  for (Eigen::Index k = 0; k < time.size(); ++k) {
    if (have_previous_) {
      const double t0 = previous_time_, t1 = time[k];
      if (step_ == 0.0 && t1 > t0) step_ = t1 - t0;                 // the dataset's grid step
      while (at_ < raw_.time.size() && raw_.time[at_] < t0) ++at_;  // before: not bracketed
      const bool adjacent = t1 > t0 && t1 - t0 <= 1.5 * step_;
      // Across a gap nothing is compared; a raw stamp on t1 then waits for the next pair.
      for (; at_ < raw_.time.size() && (raw_.time[at_] < t1 || (adjacent && raw_.time[at_] == t1));
           ++at_) {
        if (!adjacent) continue;
        const double w = (raw_.time[at_] - t0) / (t1 - t0);
        for (Eigen::Index j = 0; j < n; ++j) {
          const double p = (1.0 - w) * previous_[j] + w * predicted(j, k);
          const double m = raw_.tau(j, at_);
          residual_squared_[j] += (m - p) * (m - p);
          measured_squared_[j] += m * m;
        }
        ++compared_;
      }
    }
    previous_ = predicted.col(k);
    previous_time_ = time[k];
    have_previous_ = true;
  }
}

Validation RawTorqueComparison::result() const {
  return validationOf(residual_squared_, measured_squared_, compared_,
                      Eigen::VectorXd::Constant(residual_squared_.size(), compared_));
}

void addDatasetFile(LeastSquaresStream& stream, const Model& model, const std::string& file,
                    ThreadPool& pool, SampleKeeper* keeper, int chunk_samples,
                    const FitRows* rows) {
  DatasetReader reader(file, model.numJoints());
  Trajectory chunk;
  while (reader.read(chunk, chunk_samples, &pool) > 0) {
    stream.addTrajectory(model, chunk, &pool, rows);
    if (keeper) keeper->add(chunk);
  }
}

Eigen::VectorXd PredictionBand::halfWidth(const Model& model, Data& data, const Eigen::VectorXd& q,
                                          const Eigen::VectorXd& dq,
                                          const Eigen::VectorXd& ddq) const {
  const Eigen::MatrixXd& Y = jointTorqueRegressor(model, data, q, dq, ddq);
  const int n = model.numJoints(), b = static_cast<int>(independent.size());
  Eigen::VectorXd y(b), out(n);
  for (int j = 0; j < n; ++j) {
    for (int c = 0; c < b; ++c) y[c] = Y(j, independent[static_cast<std::size_t>(c)]);
    // y Sigma y^T from Sigma's lower triangle, sum_k y_k (Sigma_kk y_k + 2 sum_{i>k} Sigma_ik
    // y_i), over the entries that are not zero: joint j's row is zero for the links before j
    // (and the other joints' drives), so this is about a sixth of a product with the whole
    // matrix on a 7-joint arm.
    double parameter = 0.0;
    for (int k = 0; k < b; ++k) {
      if (y[k] == 0.0) continue;
      const int below = b - k - 1;
      parameter +=
          y[k] * (covariance(k, k) * y[k] + 2.0 * covariance.col(k).tail(below).dot(y.tail(below)));
    }
    // z sqrt(y Sigma y^T + sigma^2)
    out[j] = z * std::sqrt(parameter + noise_sigma[j] * noise_sigma[j]);
  }
  return out;
}

Prediction predictFile(const Model& model, const std::string& file, ThreadPool& pool,
                       PredictionSink* sink, int chunk_samples, const PredictionBand* band,
                       const FitRows* filtered) {
  DatasetReader reader(file, model.numJoints());
  PredictionAccumulator accumulator(model, pool.numThreads(), band, filtered);
  Trajectory chunk;
  while (reader.read(chunk, chunk_samples, &pool) > 0) accumulator.add(chunk, &pool, sink);
  return accumulator.finish();
}

Prediction predictTorques(const Model& model, const Trajectory& data, ThreadPool* pool,
                          PredictionSink* sink, const PredictionBand* band,
                          const FitRows* filtered) {
  requireJoints(model, data.numJoints(), "the data");
  PredictionAccumulator accumulator(model, pool ? pool->numThreads() : 1, band, filtered);
  accumulator.add(data, pool, sink);
  return accumulator.finish();
}

Prediction predictionOfKept(const Model& model, const SampleKeeper& keeper,
                            const Validation& validation, const Eigen::VectorXd& measured_rms) {
  Prediction out;
  out.validation = validation;
  out.measured_rms = measured_rms;
  out.stride = keeper.stride();
  const Trajectory kept = keeper.kept();
  const int count = keeper.count();
  out.time = kept.time.head(count);
  out.measured = kept.tau.leftCols(count);
  out.velocity = kept.dq.leftCols(count);
  out.predicted.resize(model.numJoints(), count);
  Data work(model);
  for (int k = 0; k < count; ++k)
    out.predicted.col(k) = rnea(model, work, kept.q.col(k), kept.dq.col(k), kept.ddq.col(k));
  return out;
}

void addFilteredFriction(const Model& model, const FitRows& filtered, Prediction& prediction) {
  if (!filtered.filtered()) return;
  for (Eigen::Index k = 0; k < prediction.predicted.cols(); ++k) {
    const long long sample = k * static_cast<long long>(prediction.stride);
    for (int j = 0; j < model.numJoints(); ++j)
      prediction.predicted(j, k) +=
          filtered.filteredDriveCorrection(model, sample, j, prediction.velocity(j, k));
  }
}

}  // namespace dynid
