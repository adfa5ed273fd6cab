#include "reports/prediction_report.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"
#include "reports/plots.hpp"

namespace dynid {

nlohmann::json rawValidationJson(const Validation& raw, const std::string& file, int skipped) {
  return {{"file", file},
          {"samples", raw.num_samples},
          {"not_bracketed", skipped},
          {"residual_rms", numbersOrNull(raw.torque_rms)},
          {"joint_relative_error", numbersOrNull(raw.normalised_rms)},
          {"relative_error", numberOrNull(raw.relative_error)},
          {"meaning",
           "the measured torque as logged (unfiltered, at the log's own stamps) against the "
           "prediction interpolated linearly at those stamps"}};
}

std::string rawValidationLine(const Validation& raw, int skipped) {
  std::string line = "against the raw torque at its " + std::to_string(raw.num_samples) +
                     " logged stamps: relative torque error " +
                     formatNumber(100.0 * raw.relative_error, 4, "n/a") +
                     " %; per joint RMS [N m]:";
  for (Eigen::Index j = 0; j < raw.torque_rms.size(); ++j)
    line.append(" ").append(formatNumber(raw.torque_rms[j], 4, "n/a"));
  if (skipped > 0)
    line.append(" (")
        .append(std::to_string(skipped))
        .append(" raw samples outside the dataset's samples not compared)");
  return line;
}

nlohmann::json restVelocityJson(const std::vector<RestVelocity>& rest) {
  nlohmann::json velocity = nlohmann::json::array(), noise = nlohmann::json::array(),
                 chatter = nlohmann::json::array(), source = nlohmann::json::array(),
                 at_rest = nlohmann::json::array();
  for (const RestVelocity& r : rest) {
    velocity.push_back(numberOrNull(r.velocity));
    noise.push_back(numberOrNull(r.noise_level));
    chatter.push_back(numberOrNull(r.chatter_level));
    source.push_back(r.source());
    at_rest.push_back(r.samples_at_rest);
  }
  return {
      {"velocity", velocity},
      {"noise_level", noise},
      {"chatter_level", chatter},
      {"source", source},
      {"samples_at_rest", at_rest},
      {"samples", rest.empty() ? 0L : rest.front().samples},
      {"rule",
       "a joint is at rest where |dq| <= velocity, the largest of noise_level (3 sigma of the "
       "velocity's white noise: 1.4826 MAD of dq less its local quadratic fit over " +
           std::to_string(kRestNoiseWindow) +
           " samples) and chatter_level (the 99th percentile of |dq| over the sign runs "
           "shorter than " +
           formatNumber(kRestChatterSeconds, 3) + " s, when there are at least " +
           std::to_string(kRestMinChatterRuns) + ") and " + formatNumber(kRestVelocityFloor, 3) +
           " (no robot measures a slower joint velocity); there sign(dq) is noise, so Coulomb, "
           "asymmetry and Stribeck friction are "
           "static friction: predicted as zero, fitted on no sample"}};
}

nlohmann::json atRestJson(const RestPrediction& rest) {
  return {{"samples", numbersOrNull(rest.samples)},
          {"rest_velocity", numbersOrNull(rest.rest_velocity)},
          {"static_friction_band",
           {{"low", numbersOrNull(rest.band_lo)}, {"high", numbersOrNull(rest.band_hi)}}},
          {"residual_mean", numbersOrNull(rest.residual_mean)},
          {"residual_std", numbersOrNull(rest.residual_std)},
          {"measured_std", numbersOrNull(rest.measured_std)},
          {"predicted_std", numbersOrNull(rest.predicted_std)},
          {"within_band", numbersOrNull(rest.within_band)},
          {"moving_residual_rms", numbersOrNull(rest.moving_rms)},
          {"meaning",
           "per joint, the samples at rest: the static friction there is any value in "
           "static_friction_band that the other torques demand, predicted as zero (a prediction "
           "reads no measured torque); so the residual at rest is the friction held plus the "
           "sensor's noise, and within_band is the share of residuals inside the band"}};
}

std::string atRestLine(const RestPrediction& rest) {
  std::string line;
  for (Eigen::Index j = 0; j < rest.samples.size(); ++j) {
    if (rest.samples[j] < 2.0) continue;
    line += (line.empty() ? "" : "; ") + std::string("joint ") + std::to_string(j + 1) + ": " +
            formatNumber(rest.samples[j], 6) + " samples, residual sd " +
            formatNumber(rest.residual_std[j], 3) + " N m (measured torque's " +
            formatNumber(rest.measured_std[j], 3) + "), static friction in [" +
            formatNumber(rest.band_lo[j], 3) + ", " + formatNumber(rest.band_hi[j], 3) + "] N m";
  }
  return line.empty() ? "" : "at rest (|dq| within its rest velocity; friction static): " + line;
}

std::string restVelocityLine(const std::vector<RestVelocity>& rest) {
  if (rest.empty()) return "";
  std::string velocity, at_rest, sources;
  bool same = true;
  for (std::size_t j = 0; j < rest.size(); ++j) {
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on " " + a temporary.
    velocity.append(" ").append(formatNumber(rest[j].velocity, 3));
    at_rest.append(" ").append(std::to_string(rest[j].samples_at_rest));
    sources.append(j == 0 ? "" : ",").append(rest[j].source());
    same = same && rest[j].source() == rest.front().source();
  }
  const std::string how =
      rest.front().given ? "given"
                         : "from " +
                               (same ? "the " + rest.front().source() + " on every joint"
                                     : std::string("the ") + sources) +
                               "; chatter: the 99th percentile of |dq| at zero, noise: 3 sigma, "
                               "floor: none measurable";
  return "rest velocity per joint [rad/s or m/s]:" + velocity + " (" + how +
         "); samples at rest:" + at_rest + " of " + std::to_string(rest.front().samples);
}

namespace {
nlohmann::json oneBased(const std::vector<int>& joints) {
  nlohmann::json out = nlohmann::json::array();
  for (int j : joints) out.push_back(j + 1);
  return out;
}
}  // namespace

nlohmann::json reversalsJson(const ReversalResidual& r) {
  const nlohmann::json flagged = oneBased(r.flagged);
  return {{"note",
           "per joint, the samples within speed (speed_fraction of the joint's RMS speed) of zero "
           "velocity: their share of the samples and of the joint's squared residual; flagged "
           "joints (1-based) hold at least residual_share_mark of it and concentration_mark "
           "times their sample share; friction_share: the share of the joint's squared residual "
           "that Fc sign(dq) + Fv dq + Fo fitted to it explains (friction_flagged: at least "
           "friction_share_mark)"},
          {"samples", r.samples},
          {"speed_fraction", kReversalSpeedFraction},
          {"residual_share_mark", kReversalResidualShare},
          {"concentration_mark", kReversalConcentration},
          {"speed", numbersOrNull(r.speed)},
          {"sample_share", numbersOrNull(r.sample_share)},
          {"residual_share", numbersOrNull(r.residual_share)},
          {"friction_share", numbersOrNull(r.friction_share)},
          {"friction_share_mark", kFrictionResidualShare},
          {"friction_flagged", oneBased(r.friction_flagged)},
          {"flagged", flagged}};
}

std::string missingFrictionNote(DriveTerms terms, const ReversalResidual& r,
                                const std::string& residual) {
  std::vector<std::string> missing;
  for (const auto& [term, key] :
       {std::pair{DriveTerm::kViscous, "fv"}, std::pair{DriveTerm::kCoulomb, "fc"},
        std::pair{DriveTerm::kOffset, "fo"}})
    if (!terms.has(term)) missing.push_back(key);
  if (r.friction_flagged.empty() || missing.empty()) return "";
  std::vector<int> order = r.friction_flagged;  // the largest share first
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return r.friction_share[a] > r.friction_share[b]; });
  const auto percent = [](double x) { return formatNumber(100.0 * x, 2) + " %"; };
  std::string out = "friction: Fc sign(dq) + Fv dq + Fo, fitted to " + residual + ", explains " +
                    percent(r.friction_share[order[0]]) + " of it on joint " +
                    std::to_string(order[0] + 1);
  for (std::size_t k = 1; k < order.size(); ++k)
    out += (k == 1 ? " (joint " : ", joint ") + std::to_string(order[k] + 1) + ": " +
           percent(r.friction_share[order[k]]);
  out += order.size() > 1 ? ")" : "";
  std::string keys, lacks;
  for (const std::string& key : driveTermsKeys(terms)) keys += (keys.empty() ? "" : ",") + key;
  for (const std::string& key : missing) {
    keys += (keys.empty() ? "" : ",") + key;
    lacks += (lacks.empty() ? "" : ", ") + key;
  }
  return out + ", and the drive terms lack " + lacks + ": --drive-terms " + keys +
         " adds them (compare the held-out errors)";
}

