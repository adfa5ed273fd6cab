// Datasets streamed in chunks of samples: what reads a log of any length (identify, identifiability
// --data, predict, identify --validate) in memory independent of its length, on all threads, with
// results that do not depend on the thread count or the chunk size.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/records/raw_torques.hpp"
#include "core/data.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/trajectory.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {

/// Samples per chunk: large enough to keep both threads busy between reads, small enough that a
/// chunk's regressor rows stay in the last-level cache (4096 x ~100 columns x 8 B per joint).
inline constexpr int kStreamChunkSamples = 2048;

/// Samples kept for figures: every sample up to twice this many, then every stride-th sample (the
/// stride doubling as the data grow), between this many and twice as many.
inline constexpr int kMaxPlottedSamples = 4096;

/// A prediction's 95 % band: the base parameters' covariance carried to the torque, plus the
/// residual noise, half_width_j = z sqrt(y_j Sigma y_j^T + sigma_j^2), with y_j joint j's row of
/// the base regressor W1 = Y(:, independent) at the sample (W theta = W1 beta for any theta).
struct PredictionBand {
  std::vector<int> independent;  // standard-parameter index of each base parameter's column
  Eigen::MatrixXd covariance;    // of the base parameters (num_base x num_base; symmetric)
  Eigen::VectorXd noise_sigma;   // per joint [N m]
  double z = 1.959963984540054;  // the two-sided 95 % normal quantile
  /// The half widths at one sample (n entries). Overwrites data.Y.
  Eigen::VectorXd halfWidth(const Model& model, Data& data, const Eigen::VectorXd& q,
                            const Eigen::VectorXd& dq, const Eigen::VectorXd& ddq) const;
};

/// A prediction at rest, per joint: the samples whose |dq| is within the model's rest velocity,
/// where the drive terms that need sign(dq) are static friction (predicted as zero, known only to
/// lie in the static band [band_lo, band_hi], core/friction.hpp).
struct RestPrediction {
  Eigen::VectorXd rest_velocity;     // the model's [rad/s or m/s]
  Eigen::VectorXd samples;           // at rest
  Eigen::VectorXd band_lo, band_hi;  // the static friction band [N m]
  /// At rest: the residual's mean and standard deviation, the measured torque's standard
  /// deviation and the predicted torque's, and the share of residuals inside the band [N m; 0-1].
  Eigen::VectorXd residual_mean, residual_std, measured_std, predicted_std, within_band;
  Eigen::VectorXd moving_rms;  // the residual RMS of the samples in motion [N m]
};

/// A model's torques on a dataset, against the measured ones: statistics over every sample, and
/// evenly spaced samples for figures.
struct Prediction {
  RestPrediction rest;
  /// Residual RMS, normalised RMS, relative error: per joint over the rows a fit takes (FitRows: a
  /// joint at rest whose friction needs sign(dq) holds a static friction no model predicts, and
  /// `rest` describes those rows), every row where the model has no such friction.
  Validation validation;
  Eigen::VectorXd measured_rms;         // per joint, over the same rows [N m]
  Eigen::VectorXd compared_rows;        // per joint, the rows those statistics compare
  int stride = 1;                       // the series holds samples 0, stride, 2 stride, ...
  Eigen::VectorXd time;                 // the series: kept samples' time [s],
  Eigen::MatrixXd measured, predicted;  // and torques (n x kept) [N m]
  Eigen::MatrixXd velocity;             // and velocities dq (n x kept) [rad/s or m/s]
  /// With a band: per joint, the share of compared rows whose measured torque lies inside it, and
  /// the kept samples' half widths (n x kept) [N m]; empty otherwise. NaN for a joint with no
  /// row compared.
  Eigen::VectorXd band_coverage;
  Eigen::MatrixXd band;
};

/// Evenly spaced samples of a stream: every stride-th sample, the stride doubling (every other
/// kept sample dropped) whenever 2 * kMaxPlottedSamples would be exceeded. The same samples for
/// any division of the stream into chunks.
class SampleKeeper {
 public:
  /// Offers the next samples of the stream.
  void add(const Trajectory& chunk);
  /// The kept samples, in order: samples 0, stride(), 2 stride(), ... of the stream.
  Trajectory kept() const;
  int count() const { return count_; }
  int stride() const { return stride_; }

