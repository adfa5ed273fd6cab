// The CLI's spelling of the request fields library messages name (`cutoff`, `time_column`): the
// flag that sets each one (--cutoff, --time). Every message the CLI reports, an error or a warning,
// goes through cliText first.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace dynid::cli {

/// The flag that sets request field `field`: "--" and the name with '-' for '_', except the few
/// fields whose flag is named otherwise (time_column: --time, q_columns: --q, ...).
std::string cliFlag(std::string_view field);
/// `text` with each `field` written as its flag (a name that is no command's option, such as a file
/// name in backquotes, is left as it is).
std::string cliText(std::string_view text);
/// Each of `texts` through cliText.
void cliTexts(std::vector<std::string>& texts);
/// Prints each warning on standard error as "<prefix><warning>", through cliText: every warning
/// the CLI prints goes through here.
void printWarnings(const std::vector<std::string>& warnings,
                   const std::string& prefix = "warning: ");

}  // namespace dynid::cli
