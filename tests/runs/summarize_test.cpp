#include "analysis/runs/summarize.hpp"

#include "analysis/runs/identify.hpp"
#include "analysis/runs/simulate.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>

#include "analysis/runs/arm.hpp"
#include "analysis/runs/training.hpp"
#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "tests/common/puma_runs.hpp"
#include "tests/common/trajectories.hpp"

namespace dynid {
namespace {

/// A Panda log with its own friction (fv, fc, fo), a Fourier motion of `seed`, with stops (the arm
/// holds still for a second every two) when `pauses`.
Trajectory pandaLog(double duration, std::uint64_t seed, bool pauses) {
  SimulateRequest request;
  request.robot = makePanda(true);
  request.fourier = true;
  request.amplitude = Eigen::VectorXd::Constant(7, 0.4);
  request.simulation.duration = duration;
  request.simulation.noise_tau = 0.1;
  request.simulation.seed = seed;
  if (pauses) request.pauses = Pauses{2.0, 1.0, 0.3};
  return simulateRun(request).trajectory;
}

std::string written(const Trajectory& data, const std::string& name) {
  const std::string path = test::tempPath(name);
  writeDatasetCsv(path, data);
  return path;
}

struct Logs {
  std::vector<std::string> files;
  std::string all;  // the logs concatenated, one file
};

const Logs& pandaLogs() {
  static const Logs logs = [] {
    std::vector<Trajectory> parts = {pandaLog(4.0, 1, false), pandaLog(3.0, 2, true),
                                     pandaLog(5.0, 3, true)};
    Logs out;
    for (std::size_t i = 0; i < parts.size(); ++i)
      out.files.push_back(written(parts[i], "summarize_log" + std::to_string(i) + ".csv"));
    out.all = written(test::concatenated(parts, 1.0), "summarize_all.csv");
    return out;
  }();
  return logs;
}

// The acceptance of issue 70's summaries: merged in any order they give the concatenated logs'
// estimate (ols, wls, pc). With a torque filter reproduced on the friction columns, each log is
// its own set (the rows left out where a joint dwells are judged against the log's RMS speed):
// a summary then gives what identify gives on that log, and the concatenation, judged against
// the pooled RMS, leaves out other rows (docs/FLEET.md).
TEST(SummarizeRun, MergedSummariesGiveTheConcatenatedLogsEstimate) {
  const Logs& logs = pandaLogs();
  for (const TorqueFilterChoice& filter : {TorqueFilterChoice(TorqueFilter{0, 0.0, 0.0})}) {
    SummarizeRequest summarize;
    summarize.model = makePanda(true);
    summarize.data_files = logs.files;
    summarize.rest_velocity = {1e-3};  // one for every log: the concatenation measures its own
    summarize.torque_filter = filter;
    const SummarizeOutcome outcome = summarizeRun(summarize);
    ASSERT_EQ(outcome.summaries.size(), 3u);
    EXPECT_FALSE(outcome.interrupted);
    const std::vector<std::vector<int>> orders = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
    for (Method method : {Method::kOls, Method::kWls, Method::kPc}) {
      IdentifyRequest whole;
      whole.model = makePanda(true);
      whole.method = method;
      whole.data_file = logs.all;
      whole.rest_velocity = {1e-3};
      whole.torque_filter = filter;
      const IdentifyOutcome reference = identifyRun(whole);
      for (const std::vector<int>& order : orders) {
        std::vector<const Summary*> parts;
        for (int i : order) parts.push_back(&outcome.summaries[static_cast<std::size_t>(i)]);
        const Summary merged = mergeSummaries(parts, {});
        IdentifyRequest request = whole;
        request.data_file.clear();
        request.summary = &merged;
        request.summary_name = "merged";
        const IdentifyOutcome o = identifyRun(request);
        const Eigen::VectorXd& want = reference.result.estimate.beta;
        // 1e-10 relative, the bound: the same rows' QR, stacked in another order.
        EXPECT_LT((o.result.estimate.beta - want).norm(), 1e-10 * want.norm())
            << methodName(method) << " filter " << filter->order;
        EXPECT_LT((o.result.standard - reference.result.standard).norm(),
                  1e-10 * reference.result.standard.norm());
        EXPECT_EQ(o.result.estimate.fitted_rows, reference.result.estimate.fitted_rows);
        EXPECT_EQ(o.summary_sources.size(), 3u);
        // The hac covariance over the summary's batches against the one over the samples' own
        // (other batch lengths): the same long-run variance, each estimated from 30-100 batches,
        // so within 35 % (the sampling spread of a variance over 30 batches is ~26 %).
        const Eigen::VectorXd ratio =
            o.result.estimate.std_dev.cwiseQuotient(reference.result.estimate.std_dev);
        EXPECT_GT(ratio.minCoeff(), 0.65) << methodName(method);
        EXPECT_LT(ratio.maxCoeff(), 1.35) << methodName(method);
      }
    }
  }
}

TEST(SummarizeRun, AFilteredLogsSummaryGivesItsOwnEstimate) {
  const Logs& logs = pandaLogs();
  const TorqueFilterChoice filter = TorqueFilter{4, 20.0, 0.0};
  SummarizeRequest summarize;
  summarize.model = makePanda(true);
  summarize.data_files = {logs.files[1]};  // the one with stops
  summarize.torque_filter = filter;
  const Summary summary = summarizeRun(summarize).summaries.front();
  ASSERT_TRUE(summary.sources.front().torque_filter.active());
  IdentifyRequest whole;
  whole.model = makePanda(true);
  whole.method = Method::kWls;
  whole.data_file = logs.files[1];
  whole.torque_filter = filter;
  whole.validate_file = logs.files[2];
  const IdentifyOutcome reference = identifyRun(whole);
  ASSERT_GT(reference.filter_reach, 0);
  IdentifyRequest request = whole;
  request.summary = &summary;
  request.summary_name = "one";
  const IdentifyOutcome o = identifyRun(request);
  const Eigen::VectorXd& want = reference.result.estimate.beta;
  EXPECT_LT((o.result.estimate.beta - want).norm(), 1e-10 * want.norm());  // as above
  EXPECT_EQ(o.result.estimate.fitted_rows, reference.result.estimate.fitted_rows);
  // The held-out prediction reproduces the logs' filter as the log's own identify does.
  EXPECT_EQ(o.filter_reach, reference.filter_reach);
  ASSERT_TRUE(o.validation && reference.validation);
  EXPECT_NEAR(o.validation->relative_error, reference.validation->relative_error,
              1e-9 * reference.validation->relative_error);  // the same estimate to 1e-10
}

TEST(SummarizeRun, RefusesToMergeAnotherRobotOrOtherDriveTerms) {
  const Logs& logs = pandaLogs();
  SummarizeRequest request;
  request.model = makePanda(true);
  request.data_files = {logs.files[0]};
  const Summary with = summarizeRun(request).summaries.front();
  request.model = makePanda(false);
  const Summary without = summarizeRun(request).summaries.front();
  try {
    mergeSummaries({&with, &without}, {"a.summary.json", "b.summary.json"});
    FAIL() << "merged summaries of other drive terms";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.summary.json cannot be merged with a.summary.json: "
                                         "its drive terms are none"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(mergeSummaries({}, {}), InputError);
  // identify from a summary of another robot than the request's, and combined from one.
  IdentifyRequest identify;
  identify.model = makePanda(true);
  identify.summary = &without;
  identify.summary_name = "b.summary.json";
  EXPECT_THROW(identifyRun(identify), InputError);
  identify.summary = &with;
  identify.method = Method::kCombined;
  EXPECT_THROW(identifyRun(identify), InputError);
}

TEST(SummarizeRun, StoppedItKeepsTheLogsReadWhole) {
  const Logs& logs = pandaLogs();
  std::atomic<bool> stop{false};
  SummarizeRequest request;
  request.model = makePanda(true);
  request.data_files = logs.files;
  request.control.stop = &stop;
  request.control.progress = [&](const std::string& line) {
    if (line.find("2 of 3") != std::string::npos) stop = true;  // while the second is read
  };
  const SummarizeOutcome outcome = summarizeRun(request);
  EXPECT_TRUE(outcome.interrupted);
  ASSERT_EQ(outcome.summaries.size(), 1u);
  EXPECT_EQ(outcome.summaries.front().sources.front().file, logs.files[0]);
  EXPECT_THROW(summarizeRun(SummarizeRequest{}), InputError);  // no data
}

/// `count` samples of the PUMA (with drive terms) on slow sines at 1 kHz, its rigid-body torque
/// with noise: a long log without simulating it.
Trajectory pumaSines(const Model& model, int count) {
  Trajectory data;
  data.time = Eigen::VectorXd::LinSpaced(count, 0.0, (count - 1) * 1e-3);
  for (Eigen::MatrixXd* m : {&data.q, &data.dq, &data.ddq, &data.tau}) m->resize(6, count);
  Data workspace(model);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (int k = 0; k < count; ++k) {
    for (int j = 0; j < 6; ++j) {
      const double w = 0.3 + 0.17 * j, t = data.time[k];
      data.q(j, k) = 0.8 * std::sin(w * t + j);
      data.dq(j, k) = 0.8 * w * std::cos(w * t + j);
      data.ddq(j, k) = -0.8 * w * w * std::sin(w * t + j);
    }
    data.tau.col(k) = rnea(model, workspace, data.q.col(k), data.dq.col(k), data.ddq.col(k));
    for (int j = 0; j < 6; ++j) data.tau(j, k) += noise(rng);
  }
  return data;
}

// A log read once (at most kWholeHeadSamples: its samples kept from the rest velocities' read for
// the stream) and one longer than the rest velocities' measure (kRestSamples: read again, its head
// not kept): each summary is the same bits as the summary of the same samples handed over in
// memory (the builder takes them in any chunks), and gives identify's estimate on the file.
TEST(SummarizeRun, ALogIsSummarizedAsItsSamplesInMemoryShortOrLong) {
  const Model model = makePuma560(true);
  for (const int count : {kWholeHeadSamples, kRestSamples + 3000}) {
    const Trajectory data = pumaSines(model, count);
    const std::string file = written(data, "summarize_long.csv");
    SummarizeRequest request;
    request.model = model;
    request.data_files = {file};
    const Summary from_file = summarizeRun(request).summaries.front();
    request.data_files.clear();
    request.data = &data;
    const Summary in_memory = summarizeRun(request).summaries.front();
    EXPECT_EQ(from_file.factors.numSamples(), count);
    ASSERT_EQ(from_file.factors.batches().size(), in_memory.factors.batches().size()) << count;
    for (std::size_t b = 0; b < in_memory.factors.batches().size(); ++b)
      for (std::size_t j = 0; j < 6; ++j)
        ASSERT_EQ(from_file.factors.batches()[b].factors[j],
                  in_memory.factors.batches()[b].factors[j])
            << count << " samples, batch " << b << " joint " << j;
    EXPECT_EQ(from_file.sources.front().rest_velocity, in_memory.sources.front().rest_velocity);
    IdentifyRequest whole;
    whole.model = model;
    whole.data_file = file;
    const IdentifyOutcome reference = identifyRun(whole);
    IdentifyRequest from_summary = whole;
    from_summary.data_file.clear();
    from_summary.summary = &from_file;
    from_summary.summary_name = "long";
    const Eigen::VectorXd& want = reference.result.estimate.beta;
    // 1e-10 relative, the bound: the same rows' QR, folded batch by batch.
    EXPECT_LT((identifyRun(from_summary).result.estimate.beta - want).norm(), 1e-10 * want.norm())
        << count;
  }
}

}  // namespace
}  // namespace dynid
