#include "cli/spelling.hpp"

#include <algorithm>
#include <array>
#include <iostream>
#include <set>
#include <string>
#include <utility>

#include "cli/command_table.hpp"
#include "core/errors.hpp"

namespace dynid::cli {

namespace {

/// The fields whose flag is not their own name: a table's column selectors (LogSource), a floating
/// recording's joint topic and stamps (FloatingLogTopics, FloatingPrepareOptions), the GC error's
/// segment count (GcSegmentOptions, FloatingGcOptions), a standing design's sway (the design file
/// simulate reads, StandingMotionRequest).
constexpr std::array<std::pair<std::string_view, std::string_view>, 9> kFlagOf = {{
    {"joint_topic", "--topic"},
    {"receive_time", "--stamp"},
    {"time_column", "--time"},
    {"q_columns", "--q"},
    {"dq_columns", "--dq"},
    {"ddq_columns", "--ddq"},
    {"tau_columns", "--tau"},
    {"num_segments", "--segments"},
    {"base_design", "--trajectory"},
}};

/// Whether `flag` ("--cutoff") is an option of some command: a name in backquotes that is none
/// (a file name a user wrote so) is left as it is.
bool isFlag(const std::string& flag) {
  static const std::set<std::string> flags = [] {
    std::set<std::string> out;
    for (const CatalogueEntry& entry : optionCatalogue())
      for (const OptionEntry& option : entry.options.options) out.insert("--" + option.name);
    return out;
  }();
  return flags.count(flag) > 0;
}

}  // namespace

std::string cliFlag(std::string_view field) {
  for (const auto& [name, flag] : kFlagOf)
    if (name == field) return std::string(flag);
  std::string out = "--";
  out.append(field);
  std::replace(out.begin() + 2, out.end(), '_', '-');
  return out;
}

std::string cliText(std::string_view text) {
  return respellFields(text, [](std::string_view field) {
    std::string flag = cliFlag(field);
    if (isFlag(flag)) return flag;
    // Appended, not "`" + std::string(field) + "`": GCC 12's -Wrestrict misreads that (PR 105329).
    std::string quoted(1, '`');
    quoted.append(field);
    quoted += '`';
    return quoted;
  });
}

void cliTexts(std::vector<std::string>& texts) {
  for (std::string& text : texts) text = cliText(text);
}

void printWarnings(const std::vector<std::string>& warnings, const std::string& prefix) {
  for (const std::string& w : warnings) std::cerr << prefix << cliText(w) << "\n";
}

}  // namespace dynid::cli
