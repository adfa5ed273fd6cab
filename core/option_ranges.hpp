// The range of every numeric option of dynid's front ends, defined once: the CLI checks each flag
// against it when the command line is parsed (a usage error naming the flag before any work) and
// prints it in --help, the Python module checks each keyword (its snake_case spelling), and
// requests check their fields (exciteRun, logStudyRun). In core so that every floor can check
// against it; it knows nothing but names and numbers. A new numeric option gets its row here;
// docs/RELIABILITY.md lists them.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <string_view>

namespace dynid {

struct OptionRule {
  const char* command;  // "" : every command; else only this one ("excite"), before the ""
  const char* name;     // the CLI's spelling without "--" ("prior-weight")
  double lo, hi;
  bool lo_open;  // x > lo instead of x >= lo
  bool zero_ok;  // 0 (a default or "none") is also taken
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
