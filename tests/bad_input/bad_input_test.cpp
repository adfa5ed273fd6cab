// The bad-input suite: malformed files and hostile options for every command, read from the
// *.cases files beside this source (their format is described in tests/bad_input/README.md).
// Each case runs `dynid` in a fresh directory and asserts the exit code, that the message names
// the file/line/field it expects, that the run neither crashed nor hung, and that nothing in the
// directory was created or changed.
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"

namespace dynid {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string name, source;                     // source: file:line of the "case" line
  std::vector<std::vector<std::string>> steps;  // setup directives, in order
  std::map<std::string, std::string> files;     // file NAME ... end
  std::string command;
  int exit_code = -1;
  std::vector<std::string> expected;  // fragments of stderr
  std::vector<std::string> may_write;
  int memory_mb = 0;    // limit-memory MB: the run's address space (ulimit -v)
  std::string pending;  // pending REASON: a known failure not fixed yet (skipped, reported)
  std::string stdin_file = "/dev/null";  // stdin NAME: the run's standard input (a case file)
};

std::vector<std::string> words(const std::string& line, int max_words) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && line[i] == ' ') ++i;
    if (i >= line.size()) break;
    if (static_cast<int>(out.size()) == max_words - 1) {
      out.push_back(line.substr(i));
      break;
    }
    const std::size_t j = std::min(line.find(' ', i), line.size());
    out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

std::vector<Case> readCases() {
  std::vector<Case> cases;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(DYNID_SOURCE_DIR "/tests/bad_input"))
    if (entry.path().extension() == ".cases") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    std::ifstream in(file);
    std::string line;
    int number = 0;
    const std::string group = file.stem().string();
    while (std::getline(in, line)) {
      ++number;
      if (line.empty() || line[0] == '#') continue;
      const std::vector<std::string> w = words(line, 2);
      const std::string& key = w[0];
      const std::string rest = w.size() > 1 ? w[1] : "";
      if (key == "case") {
        cases.push_back({});
        cases.back().name = group + "_" + rest;
        cases.back().source = file.filename().string() + ":" + std::to_string(number);
        continue;
      }
      if (cases.empty()) throw std::runtime_error(file.string() + ": directive before a case");
      Case& c = cases.back();
      if (key == "file") {
        std::string content, body;
        while (std::getline(in, body) && body != "end") {
          ++number;
          content += body + "\n";
        }
        ++number;
        c.files[rest] = content;
        c.steps.push_back({"file", rest});
      } else if (key == "run") {
        c.command = rest;
      } else if (key == "exit") {
        c.exit_code = std::stoi(rest);
      } else if (key == "stderr") {
        c.expected.push_back(rest);
      } else if (key == "pending") {
        c.pending = rest;
      } else if (key == "limit-memory") {
        c.memory_mb = std::stoi(rest);
      } else if (key == "stdin") {
        c.stdin_file = rest;
      } else if (key == "writes") {
        c.may_write.push_back(rest);
      } else {
        std::vector<std::string> step = words(line, key == "patch" ? 4 : 3);
        if (key == "replace") step = {"replace", words(line, 3)[1], words(line, 3)[2]};
        c.steps.push_back(step);
      }
    }
  }
  return cases;
}

const std::vector<Case>& allCases() {
  static const std::vector<Case> cases = readCases();
  return cases;
}

/// Runs `command` (through the shell) in `dir`; the exit status as the shell reports it.
test::Result runIn(const std::string& dir, const std::string& command) {
  const std::string out = dir + "/../" + fs::path(dir).filename().string() + ".stdout";
  const std::string err = dir + "/../" + fs::path(dir).filename().string() + ".stderr";
  const std::string line = "cd '" + dir + "' && " + command + " >'" + out + "' 2>'" + err + "'";
  const int status = std::system(line.c_str());
  test::Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readFile(out);
  r.err = readFile(err);
  return r;
}

