#include "reports/prediction_report.hpp"

#include <algorithm>
#include <sstream>

#include "data/io.hpp"
#include "data/json_number.hpp"
#include "reports/output.hpp"
#include "reports/plots.hpp"

namespace dynid {

nlohmann::json predictionJson(const PredictOutcome& o, const std::string& estimate_file,
                              const std::string& data_file) {
  const Validation& v = o.prediction.validation;
  return {{"schema_version", kPredictionSchemaVersion},
          {"kind", "dynid.prediction"},
          {"estimate", estimate_file},
          {"method", o.method},
          {"robot_spec", o.robot_spec},
          {"drive_terms", driveTermsKeys(o.model.drive_terms)},
          {"data", {{"file", data_file}, {"samples", v.num_samples}}},
          {"relative_error", numberOrNull(v.relative_error)},
          {"joint_relative_error", numbersOrNull(v.normalised_rms)},
          {"torque_rms", numbersOrNull(v.torque_rms)}};
}

std::optional<std::string> torqueFigure(const Prediction& p, const std::string& title) {
  const auto n = static_cast<int>(p.measured.rows());
  const auto samples = static_cast<int>(p.measured.cols());
  if (n == 0 || samples == 0) return std::nullopt;
  const int stride = std::max(1, samples / 2000);  // at most ~2000 points per line
  std::ostringstream s;
  s.precision(9);
  s << "set terminal svg size 900," << 160 * n + 60 << " font 'sans,11' background rgb 'white'\n"
    << "set multiplot layout " << n << ",1 title '" << title << "'\n"
    << "set key top right horizontal\nset grid\nset lmargin 10\n";
  for (int j = 0; j < n; ++j) {
    s << "$j" << j << " << EOD\n";
    for (int k = 0; k < samples; k += stride)
      s << p.time[k] << " " << p.measured(j, k) << " " << p.predicted(j, k) << "\n";
    s << "EOD\n"
      << "set ylabel 'tau" << j + 1 << " [N m]'\n"
      << (j + 1 == n ? "set xlabel 't [s]'\n" : "unset xlabel\n") << "plot $j" << j
      << " using 1:2 with lines lw 1.5 lc rgb '#4477aa' title 'measured', $j" << j
      << " using 1:3 with lines lw 1.2 lc rgb '#ee6677' title 'predicted'\n";
  }
  s << "unset multiplot\n";
  return gnuplotSvg(s.str());
}

std::string writePrediction(const std::string& dir, const PredictOutcome& o,
                            const std::string& estimate_file, const std::string& data_file) {
  const Prediction& p = o.prediction;
  const auto n = static_cast<int>(p.measured.rows());
  std::ostringstream csv;
  csv << "t";
  for (int j = 1; j <= n; ++j) csv << ",tau" << j;
  for (int j = 1; j <= n; ++j) csv << ",tau_hat" << j;
  csv << "\n";
  for (Eigen::Index k = 0; k < p.measured.cols(); ++k) {
    csv << formatDouble(p.time[k]);
    for (int j = 0; j < n; ++j) csv << "," << formatDouble(p.measured(j, k));
    for (int j = 0; j < n; ++j) csv << "," << formatDouble(p.predicted(j, k));
    csv << "\n";
  }
  std::vector<std::pair<std::string, std::string>> files = {
      {"predicted.csv", csv.str()},
      {"prediction.json", predictionJson(o, estimate_file, data_file).dump(2) + "\n"}};
  const std::optional<std::string> figure =
      torqueFigure(p, "measured and predicted joint torques: " + o.robot_spec);
  if (figure) files.emplace_back("torques.svg", *figure);
  writeReportFiles(dir, files);
  const Validation& v = p.validation;
  std::ostringstream out;
  out << o.robot_spec << " (" << (o.method.empty() ? "estimate" : o.method) << ") on "
      << v.num_samples << " samples: relative torque error "
      << threeDigits(100.0 * v.relative_error) << " %; per joint RMS [N m]:";
  for (Eigen::Index j = 0; j < v.torque_rms.size(); ++j) out << " " << threeDigits(v.torque_rms[j]);
  out << "\nwrote " << dir << "/predicted.csv, " << dir << "/prediction.json";
  if (figure) out << " and " << dir << "/torques.svg";
  out << "\n";
  if (!figure) out << "warning: gnuplot did not run: no torques.svg\n";
  return out.str();
}

}  // namespace dynid
