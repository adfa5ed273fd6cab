// The monitor's sample feeds: one pass of the observer (and of the direct residual where ddq is
// given) over a dataset CSV, a recording or samples streamed on stdin; the streamed samples' line
// parser; a simulation's ground-truth episodes.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "analysis/monitor/monitor.hpp"
#include "core/model.hpp"

namespace dynid {

/// Parses one streamed sample: "t,q1..qn,dq1..dqn,tau1..taun" (3n + 1 fields) or the dataset row
/// "t,q..,dq..,ddq..,tau.." (4n + 1); the header decides which (`with_ddq`). Throws ParseError
/// naming `source`, the line and the column.
void parseSampleLine(const std::string& line, int n, bool with_ddq, const std::string& source,
                     long long line_number, double& t, Eigen::VectorXd& q, Eigen::VectorXd& dq,
                     Eigen::VectorXd& ddq, Eigen::VectorXd& tau);
/// The streamed header: the dataset header (returns true: with ddq) or t,q..,dq..,tau.. (false).
/// Throws ParseError naming the first column that differs.
bool parseSampleHeader(const std::string& line, int n, const std::string& source);

/// One pass over a log: the observer (and the direct residual where ddq is given) at every
/// sample, handed to `visit(t, dt, r_observer, r_direct or null, dq)`; dt = 0 after a restart.
struct Pass {
  long long samples = 0;
  double first = 0.0, last = 0.0;
  int restarts = 0;
  bool has_direct = false;
  bool interrupted = false;
};

using Visit = std::function<void(double t, double dt, const Eigen::VectorXd& observer,
                                 const Eigen::VectorXd* direct, const Eigen::VectorXd& dq)>;

/// Why the direct residual cannot be had from a recording.
extern const char* const kDirectNeedsDdq;

/// One pass over `file` (a dataset CSV or a recording) with the observer of `gain`.
Pass passOverLog(const Model& model, const std::string& file, const MonitorRequest& request,
                 const Eigen::VectorXd& gain, const Visit& visit,
                 std::vector<std::string>& warnings);
/// One pass over the samples request.next_line streams (a header, then samples). A stream that
/// ends while request.control is stopped is an interrupted pass, even before its header.
Pass passOverStream(const Model& model, const MonitorRequest& request, const Eigen::VectorXd& gain,
                    const Visit& visit);
/// The ground truth's episodes (dynid simulate --disturbance's file): runs of samples where any
/// applied torque is nonzero, as (start, end) [s].
std::vector<std::pair<double, double>> truthEpisodes(const std::string& file, int n);

}  // namespace dynid