/// The fixtures cases copy: a dataset, models, a search with its checkpoints, an estimate and a
/// batch, made once per dynid binary (its directory is named by the binary's size and time, so a
/// rebuilt dynid never meets the documents of an older one), renamed into place whole.
std::string fixtures() {
  static const std::string dir = [] {
    const fs::path bin = DYNID_BIN;
    const auto stamp = fs::last_write_time(bin).time_since_epoch().count();
    const std::string final_dir = std::string(DYNID_TEST_TMP) + "/bad_input_fixtures." +
                                  std::to_string(fs::file_size(bin)) + "." + std::to_string(stamp);
    if (fs::exists(final_dir + "/complete")) return final_dir;
    const std::string work = final_dir + ".tmp." + std::to_string(::getpid());
    fs::remove_all(work);
    fs::create_directories(work);
    const std::string d = DYNID_BIN;
    const std::vector<std::string> commands = {
        d + " simulate --robot puma560 --duration 3 --out puma.csv",
        d + " simulate --robot puma560 --duration 0.2 --out short.csv",
        d + " model export --robot puma560 --format json --out model.json",
        d + " model export --robot puma560 --format urdf --out model.urdf",
        d + " model export --robot puma560 --drives --format json --out drives.json",
        d + " search --method ga --robot puma560 --data puma.csv --perturb 0.3 --population 6 "
            "--budget-evals 18 --segments 10 --threads 1 --checkpoint ga.ckpt --out search",
        d + " search --method nlo --robot puma560 --data puma.csv --perturb 0.3 "
            "--evals-per-seed 10 --budget-evals 20 --segments 10 --threads 1 "
            "--checkpoint nlo.ckpt --out nlo",
        d + " identify --robot puma560 --data puma.csv --out estimate",
        d + " summarize --robot puma560 --data puma.csv --out summaries",
        d + " summarize --robot puma560 --drives --data short.csv --out summaries_drives",
        d + " batch manifest.json --shard 1/2 --out shard1",
        d + " batch manifest.json --shard 2/2 --out shard2",
        "cp search/search.json search.json && cp estimate/estimate.json estimate.json && "
        "cp summaries/puma.summary.json puma.summary.json && "
        "cp summaries_drives/short.summary.json drives.summary.json",
        "touch complete"};
    std::ofstream(work + "/manifest.json")
        << R"({"schema_version": 1, "grid": {"method": ["ols"], "seed": [1, 2]},)"
        << R"( "fixed": {"train_seconds": 1, "test_seconds": 1, "segments": 5}})"
        << "\n";
    for (const std::string& c : commands) {
      const test::Result r = runIn(work, c + " </dev/null");
      if (r.code != 0) throw std::runtime_error("fixture command failed: " + c + "\n" + r.err);
    }
    std::error_code ignored;
    fs::rename(work, final_dir, ignored);  // another process may have won the race: either will do
    fs::remove_all(work, ignored);
    // Older binaries' fixtures (and their logs) are no use to this one.
    const std::string prefix = "bad_input_fixtures.";
    for (const auto& old : fs::directory_iterator(DYNID_TEST_TMP, ignored)) {
      const std::string name = old.path().filename().string();
      if (name.rfind(prefix, 0) == 0 && old.path() != fs::path(final_dir) &&
          name.find(".tmp.") == std::string::npos)
        fs::remove_all(old.path(), ignored);
    }
    return final_dir;
  }();
  return dir;
}