std::string reversalNote(DriveTerms terms, const ReversalResidual& r,
                         const std::string& filtering) {
  if (const std::string friction = missingFrictionNote(terms, r); !friction.empty())
    return friction + (filtering.empty() ? "" : "; " + filtering);
  if (r.flagged.empty()) return "";
  std::vector<int> order = r.flagged;  // the largest share first
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return r.residual_share[a] > r.residual_share[b]; });
  const auto percent = [](double x) { return formatNumber(100.0 * x, 2) + " %"; };
  std::string out =
      "friction at reversals: on the samples near zero velocity (|dq| under a tenth of the "
      "joint's RMS speed), joint " +
      std::to_string(order[0] + 1) + " has " + percent(r.residual_share[order[0]]) +
      " of its squared torque residual on " + percent(r.sample_share[order[0]]) + " of the samples";
  for (std::size_t k = 1; k < order.size(); ++k)
    out += (k == 1 ? " (joint " : ", joint ") + std::to_string(order[k] + 1) + ": " +
           percent(r.residual_share[order[k]]) + " on " + percent(r.sample_share[order[k]]);
  out += order.size() > 1 ? ")" : "";
  std::string keys;
  for (const std::string& key : driveTermsKeys(terms)) keys += (keys.empty() ? "" : ",") + key;
  if (!terms.has(DriveTerm::kCoulomb))
    out += ": the drive terms have no Coulomb friction; --drive-terms " +
           (keys.empty() ? std::string("fv,fc") : keys + ",fc") + " adds it";
  else if (!terms.has(DriveTerm::kStribeck))
    out += ": Fc sign(dq) models the friction there worst; --drive-terms " + keys +
           ",fs adds Stribeck (breakaway) friction, which can model part of it (compare the "
           "held-out errors)";
  else
    out +=
        ": the friction there (stick, presliding) is beyond the drive terms; that residual "
        "is the model's, not noise";
  return filtering.empty() ? out : out + "; " + filtering;
}

