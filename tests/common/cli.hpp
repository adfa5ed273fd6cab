// Running the dynid executable from the CLI tests: its exit code, standard output and error.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <string>
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
