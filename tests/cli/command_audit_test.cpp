// dynid audit through the executable: sessions from logs and from estimates, the same verdict.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, AuditFromLogsAndFromTheirEstimatesAgrees) {
  const std::string dir = test::tempPath("cli_audit");
  std::filesystem::create_directories(dir);
  std::string logs, estimates;
  for (int s = 1; s <= 3; ++s) {
    const std::string log = dir + "/s" + std::to_string(s) + ".csv";
    ASSERT_EQ(run("simulate --robot puma560 --duration 5 --noise-tau 0.1 --seed " +
                  std::to_string(s) + " --out " + log)
                  .code,
              0);
    ASSERT_EQ(
        run("identify --robot puma560 --data " + log + " --out " + dir + "/e" + std::to_string(s))
            .code,
        0);
    logs += " " + log;
    estimates += " " + dir + "/e" + std::to_string(s) + "/estimate.json";
  }
  const Result from_logs = run("audit --robot puma560 --data" + logs + " --out " + dir + "/a1");
  ASSERT_EQ(from_logs.code, 0) << from_logs.err;
  const Result from_estimates = run("audit --estimates" + estimates + " --out " + dir + "/a2");
  ASSERT_EQ(from_estimates.code, 0) << from_estimates.err;
  const auto a = nlohmann::json::parse(readFile(dir + "/a1/audit.json"));
  const auto b = nlohmann::json::parse(readFile(dir + "/a2/audit.json"));
  EXPECT_EQ(a["kind"], "dynid.audit");
  EXPECT_EQ(a["sessions"].size(), 3u);
  // The same estimates either way: the same statistics (the estimates' JSON round trip is exact).
  EXPECT_EQ(a["chi2"], b["chi2"]);
  EXPECT_EQ(a["verdict"], b["verdict"]);
  EXPECT_EQ(a["parameters"].size(), a["parameters"].size());
  // The robot audited, embedded either way: identified here, or as the estimates embed it.
  EXPECT_EQ(a["model"], b["model"]);
  EXPECT_EQ(a["model_source"], b["model_source"]);
  EXPECT_EQ(b["model_source"]["spec"], "puma560");
  EXPECT_EQ(b["provenance"]["inputs"].size(), 3u);  // the three estimates, by content
  EXPECT_TRUE(contains(from_logs.out, "3 sessions of puma560 (ols)")) << from_logs.out;
  const std::string html = readFile(dir + "/a1/report.html");
  EXPECT_TRUE(test::opensWithVerdict(html, {"Compared", "Verdict", "How sure", "Moved", "Next"}));
  EXPECT_TRUE(contains(html, "<dd>" + a["verdict"].get<std::string>() + "</dd>"));
}

}  // namespace
}  // namespace dynid