/// The torque filter the comparison reproduced (null: none), and where it came from.
nlohmann::json predictionFilterJson(const PredictOutcome& o) {
  nlohmann::json filter = nullptr;
  if (o.torque_filter.active() && o.filter_reach > 0)
    filter = {{"kind", "Butterworth low-pass, zero phase (forward-backward)"},
              {"order", o.torque_filter.order},
              {"cutoff_hz", o.torque_filter.cutoff},
              {"rate_hz", o.torque_filter.rate},
              {"reach_samples", o.filter_reach}};
  return filter;
}

/// The console's line on the filter reproduced, or why none was; empty when there is nothing to
/// say (no filter, and no prepare.json that had one).
std::string predictionFilterLine(const PredictOutcome& o) {
  if (o.torque_filter.active() && o.filter_reach > 0)
    return "compared with the filtered torque: the model's friction that needs sign(dq) through "
           "the same filter, " +
           o.torque_filter.describe() + " (" + o.torque_filter_source +
           "), as identify's held-out error; predicted.csv has the model's own torque";
  if (o.torque_filter.active()) return "torque filter: " + o.torque_filter_source;
  return "";
}

/// Which rows the error compares, when a joint's rows at rest were left out ("" when none was).
std::string comparedRowsLine(const Prediction& p) {
  const Eigen::VectorXd& rows = p.compared_rows;
  if (rows.size() == 0 || rows.minCoeff() >= p.validation.num_samples) return "";
  std::string out = "rows compared per joint:";
  for (Eigen::Index j = 0; j < rows.size(); ++j)
    out += " " + std::to_string(static_cast<long long>(rows[j]));
  return out + " of " + std::to_string(p.validation.num_samples) +
         " (a joint at rest, or within a filter's reach of rest, holds a static friction that no "
         "model predicts: those rows are described below, not counted as error)";
}

