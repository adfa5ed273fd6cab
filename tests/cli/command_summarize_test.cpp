// dynid summarize and identify --summaries through the executable: summaries of logs give the
// estimate of the logs together, merged by identify or by summarize --merge, and rerun the same.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

/// The base parameters' estimates of an estimate.json.
std::vector<double> estimates(const std::string& file) {
  const auto doc = nlohmann::json::parse(readFile(file));
  std::vector<double> out;
  for (const auto& p : doc["base_parameters"]) out.push_back(p["estimate"].get<double>());
  return out;
}

double relativeDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0, n = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d += (a[i] - b[i]) * (a[i] - b[i]);
    n += b[i] * b[i];
  }
  return std::sqrt(d / n);
}

TEST(Cli, SummariesGiveTheEstimateOfTheLogsTogether) {
  const std::string dir = test::tempPath("cli_summarize");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::string logs;
  for (int s = 1; s <= 2; ++s) {
    const std::string log = dir + "/s" + std::to_string(s) + ".csv";
    ASSERT_EQ(run("simulate --robot puma560 --drives --duration 3 --noise-tau 0.1 --seed " +
                  std::to_string(s) + " --out " + log)
                  .code,
              0);
    logs += " " + log;
  }
  // The logs together as one file: the second's stamps after the first's, a second apart.
  {
    std::ofstream all(dir + "/all.csv");
    all << readFile(dir + "/s1.csv");
    std::ifstream second(dir + "/s2.csv");
    std::string line;
    std::getline(second, line);  // its header
    while (std::getline(second, line)) {
      const std::size_t comma = line.find(',');
      all << std::stod(line.substr(0, comma)) + 10.0 << line.substr(comma) << "\n";
    }
  }
  const Result sum = run("summarize --robot puma560 --drives --rest-velocity 1e-3 --data" + logs +
                         " --out " + dir + "/sums");
  ASSERT_EQ(sum.code, 0) << sum.err;
  EXPECT_TRUE(contains(sum.out, "s1.summary.json: 1 log, 3001 samples")) << sum.out;
  const Result merged =
      run("summarize --robot puma560 --drives --rest-velocity 1e-3 --merge --data" + logs +
          " --out " + dir + "/merged");
  ASSERT_EQ(merged.code, 0) << merged.err;
  ASSERT_EQ(run("identify --method wls --robot puma560 --drives --rest-velocity 1e-3 --data " +
                dir + "/all.csv --out " + dir + "/all")
                .code,
            0);
  const Result from = run("identify --method wls --summaries " + dir + "/sums/s2.summary.json " +
                          dir + "/sums/s1.summary.json --out " + dir + "/from");
  ASSERT_EQ(from.code, 0) << from.err;
  EXPECT_FALSE(contains(from.err, "gnuplot")) << from.err;  // no training figure is asked for
  const Result from_merged = run("identify --method wls --summaries " + dir +
                                 "/merged/summary.json --out " + dir + "/from_merged");
  ASSERT_EQ(from_merged.code, 0) << from_merged.err;
  const std::vector<double> want = estimates(dir + "/all/estimate.json");
  // 1e-10: the same rows' QR in another order (the CSV's shortest decimals are the same values).
  EXPECT_LT(relativeDifference(estimates(dir + "/from/estimate.json"), want), 1e-10);
  EXPECT_LT(relativeDifference(estimates(dir + "/from_merged/estimate.json"), want), 1e-10);
  const auto e = nlohmann::json::parse(readFile(dir + "/from/estimate.json"));
  EXPECT_EQ(e["data"]["sources"].size(), 2u);
  EXPECT_EQ(e["data"]["samples"], 6002);
  EXPECT_EQ(e["model_source"]["spec"], "puma560");  // the summaries' robot
  EXPECT_TRUE(contains(readFile(dir + "/from/report.md"), "least-squares summaries of 2 logs"));
  // Rerun: the same summary from the same log.
  const Result again = run("rerun " + dir + "/merged/summary.json");
  EXPECT_EQ(again.code, 0) << again.out << again.err;
  EXPECT_TRUE(contains(again.out, "apart from its times")) << again.out;
}

}  // namespace
}  // namespace dynid