std::string generate(const std::string& kind, long n) {
  std::string s;
  if (kind == "deep_xml") {  // a URDF whose root holds n nested elements
    s = "<robot name=\"r\">";
    for (long i = 0; i < n; ++i) s += "<a>";
    for (long i = 0; i < n; ++i) s += "</a>";
    return s + "</robot>\n";
  }
  if (kind == "deep_json") {  // n nested arrays in a model's field
    s = "{\"schema_version\": 1, \"name\": ";
    for (long i = 0; i < n; ++i) s += "[";
    for (long i = 0; i < n; ++i) s += "]";
    return s + "}\n";
  }
  if (kind == "chain_urdf") {  // a serial chain of n revolute joints
    s = "<robot name=\"chain\">\n<link name=\"l0\"/>\n";
    for (long i = 1; i <= n; ++i) {
      const std::string p = "l" + std::to_string(i - 1), c = "l" + std::to_string(i);
      s += "<link name=\"" + c +
           "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" "
           "iyz=\"0\" izz=\"0.1\"/></inertial></link>\n<joint name=\"j" +
           std::to_string(i) + "\" type=\"revolute\"><parent link=\"" + p + "\"/><child link=\"" +
           c +
           "\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" "
           "velocity=\"1\"/></joint>\n";
    }
    return s + "</robot>\n";
  }
  if (kind == "long_line") return std::string(static_cast<std::size_t>(n), '1') + "\n";
  if (kind == "csv_rows_bad_last") {  // n - 1 rows of zeros, then one whose q2 is not a number
    s = generate("csv_rows", n - 1);
    s += std::to_string(n - 1) + ",0,x";
    for (int k = 0; k < 22; ++k) s += ",0";
    return s + "\n";
  }
  if (kind == "csv_rows") {  // a PUMA dataset of n rows of zeros (a valid header)
    s = "t";
    for (const char* g : {"q", "dq", "ddq", "tau"})
      for (int j = 1; j <= 6; ++j) s += std::string(",") + g + std::to_string(j);
    s += "\n";
    std::string zeros;
    for (int k = 0; k < 24; ++k) zeros += ",0";
    for (long i = 0; i < n; ++i) s += std::to_string(i) + zeros + "\n";
    return s;
  }
  throw std::runtime_error("unknown generator " + kind);
}

/// Every regular file under dir (relative path -> contents), and the other entries' types.
std::map<std::string, std::string> snapshot(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(entry.path(), dir).string();
    const fs::file_status st = fs::symlink_status(entry.path());
    if (fs::is_regular_file(st))
      out[rel] = readFile(entry.path().string());
    else
      out[rel] = "<" + std::to_string(static_cast<int>(st.type())) + ">";
  }
  return out;
}