nlohmann::json predictionJson(const PredictOutcome& o, const std::string& estimate_file,
                              const std::string& data_file) {
  const Validation& v = o.prediction.validation;
  nlohmann::json out = {
      {"schema_version", kPredictionDocument.schema_version},
      {"kind", kPredictionDocument.kind},
      {"estimate", estimate_file.empty() ? nlohmann::json() : nlohmann::json(estimate_file)},
      {"method", o.method},
      {"robot_spec", o.robot_spec},
      {"drive_terms", driveTermsKeys(o.model.driveTerms())},
      {"data", {{"file", data_file}, {"samples", v.num_samples}}},
      {"compared_rows", numbersOrNull(o.prediction.compared_rows)},
      {"relative_error", numberOrNull(v.relative_error)},
      {"joint_relative_error", numbersOrNull(v.normalised_rms)},
      {"residual_rms", numbersOrNull(v.torque_rms)}};
  embedModel(out, o.model, o.source);  // the robot and parameters predicted with
  if (o.raw) out["raw_measurement"] = rawValidationJson(*o.raw, o.raw_file, o.raw_skipped);
  if (o.reversals.samples > 0) out["reversals"] = reversalsJson(o.reversals);
  if (!o.rest.empty()) out["rest_velocity"] = restVelocityJson(o.rest);
  if (o.prediction.rest.samples.size() > 0) out["at_rest"] = atRestJson(o.prediction.rest);
  out["torque_filter"] = predictionFilterJson(o);
  out["torque_filter_source"] = o.torque_filter_source;
  if (o.prediction.band_coverage.size() > 0)
    out["band"] = {
        {"level", 0.95},
        {"coverage", numbersOrNull(o.prediction.band_coverage)},
        {"outside_expected", bandWarnings(o.prediction.band_coverage)},
        {"method",
         "per sample and joint, 1.96 sqrt(y Sigma y^T + sigma_j^2): y the joint's base-regressor "
         "row, Sigma the estimate's base covariance, sigma_j its residual noise (estimate.json's "
         "base_covariance and joint_sigma). For a physically consistent estimate Sigma is the "
         "least-squares covariance at that estimate."}};
  return out;
}

std::vector<std::string> bandWarnings(const Eigen::VectorXd& coverage) {
  std::vector<std::string> out;
  for (Eigen::Index j = 0; j < coverage.size(); ++j)
    if (coverage[j] < kBandCoverageLow || coverage[j] > kBandCoverageHigh)
      out.push_back("joint " + std::to_string(j + 1) + ": the 95 % band covers " +
                    formatNumber(100.0 * coverage[j], 3) + " % of the samples" +
                    (coverage[j] < kBandCoverageLow
                         ? " (these data are noisier than the training data, or the model misses "
                           "something here: a collision, a payload, another friction)"
                         : " (these data are quieter than the training data's residuals)"));
  return out;
}

