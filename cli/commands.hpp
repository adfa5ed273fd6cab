// One function per top-level command; each takes the arguments after the command name and returns
// the process exit code (or throws UsageError / dynid::Error, mapped to 2 / 1 by main).
#pragma once

#include <string>
#include <vector>

namespace dynid::cli {

int runModel(const std::vector<std::string>& args);
int runDynamics(const std::vector<std::string>& args);
int runSimulate(const std::vector<std::string>& args);
int runPrepare(const std::vector<std::string>& args);
int runPredict(const std::vector<std::string>& args);
int runIdentifiability(const std::vector<std::string>& args);
int runIdentify(const std::vector<std::string>& args);
int runSummarize(const std::vector<std::string>& args);
int runFleet(const std::vector<std::string>& args);
int runSearch(const std::vector<std::string>& args);
int runRefine(const std::vector<std::string>& args);
int runDemo(const std::vector<std::string>& args);
int runStudy(const std::vector<std::string>& args);
int runBatch(const std::vector<std::string>& args);
int runExcite(const std::vector<std::string>& args);
int runPayload(const std::vector<std::string>& args);
int runMonitor(const std::vector<std::string>& args);
int runAudit(const std::vector<std::string>& args);
int runUpgrade(const std::vector<std::string>& args);
int runRerun(const std::vector<std::string>& args);

}  // namespace dynid::cli