void setUp(const Case& c, const std::string& dir) {
  for (const std::vector<std::string>& step : c.steps) {
    const std::string& op = step[0];
    const std::string path = step.size() > 1 ? dir + "/" + step[1] : dir;
    if (op == "file") {
      std::ofstream(path, std::ios::binary) << c.files.at(step[1]);
    } else if (op == "fixture") {
      const std::string target = dir + "/" + (step.size() > 2 ? step[2] : step[1]);
      fs::copy(fixtures() + "/" + step[1], target,
               fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    } else if (op == "source") {  // source PATH [AS]: a file or directory of the repository
      const std::string target =
          dir + "/" + (step.size() > 2 ? step[2] : fs::path(step[1]).filename().string());
      fs::copy(std::string(DYNID_SOURCE_DIR) + "/" + step[1], target,
               fs::copy_options::recursive | fs::copy_options::overwrite_existing);
      fs::permissions(target, fs::perms::owner_write, fs::perm_options::add);
      if (fs::is_directory(target))
        for (const auto& entry : fs::recursive_directory_iterator(target))
          fs::permissions(entry.path(), fs::perms::owner_write, fs::perm_options::add);
    } else if (op == "patch" || op == "remove") {
      nlohmann::json j = nlohmann::json::parse(readFile(path));
      const nlohmann::json::json_pointer pointer(step.at(2));
      if (op == "patch")
        j[pointer] = nlohmann::json::parse(step.at(3));
      else {
        nlohmann::json& parent = j.at(pointer.parent_pointer());
        if (parent.is_array())
          parent.erase(std::stoul(pointer.back()));
        else
          parent.erase(pointer.back());
      }
      std::ofstream(path, std::ios::binary) << j.dump(1);
    } else if (op == "replace") {  // replace FILE |old|new|: every occurrence; \xNN: that byte
      const std::string spec = step.at(2);
      const char delimiter = spec.at(0);
      const std::size_t middle = spec.find(delimiter, 1);
      const std::string from = spec.substr(1, middle - 1);
      std::string to = spec.substr(middle + 1, spec.size() - middle - 2);
      for (std::size_t k = to.find("\\x"); k != std::string::npos && k + 4 <= to.size();
           k = to.find("\\x", k + 1))
        to.replace(k, 4, 1, static_cast<char>(std::stoi(to.substr(k + 2, 2), nullptr, 16)));
      std::string text = readFile(path);
      const std::size_t at = text.find(from);
      if (at == std::string::npos)
        throw std::runtime_error(c.source + ": replace: '" + from + "' not in " + step[1]);
      for (std::size_t k = at; k != std::string::npos; k = text.find(from, k + to.size()))
        text.replace(k, from.size(), to);
      std::ofstream(path, std::ios::binary) << text;
    } else if (op == "truncate") {
      fs::resize_file(path, std::stoul(step.at(2)));
    } else if (op == "append") {
      std::ofstream(path, std::ios::binary | std::ios::app) << step.at(2) << "\n";
    } else if (op == "generate") {
      const std::vector<std::string> args = words(step.at(2), 2);
      std::ofstream(path, std::ios::binary) << generate(args.at(0), std::stol(args.at(1)));
    } else if (op == "mkdir") {
      fs::create_directories(path);
    } else if (op == "fifo") {
      if (::mkfifo(path.c_str(), 0600) != 0) throw std::runtime_error("mkfifo " + path);
    } else if (op == "chmod") {
      fs::permissions(path, static_cast<fs::perms>(std::stoi(step.at(2), nullptr, 8)));
    } else {
      throw std::runtime_error(c.source + ": unknown directive " + op);
    }
  }
}

void PrintTo(const Case& c, std::ostream* out) { *out << c.source << " " << c.name; }

class BadInput : public ::testing::TestWithParam<Case> {};

TEST_P(BadInput, RefusedCleanly) {
  const Case& c = GetParam();
  ASSERT_FALSE(c.command.empty()) << c.source << ": no run";
  ASSERT_GE(c.exit_code, 0) << c.source << ": no exit";
  const std::string dir = std::string(DYNID_TEST_TMP) + "/bad_input/" + c.name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  if (!c.pending.empty()) GTEST_SKIP() << "pending: " << c.pending;
#ifdef DYNID_SANITIZED
  if (c.memory_mb > 0) GTEST_SKIP() << "a sanitizer's shadow memory does not fit under ulimit -v";
#endif
  setUp(c, dir);
  const auto before = snapshot(dir);
  const std::string limit =
      c.memory_mb > 0 ? "ulimit -v " + std::to_string(c.memory_mb * 1024) + " && " : "";
  // A hang is a failure: `timeout` ends it (exit 124) well inside CTest's own limit.
  const test::Result r = runIn(dir, limit + "timeout -k 5 100 " + std::string(DYNID_BIN) + " " +
                                        c.command + " <'" + c.stdin_file + "'");
  SCOPED_TRACE(c.source + ": dynid " + c.command + "\nstderr: " + r.err);
  EXPECT_NE(r.code, 124) << "hung (killed after 100 s)";
  EXPECT_EQ(r.code, c.exit_code);
  for (const std::string& fragment : c.expected)
    EXPECT_TRUE(test::contains(r.err, fragment)) << "the message does not name: " << fragment;
  for (const char* crash : {"bad_alloc", "terminate called", "Sanitizer",
                            "runtime error:", "Segmentation", "core dumped"})
    EXPECT_FALSE(test::contains(r.err, crash)) << crash;
  if (c.exit_code != 0) {
    EXPECT_FALSE(r.err.empty()) << "refused without a message";
  }
  auto after = snapshot(dir);
  for (const std::string& allowed : c.may_write) after.erase(allowed);
  auto expected = before;
  for (const std::string& allowed : c.may_write) expected.erase(allowed);
  for (const auto& [file, content] : after) {
    const auto it = expected.find(file);
    if (it == expected.end())
      ADD_FAILURE() << "created " << file;
    else if (it->second != content)
      ADD_FAILURE() << "changed " << file;
  }
  for (const auto& [file, content] : expected)
    if (!after.count(file)) ADD_FAILURE() << "removed " << file;
  if (!HasFailure()) fs::remove_all(dir);
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) {
  std::string name = info.param.name;
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Cases, BadInput, ::testing::ValuesIn(allCases()), caseName);

TEST(BadInputSuite, HasAtLeast150Cases) { EXPECT_GE(allCases().size(), 150u); }

}  // namespace
}  // namespace dynid
