// The field convention of library messages (core/errors.hpp): `name` respelled by a front end,
// anything else in backquotes left as it is.
#include "core/errors.hpp"

#include <gtest/gtest.h>

#include <string>
#include <string_view>

namespace dynid {
namespace {

std::string asFlag(std::string_view field) { return "--" + std::string(field); }

TEST(Errors, FieldsInBackquotesAreRespelledAndNothingElse) {
  EXPECT_EQ(respellFields("`cutoff` must be > 0; give `tau_cutoff` too", asFlag),
            "--cutoff must be > 0; give --tau_cutoff too");
  // Not a field: words with a space, capitals, a digit first, an empty pair, an unclosed quote.
  EXPECT_EQ(respellFields("`dynid prepare` and `Fc3` and `3d` and `` and `open", asFlag),
            "`dynid prepare` and `Fc3` and `3d` and `` and `open");
  EXPECT_EQ(respellFields("`q_columns`'s `dq_max2`", asFlag), "--q_columns's --dq_max2");
  EXPECT_EQ(respellFields("", asFlag), "");
  EXPECT_EQ(respellFields("no fields", asFlag), "no fields");
}

TEST(Errors, AParseErrorNamesFileLineAndElement) {
  const ParseError e("log.csv", 3, "`time_column`", "no column 'x'");
  EXPECT_STREQ(e.what(), "log.csv:3: `time_column`: no column 'x'");
  EXPECT_EQ(respellFields(e.what(), asFlag), "log.csv:3: --time_column: no column 'x'");
}

}  // namespace
}  // namespace dynid
