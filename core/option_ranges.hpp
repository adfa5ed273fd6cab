// Every numeric option of dynid's front ends, defined once: its range and its help. The CLI checks
// each flag against it when the command line is parsed (a usage error naming the flag before any
// work) and prints the help and the range in --help; the requests check their fields against it
// (SearchRequest::check(), ... : each run function checks its request first), which is how the
// Python module's keywords are checked (their snake_case spelling). In core so that every floor
// can check against it; it knows nothing but names, numbers and words. A new numeric option gets
// its row here; docs/RELIABILITY.md lists them.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <string_view>

namespace dynid {

/// The values an option takes: lo (or above it) to hi, and perhaps 0.
struct OptionRange {
  double lo, hi;
  bool lo_open;  // x > lo instead of x >= lo
  bool zero_ok;  // 0 (a default or "none") is also taken
};

struct OptionRule {
  const char* command;  // "" : every command; else only this one ("excite"), before the ""
  const char* name;     // the CLI's spelling without "--" ("prior-weight")
  OptionRange range;
  const char* help;  // what --help says before the range ("prediction horizon [s]")
};

inline constexpr double kNoOptionLimit = std::numeric_limits<double>::max();

/// Every rule, in table order.
std::span<const OptionRule> optionRules();
/// The rule for option `name` of `command` (its own first, then the one for every command), or
/// null when the option has none.
const OptionRule* findOptionRule(std::string_view command, std::string_view name);
/// ">= 0 and <= 1e+06", "0 or >= 1e-06 and <= 10", "> 0".
std::string optionRangeText(const OptionRule& rule);
/// Throws InputError "<spelling> must be <range>, not <x>" when x is not finite or breaks the
/// rule of `name` for `command` (no rule: only finiteness). `spelling` is how the caller's user
/// writes the option: "--prior-weight", "prior_weight", "refine_seconds".
void checkOption(std::string_view command, std::string_view name, double x,
                 const std::string& spelling);

}  // namespace dynid