std::optional<std::string> torqueFigure(const Prediction& p, const std::string& title) {
  const auto n = static_cast<int>(p.measured.rows());
  const auto samples = static_cast<int>(p.measured.cols());
  if (n == 0 || samples == 0) return std::nullopt;
  const int stride = std::max(1, samples / 1000);  // at most ~1000 points per line
  PlotScript s;
  s.precision(9);
  s << "set terminal svg size 900," << 160 * n + 60 << " font 'sans,11' background rgb 'white'\n"
    << "set multiplot layout " << n << ",1 title " << gnuplotString(title) << "\n"
    << "set key top right horizontal\nset grid\nset lmargin 10\n";
  const bool band = p.band.rows() == n && p.band.cols() == samples;
  for (int j = 0; j < n; ++j) {
    PlotRows data;
    for (int k = 0; k < samples; k += stride)
      data.append({p.time[k], p.measured(j, k), p.predicted(j, k),
                   band ? p.predicted(j, k) - p.band(j, k) : 0.0,
                   band ? p.predicted(j, k) + p.band(j, k) : 0.0});
    s << "$j" << j << " << EOD\n"
      << data << "EOD\n"
      << "set ylabel 'tau" << j + 1 << " [N m]'\n";
    if (j + 1 == n)
      s << "set xlabel 't [s]'\n";
    else
      s << "unset xlabel\n";
    s << "plot ";
    if (band)
      s << "$j" << j << " using 1:4:5 with filledcurves lc rgb '#f4c6cb' title '95 % band', ";
    s << "$j" << j << " using 1:2 with lines lw 1.5 lc rgb '#4477aa' title 'measured', $j" << j
      << " using 1:3 with lines lw 1.2 lc rgb '#ee6677' title 'predicted'\n";
  }
  s << "unset multiplot\n";
  return gnuplotSvg(s);
}

namespace {
/// Inline gnuplot data "$<prefix><j> << EOD": (time, residual of joint j), at most ~1000 points.
void residualBlock(PlotScript& s, bool held_out, const Prediction& p, int j) {
  const auto samples = static_cast<int>(p.measured.cols());
  const int stride = std::max(1, samples / 1000);
  PlotRows data;
  for (int k = 0; k < samples; k += stride)
    data.append({p.time[k], p.measured(j, k) - p.predicted(j, k)});
  if (held_out)
    s << "$v";
  else
    s << "$t";
  s << j << " << EOD\n" << data << "EOD\n";
}
}  // namespace

std::optional<std::string> residualFigure(const Prediction& train, const Prediction* validate) {
  const auto n = static_cast<int>(train.measured.rows());
  if (n == 0 || train.measured.cols() == 0) return std::nullopt;
  PlotScript s;
  s.precision(9);
  s << "set terminal svg size 900," << 130 * n + 60 << " font 'sans,11' background rgb 'white'\n"
    << "set multiplot layout " << n << ",1 title 'torque residuals (measured - predicted)'\n"
    << "set key top right horizontal\nset grid\nset lmargin 10\n";
  for (int j = 0; j < n; ++j) {
    residualBlock(s, false, train, j);
    const bool held_out = validate != nullptr && validate->measured.cols() > 0;
    if (held_out) residualBlock(s, true, *validate, j);
    s << "set ylabel 'r" << j + 1 << " [N m]'\n";
    if (j + 1 == n)
      s << "set xlabel 't [s]'\n";
    else
      s << "unset xlabel\n";
    s << "plot $t" << j << " using 1:2 with lines lw 1 lc rgb '#4477aa' title 'training'";
    if (held_out)
      s << ", $v" << j << " using 1:2 with lines lw 1 lc rgb '#ee6677' title 'held out'";
    s << "\n";
  }
  s << "unset multiplot\n";
  return gnuplotSvg(s);
}

