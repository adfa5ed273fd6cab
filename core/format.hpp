// The one number formatter of dynid's text (reports, messages, CSV and JSON numbers written as
// text): every number a user reads goes through formatNumber.
#pragma once

#include <string>

namespace dynid {

/// x with `digits` significant digits, as printf's %.*g ("0.0123", "1.23e+06"); with digits = 0
/// the shortest text that reads back as exactly x (std::to_chars: "0.1", "1e+300"). A value that
/// is not finite reads "inf", "-inf" or "nan", or `non_finite` when one is given ("n/a").
std::string formatNumber(double x, int digits = 0, const char* non_finite = nullptr);

/// A long run's progress for a terminal line: "42 %, about 1 min 5 s left" from the done
/// fraction (0 to 1) and the seconds so far, the time left extrapolated linearly; "0 %" before
/// anything is done (no estimate yet), "100 %" at the end. A fraction outside [0, 1] is clamped.
std::string progressText(double done_fraction, double elapsed_seconds);

/// Natural order of names: runs of digits compare as numbers (any length, leading zeros ignored),
/// the rest as text, so "q2" < "q10" and "log_9.db3" < "log_10.db3".
bool naturalLess(const std::string& a, const std::string& b);

}  // namespace dynid