 private:
  Trajectory kept_;  // capacity 2 kMaxPlottedSamples
  int count_ = 0;    // kept samples in use
  long long seen_ = 0;
  int stride_ = 1;
};

/// Receives a prediction's samples in order, chunk by chunk (predict's per-sample CSV).
class PredictionSink {
 public:
  virtual ~PredictionSink() = default;
  /// measured and predicted: n x time.size().
  virtual void samples(const Eigen::VectorXd& time, const Eigen::MatrixXd& measured,
                       const Eigen::MatrixXd& predicted) = 0;
  /// With a band: the chunk's half widths (n x time.size()), called just before samples().
  virtual void bands(const Eigen::MatrixXd& half_width) { (void)half_width; }
};

/// A prediction against the raw measurement: the predicted torque interpolated linearly at each
/// raw stamp between the two dataset samples around it (never the measurement: it stays as
/// logged, noise included), only where those samples are consecutive and at most 1.5 dataset
/// steps apart (no bridging of gaps or runs). Fed chunk by chunk as a PredictionSink (forwarding to
/// `next` when given); memory: the raw torques.
class RawTorqueComparison : public PredictionSink {
 public:
  RawTorqueComparison(const RawTorques& raw, PredictionSink* next = nullptr);
  void samples(const Eigen::VectorXd& time, const Eigen::MatrixXd& measured,
               const Eigen::MatrixXd& predicted) override;
  void bands(const Eigen::MatrixXd& half_width) override {
    if (next_) next_->bands(half_width);
  }
  /// The statistics over the raw samples compared (num_samples: how many); raw samples that no
  /// pair of dataset samples brackets are not compared (skipped()).
  Validation result() const;
  int skipped() const { return static_cast<int>(raw_.time.size()) - compared_; }

 private:
  const RawTorques& raw_;
  PredictionSink* next_;
  Eigen::Index at_ = 0;  // the next raw sample to place
  bool have_previous_ = false;
  double previous_time_ = 0.0, step_ = 0.0;
  Eigen::VectorXd previous_;
  Eigen::VectorXd residual_squared_, measured_squared_;
  int compared_ = 0;
};

/// Folds every sample of the dataset `file` into `stream` with `model`'s regressor, chunk by
/// chunk; offers each chunk to `keeper` when given. Throws what DatasetReader throws, and
/// InputError prefixed with the file for a dataset of another joint count.
void addDatasetFile(LeastSquaresStream& stream, const Model& model, const std::string& file,
                    ThreadPool& pool, SampleKeeper* keeper = nullptr,
                    int chunk_samples = kStreamChunkSamples, const FitRows* rows = nullptr);

/// RNEA of `model` (its parameters and drive terms) at every sample of the dataset `file`,
/// streamed; each chunk also goes to `sink` when given. Throws what DatasetReader throws.
/// With `band`, also its half widths and coverage (Prediction::band_coverage, band). With
/// `filtered` (the file's samples through its torque's filter, FitRows), the prediction compared
/// with the file's filtered torque (statistics, band coverage, the kept series) has its friction
/// that needs sign(dq) through the same filter; `sink` still gets the model's own torque.
Prediction predictFile(const Model& model, const std::string& file, ThreadPool& pool,
                       PredictionSink* sink = nullptr, int chunk_samples = kStreamChunkSamples,
                       const PredictionBand* band = nullptr, const FitRows* filtered = nullptr);

/// The same for data in memory (on the pool's threads when given; the same result for any count).
/// Throws InputError when the joint counts differ.
Prediction predictTorques(const Model& model, const Trajectory& data, ThreadPool* pool = nullptr,
                          PredictionSink* sink = nullptr, const PredictionBand* band = nullptr,
                          const FitRows* filtered = nullptr);

/// The kept series' predictions (samples 0, stride, 2 stride, ... of `filtered`'s set) with
/// `model`'s friction that needs sign(dq) through `filtered`'s filter; nothing unfiltered.
void addFilteredFriction(const Model& model, const FitRows& filtered, Prediction& prediction);

/// The series of a prediction whose statistics are known (a least-squares fit's residuals): RNEA
/// of `model` on the kept samples, with `validation` and `measured_rms` as given.
Prediction predictionOfKept(const Model& model, const SampleKeeper& keeper,
                            const Validation& validation, const Eigen::VectorXd& measured_rms);

}  // namespace dynid
