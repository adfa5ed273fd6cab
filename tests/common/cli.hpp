// Running the dynid executable from the CLI tests: its exit code, standard output and error.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "data/io.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/text.hpp"

namespace dynid::test {

struct Result {
  int code = -1;
  std::string out, err;
};

/// Runs `dynid ARGS` through the shell (ARGS may hold redirections), capturing both streams.
inline Result run(const std::string& args) {
  const std::string out = tempPath("stdout"), err = tempPath("stderr");
  const int status =
      std::system((std::string(DYNID_BIN) + " " + args + " >" + out + " 2>" + err).c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readFile(out);
  r.err = readFile(err);
  return r;
}

/// A noisy PUMA log pair with the robot's drives (0.3 N m of torque noise): 2 s for training and
/// 1.5 s held out, written as `prefix`_train.csv and `prefix`_held.csv in the tests' scratch
/// directory (the fronts' tests: a short log whose GC error the combined estimator can lower).
/// Returns their paths, empty when a simulation failed.
inline std::pair<std::string, std::string> noisyPumaPair(const std::string& prefix) {
  const std::string train = tempPath(prefix + "_train.csv"), held = tempPath(prefix + "_held.csv");
  const std::string sim = "simulate --robot puma560 --drives --noise-tau 0.3 ";
  if (run(sim + "--duration 2 --seed 4 --out " + train).code != 0 ||
      run(sim + "--duration 1.5 --seed 5 --out " + held).code != 0)
    return {};
  return {train, held};
}

/// Whether an HTML report opens with its verdict box (its heading is the document's first
/// section heading) and the box names each of `labels`.
inline bool opensWithVerdict(const std::string& html, const std::vector<std::string>& labels) {
  const std::size_t box = html.find("<section class=\"verdict\"");
  const std::size_t end = html.find("</section>", box);
  if (box == std::string::npos || end == std::string::npos) return false;
  if (html.find("<h2>") != html.find("<h2>Verdict</h2>")) return false;
  for (const std::string& label : labels)
    if (html.substr(box, end - box).find("<dt>" + label + "</dt>") == std::string::npos)
      return false;
  return true;
}

}  // namespace dynid::test