std::optional<std::string> residualHistogram(const Prediction& train) {
  const auto n = static_cast<int>(train.measured.rows());
  const auto samples = train.measured.cols();
  if (n == 0 || samples == 0) return std::nullopt;
  constexpr int kBins = 41;
  const int columns = n > 1 ? 2 : 1, rows = (n + columns - 1) / columns;
  PlotScript s;
  s.precision(9);
  s << "set terminal svg size 900," << 220 * rows + 60 << " font 'sans,11' background rgb 'white'\n"
    << "set multiplot layout " << rows << "," << columns
    << " title 'training residuals: histogram and the normal density of the same RMS'\n"
    << "set key top right\nset grid\nset style fill solid 0.5 noborder\n";
  for (int j = 0; j < n; ++j) {
    const Eigen::VectorXd r = (train.measured.row(j) - train.predicted.row(j)).transpose();
    const double rms = std::sqrt(r.squaredNorm() / static_cast<double>(samples));
    if (!(rms > 0.0) || !std::isfinite(rms)) continue;  // a perfect fit has no histogram
    const double width = 8.0 * rms / kBins;
    Eigen::VectorXd counts = Eigen::VectorXd::Zero(kBins);
    for (Eigen::Index k = 0; k < r.size(); ++k) {
      const double bin = std::floor((r[k] + 4.0 * rms) / width);
      if (bin >= 0.0 && bin < kBins) counts[static_cast<int>(bin)] += 1.0;
    }
    PlotRows bins;
    for (int b = 0; b < kBins; ++b)
      bins.append(
          {-4.0 * rms + (b + 0.5) * width, counts[b] / (static_cast<double>(samples) * width)});
    s << "$h" << j << " << EOD\n"
      << bins << "EOD\n"
      << "s" << j << " = " << rms << "\n"
      << "set xlabel 'r" << j + 1 << " [N m]'\nset xrange [" << -4.0 * rms << ":" << 4.0 * rms
      << "]\nset boxwidth " << width << "\nplot $h" << j
      << " using 1:2 with boxes lc rgb '#4477aa' title 'joint " << j + 1 << "', exp(-x**2/(2*s" << j
      << "**2))/(s" << j << "*sqrt(2*pi)) with lines lw 1.5 lc rgb '#ee6677' title 'normal'\n";
  }
  s << "unset multiplot\n";
  return gnuplotSvg(s);
}

PredictedCsv::PredictedCsv(const std::string& dir) : dir_(dir) {}

PredictedCsv::~PredictedCsv() {
  set_.reset();  // removes the temporaries unless published
  std::error_code ignored;
  if (created_dir_) std::filesystem::remove(dir_, ignored);  // only when left empty
}

void PredictedCsv::open() {
  std::error_code ec;
  created_dir_ = !std::filesystem::exists(dir_, ec);
  set_ = std::make_unique<OutputSet>(dir_);  // creates the directory
  out_ = &set_->stream("predicted.csv");
}

void PredictedCsv::bands(const Eigen::MatrixXd& half_width) { band_ = &half_width; }

void PredictedCsv::samples(const Eigen::VectorXd& time, const Eigen::MatrixXd& measured,
                           const Eigen::MatrixXd& predicted) {
  const auto n = static_cast<int>(measured.rows());
  if (!out_) open();
  const Eigen::MatrixXd* band = band_;
  band_ = nullptr;  // this chunk's only
  if (!header_written_) {
    with_band_ = band != nullptr;
    std::string header = "t";
    for (int j = 1; j <= n; ++j) header += ",tau" + std::to_string(j);
    for (int j = 1; j <= n; ++j) header += ",tau_hat" + std::to_string(j);
    if (with_band_)
      for (int j = 1; j <= n; ++j) header += ",band" + std::to_string(j);
    out_->write(header + "\n");
    header_written_ = true;
  }
  std::array<char, 32> number;
  const auto append = [&](double x) {
    row_.append(number.data(), std::to_chars(number.data(), number.data() + number.size(), x).ptr);
  };
  for (Eigen::Index k = 0; k < time.size(); ++k) {
    row_.clear();
    append(time[k]);
    for (int j = 0; j < n; ++j) {
      row_ += ',';
      append(measured(j, k));
    }
    for (int j = 0; j < n; ++j) {
      row_ += ',';
      append(predicted(j, k));
    }
    if (with_band_)
      for (int j = 0; j < n; ++j) {
        row_ += ',';
        append((*band)(j, k));
      }
    row_ += '\n';
    out_->write(row_);
  }
}

