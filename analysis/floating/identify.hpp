// Estimation on a floating robot's data (`dynid identify --floating-base`, docs/FLOATING.md): the
// base parameters of each sensor set the dataset measures, by least squares on that set's rows,
// with the measures of how well they hold: the residual, held-out prediction, and the distance
// from the model's own parameters in standard deviations.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "data/floating/floating_dataset.hpp"
#include "identifiability/floating/floating_fit.hpp"
#include "identifiability/floating/floating_physical.hpp"
#include "search/floating/floating_combined.hpp"
#include "search/floating/floating_gc.hpp"

namespace dynid {

/// How the rows are weighted: ordinary least squares, or generalized least squares with every
/// channel's noise estimated from the data (fitFloatingFeasible): torques, forces and moments of
/// different sizes and units weighted by what they carry; pc: weighted as wls, every body
/// physically consistent (fitFloatingPhysical); combined: pc's estimate refined to fit the rows
/// and predict the data's motion together (analysis/floating/combined.hpp).
enum class FloatingMethod { kOls, kWls, kPc, kCombined };
/// "ols", "wls", "pc", "combined".
const char* floatingMethodName(FloatingMethod method);
/// Throws InputError naming `method` and the names.
FloatingMethod parseFloatingMethod(const std::string& text);

struct FloatingIdentifyRequest {
  /// The contacts (FloatingIdentifiabilityRequest::contacts' form); empty: the dataset's own, each
  /// frame with a wrench (a frame contact for six components, a point for three) or a flag (a
  /// point).
  std::vector<std::string> contacts;
  /// The sets to estimate; empty: every set the dataset measures (wrenches: a wrench at every
  /// contact; torques_wrenches: torques too; torques_contacts: torques and a flag at every
  /// contact).
  std::vector<SensorSet> sensors;
  /// The motion class the structural base parameters are drawn for; unset: with a contact on
  /// the base body, carried when the base moves in the data (RMS angular rate >= 0.05 rad/s or
  /// the linear acceleration's spread about its mean >= 0.2 m/s^2) and suspended when not (a
  /// warning says which); holding with contacts, free without.
  std::optional<FloatingMotion> motion;
  FloatingMethod method = FloatingMethod::kWls;
  /// pc: the weight of the divergence from the model's own parameters (PhysicalOptions').
  double prior_weight = kDefaultPriorWeight;
  /// The GC error of every estimate and of the model's own parameters, on the data and the
  /// held-out data (analysis/floating/gc_measure.hpp); unset: not measured.
  std::optional<FloatingGcOptions> gc = FloatingGcOptions{};
  /// combined: the combined estimator's weight, budget and noise floor (CombinedOptions; its
  /// rollouts are `gc`'s segments, its floor the one the GC summary gives pc's estimate), and its
  /// progress and stop.
  CombinedOptions combined;
  int threads =
      1;  // combined: the rollouts' threads (0: every core; the same estimate for any count)
  StructuralOptions structural;
  void check() const;
};

/// One set's estimate, or why it has none.
struct FloatingSetEstimate {
  SensorSetBase base;   // the set's structural base parameters
  std::string refused;  // empty: estimated; else why the data do not determine them
  /// The weighted fit (pc: its covariance is the estimate's, the constraints taken as inactive).
  FloatingFit fit;
  /// pc: the physically consistent estimate (fit.beta is its beta).
  std::optional<FloatingPhysicalEstimate> physical;
  /// combined: the combined estimator's run from pc's estimate (physical holds its result, and
  /// fit its base parameters with pc's covariance).
  std::optional<CombinedResult> combined;
  /// wls: the channel variances the fit is weighted by, torques_wrenches' estimate for every set
  /// when it has one (the same sensors feed them all), else the set's own.
  ChannelVariances variances;
  /// The set whose rows estimated them (a channel it does not read keeps 1: torques for
  /// wrenches, forces and moments for torques_contacts).
  SensorSet variances_from = SensorSet::kTorquesAndWrenches;
  Eigen::VectorXd model_beta;  // the model's own base parameters
  /// ||W beta - y|| / ||y|| in percent, on the data and on the held-out data (NaN without).
  double residual_percent = 0.0, validation_percent = 0.0;
  /// ||beta - model_beta|| / ||model_beta|| in percent (the paper's parameter error, against the
  /// model read: the truth when it made the data), and the RMS of (beta - model_beta) / sd.
  double model_error_percent = 0.0, model_z_rms = 0.0;
  /// The estimate's GC error on the data and on the held-out data, and the floor the inputs'
  /// noise gives it there (FloatingGcSummary; NaN where not measured).
  double gc_train = std::numeric_limits<double>::quiet_NaN();
  double gc_test = std::numeric_limits<double>::quiet_NaN();
  double gc_floor_train = std::numeric_limits<double>::quiet_NaN();
  double gc_floor_test = std::numeric_limits<double>::quiet_NaN();
};

/// The GC error measured on the identification's data (search/floating/floating_gc.hpp, the
/// paper's measure on a floating base): segments of the recorded motion rolled out by each
/// estimate, and by the model's own parameters for comparison.
struct FloatingGcSummary {
  /// Empty: measured on the data; else why not (not asked, no joint torques, a contact known by
  /// its flag alone, samples that are not one motion, a recording too short for a segment).
  std::string refused;
  /// The same for the held-out data (empty also when there are none).
  std::string validation_refused;
  double horizon = 0.0;  // as taken: a whole number of sample periods [s]
  int samples_per_segment = 0, segments = 0, validation_segments = 0;
  /// Whether the base's linear velocity entered the error (FloatingGcData::linear_velocity).
  bool linear_velocity = true;
  /// The model's own parameters' GC error, on the data and held out (NaN where not measured).
  double model_train = std::numeric_limits<double>::quiet_NaN();
  double model_test = std::numeric_limits<double>::quiet_NaN();
  /// The GC error the measured inputs' noise alone gives the model's own parameters, on the data
  /// and held out (each estimate has its own: FloatingSetEstimate::gc_floor_train): the mean over
  /// kGcFloorDraws draws of GC(inputs + noise) - GC(inputs), the noise drawn at the channels'
  /// variances the weighted fit estimated, the same draws for every candidate (seeded by the
  /// structural seed). A GC error at its floor is all noise; what it has above it is the
  /// candidate's own (its squared bias). The floor grows as the candidate's inertia shrinks (the
  /// same noisy torque accelerates a lighter robot more). NaN with ols, which estimates none.
  double floor_train = std::numeric_limits<double>::quiet_NaN();
  double floor_test = std::numeric_limits<double>::quiet_NaN();
};

/// Draws of the inputs' noise the GC error's floor averages (FloatingGcSummary): each draw's
/// difference carries a cross term of mean zero, whose spread four draws halve.
inline constexpr int kGcFloorDraws = 4;

struct FloatingIdentifyOutcome {
  std::vector<Contact> contacts;
  FloatingMotion motion = FloatingMotion::kHolding;
  FloatingMethod method = FloatingMethod::kWls;
  int samples = 0, validation_samples = 0;
  std::vector<FloatingSetEstimate> sets;
  FloatingGcSummary gc;
  std::vector<std::string> warnings;
};

/// One sample's measurement for `set` (FloatingMeasurement): the regressor at the sample's state,
/// and the contacts' Jacobians and forces in base-frame axes (every contact's wrench for the
/// wrench sets; the holding contacts by their flags for torques_contacts). Throws InputError when
/// the dataset lacks what the set reads.
FloatingMeasurement floatingMeasurement(const FloatingModel& model, FloatingData& data,
                                        const FloatingDataset& dataset,
                                        const std::vector<Contact>& contacts, SensorSet set,
                                        int sample);

/// A set's measures of its estimate out.fit.beta: its residual on `data` and `validation` (when
/// given), its distance from the model's own parameters (FloatingSetEstimate's fields).
void measureSetEstimate(const FloatingModel& model, const std::vector<Contact>& contacts,
                        const FloatingDataset& data, const FloatingDataset* validation,
                        FloatingSetEstimate& out);

/// The request for the other dataset of a loaded/unloaded pair: `request` with the motion class
/// the loaded data were analysed in (a default taken from one dataset's motion must not differ
/// between the two, or their base parameters would), and no GC error (only the payload is read;
/// combined keeps it: its rollouts are the estimator).
FloatingIdentifyRequest pairedRequest(const FloatingIdentifyRequest& request,
                                      const FloatingIdentifyOutcome& loaded);

/// Estimates each set on `data` (and checks it on `validation` when it has samples), then
/// measures the GC errors the request asks for (measureFloatingGc). Throws
/// InputError for a bad request, contacts the dataset and the request disagree on, a requested
/// set the dataset cannot feed; a set whose rows do not determine its base parameters is reported
/// refused.
FloatingIdentifyOutcome floatingIdentifyRun(const FloatingModel& model,
                                            const FloatingIdentifyRequest& request,
                                            const FloatingDataset& data,
                                            const FloatingDataset* validation = nullptr);

}  // namespace dynid