OutputSet& PredictedCsv::finish() {
  if (!out_) open();  // no samples: the header alone
  if (!header_written_) out_->write("t\n");
  out_->stage();
  return *set_;
}

std::string writePrediction(const std::string& dir, const PredictOutcome& o,
                            const std::string& estimate_file, const std::string& data_file,
                            PredictedCsv& csv) {
  const Prediction& p = o.prediction;
  std::vector<std::pair<std::string, std::string>> files = {
      {"prediction.json",
       jsonText(withProvenance(predictionJson(o, estimate_file, data_file)), 2) + "\n"}};
  const std::optional<std::string> figure =
      torqueFigure(p, "measured and predicted joint torques: " + o.robot_spec);
  if (figure) files.emplace_back("torques.svg", *figure);
  OutputSet& set = csv.finish();
  if (set.dir() != dir) throw Error("predicted.csv and the prediction must go to one directory");
  for (const auto& [name, content] : files) set.add(name, content);
  set.publish();
  const Validation& v = p.validation;
  std::ostringstream out;
  out << o.robot_spec << " (" << (o.method.empty() ? "estimate" : o.method) << ") on "
      << v.num_samples << " samples: relative torque error "
      << formatNumber(100.0 * v.relative_error, 3, "n/a") << " %; per joint RMS [N m]:";
  for (Eigen::Index j = 0; j < v.torque_rms.size(); ++j) {
    // A joint with no row compared (at rest throughout) has no RMS to show.
    const bool none = j < p.compared_rows.size() && p.compared_rows[j] == 0.0;
    out << " " << (none ? std::string("n/a") : formatNumber(v.torque_rms[j], 3, "n/a"));
  }
  if (const std::string line = comparedRowsLine(p); !line.empty()) out << "\n" << line;
  if (o.raw) out << "\n" << rawValidationLine(*o.raw, o.raw_skipped);
  const Eigen::VectorXd& coverage = p.band_coverage;
  if (coverage.size() > 0) {
    out << "\n95 % band coverage per joint [%]:";
    for (Eigen::Index j = 0; j < coverage.size(); ++j)
      out << " " << formatNumber(100.0 * coverage[j], 3, "n/a");
    for (const std::string& w : bandWarnings(coverage)) out << "\nwarning: " << w;
  } else if (o.method == "model") {
    out << "\nno band: a model has no covariance (predict from identify's estimate.json for a "
           "95 % band)";
  } else {
    out << "\nno band: the estimate has no base covariance (made before dynid recorded it: "
           "identify again)";
  }
  if (const std::string line = restVelocityLine(o.rest); !line.empty()) out << "\n" << line;
  if (const std::string line = atRestLine(p.rest); !line.empty()) out << "\n" << line;
  if (const std::string line = predictionFilterLine(o); !line.empty()) out << "\n" << line;
  const std::string filtering =
      o.torque_filter.active() && o.filter_reach > 0
          ? "not the torque filter's artefact: the comparison reproduces its low-pass (" +
                o.torque_filter.describe() + ") on the friction"
          : "";
  if (const std::string note = reversalNote(o.model.driveTerms(), o.reversals, filtering);
      !note.empty())
    out << "\nnote: " << note;
  out << "\nwrote " << dir << "/predicted.csv, " << dir << "/prediction.json";
  if (figure) out << " and " << dir << "/torques.svg";
  out << "\n";
  if (!figure) out << "warning: gnuplot did not run: no torques.svg\n";
  return out.str();
}

}  // namespace dynid
