#include "analysis/logs/raw_log.hpp"

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::writeTemp;

TEST(RawLog, TablesWithAndWithoutHeadersAndAnyDelimiter) {
  const RawTable csv = readRawTable(writeTemp(
      "a.csv", "# a comment\ntime,q_1,q_2,tau_1,tau_2\n0,1,2,3,4\n\n0.001,1.5,2.5,3.5,4.5\n"));
  ASSERT_EQ(csv.names.size(), 5u);
  EXPECT_EQ(csv.names[1], "q_1");
  EXPECT_EQ(csv.values.rows(), 2);
  EXPECT_EQ(csv.values(1, 4), 4.5);
  EXPECT_EQ(csv.first_data_line, 3);
  const RawTable tsv = readRawTable(writeTemp("a.tsv", "0\t1\t2\n1\t3\t4\n"));
  EXPECT_EQ(tsv.names, (std::vector<std::string>{"1", "2", "3"}));
  const RawTable blanks = readRawTable(writeTemp("a.txt", "t  a b\n 0   1 2\n1 3   4\n"));
  EXPECT_EQ(blanks.names[2], "b");
  EXPECT_EQ(blanks.values(1, 2), 4.0);
  const RawTable semicolons = readRawTable(writeTemp("b.csv", "t;x\n0;1e-3\n"));
  EXPECT_EQ(semicolons.values(0, 1), 1e-3);
}

TEST(RawLog, ErrorsNameTheFileLineAndColumn) {
  const auto fails = [](const std::string& text, int line, const std::string& column) {
    const std::string path = writeTemp("bad.csv", text);
    try {
      readRawTable(path);
      ADD_FAILURE() << text;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_EQ(e.element(), column) << e.what();
    }
  };
  fails("t,q1\n0,1\n1,nan\n", 3, "q1");
  fails("t,q1\n0,1\n1,2,3\n", 3, "");
  fails("t,q1\n0,1\n1,abc\n", 3, "q1");
  fails("t,q1\n", 0, "");
}

TEST(RawLog, MissingValuesAreSkippedWhenAskedAndNamedWhenNot) {
  // Lines 3 (nan), 5 (empty) and 6 (-inf in a kept column) are dropouts; line 7's text in a
  // column not asked for is never parsed; any other text is still an error.
  const std::string path =
      writeTemp("dropouts.csv", "t,q1,note\n0,1,a\n1,nan,b\n2,3,c\n3,,d\n4,-INF,e\n5,6,text\n");
  const RawTable header = readRawHeader(path);
  std::vector<Eigen::Index> skipped;
  std::vector<int> lines;
  const Eigen::MatrixXd kept = readRawColumns(header, {0, 1}, nullptr, &skipped, &lines);
  ASSERT_EQ(kept.rows(), 3);
  EXPECT_EQ(kept(0, 0), 0.0);
  EXPECT_EQ(kept(1, 0), 2.0);
  EXPECT_EQ(kept(1, 1), 3.0);
  EXPECT_EQ(kept(2, 1), 6.0);
  EXPECT_EQ(skipped, (std::vector<Eigen::Index>{1, 3, 4}));
  EXPECT_EQ(lines, (std::vector<int>{3, 5, 6}));
  try {  // without skipping: refused at the first, with the way out
    readRawColumns(header, {0, 1});
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("`skip_missing`"), std::string::npos) << e.what();
  }
  try {  // text is not a dropout
    skipped.clear();
    readRawColumns(header, {0, 2}, nullptr, &skipped);
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(std::string(e.what()).find("`skip_missing`"), std::string::npos) << e.what();
  }
}

// --decimal-comma: ',' as the decimal point, fields separated by ';', tab or blanks; the same
// numbers as the table written with '.' (time stamps in 64-bit precision too). Without the option
// the field is an error naming it; a ',' separated table cannot have decimal commas.
TEST(RawLog, DecimalCommaTablesReadAsTheirPointTwins) {
  const auto columns = [](const std::string& path, bool comma) {
    const RawTable header = readRawHeader(path, comma);
    long double origin = 0.0L;
    Eigen::MatrixXd v = readRawColumns(header, {0, 1, 2}, &origin);
    v.col(0).array() += static_cast<double>(origin);
    return v;
  };
  const std::string point = writeTemp(
      "point.csv", "t[ms];q1[deg];tau1\n123456789.017;-0.25;1e-3\n123456794.041;12.5;2\n");
  const Eigen::MatrixXd expected = columns(point, false);
  for (const auto& [name, text] :
       {std::pair{"comma_semicolon.csv",
                  "t[ms];q1[deg];tau1\n123456789,017;-0,25;1e-3\n123456794,041;12,5;2\n"},
        std::pair{"comma_headerless.csv", "123456789,017;-0,25;1e-3\n123456794,041;12,5;2\n"},
        std::pair{"comma_tab.tsv", "123456789,017\t-0,25\t1e-3\n123456794,041\t12,5\t2\n"},
        std::pair{"comma_blanks.txt", "123456789,017 -0,25 1e-3\n123456794,041  12,5 2\n"}})
    EXPECT_EQ(columns(writeTemp(name, text), true), expected) << name;
  try {
    columns(writeTemp("comma_unasked.csv", "t;q1;tau1\n0,5;1;2\n"), false);
    ADD_FAILURE() << "a decimal comma read without the option";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("`decimal_comma`"), std::string::npos) << e.what();
  }
  // A ',' separated table: no hint (its commas separate), and the option is refused.
  try {
    columns(writeTemp("comma_csv.csv", "t,q1,tau1\n0,x,2\n"), false);
    ADD_FAILURE() << "text read as a number";
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()).find("`decimal_comma`"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readRawHeader(writeTemp("comma_csv2.csv", "0,1,2\n1,3,4\n"), true), ParseError);
}

TEST(RawLog, AByteOrderMarkIsNotPartOfTheHeader) {
  const RawTable t = readRawTable(writeTemp("bom.csv", "\xEF\xBB\xBFtime,q1\n0,1\n1,2\n"));
  ASSERT_EQ(t.names.size(), 2u);
  EXPECT_EQ(t.names[0], "time");
  EXPECT_EQ(selectColumns(t, "time", 1, "--time"), std::vector<int>{0});
}

TEST(RawLog, ATableMustBeARegularFileAndLinesHaveALimit) {
  // A table is read twice: a FIFO (a pipe) is refused before it is opened.
  const std::string fifo = test::tempPath("log.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  RawTable header;
  header.file = fifo;
  header.names = {"t", "q1"};
  header.first_data_line = 1;
  header.delimiter = ',';
  EXPECT_THROW(readRawColumns(header, {0, 1}), ParseError);
  // A line of 65 MiB without a break is not a log.
  const std::string long_line = writeTemp("long.csv", std::string((65u << 20), '1'));
  try {
    readRawHeader(long_line);
    ADD_FAILURE() << "a 65 MiB line was read";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 1);
  }
}

TEST(RawLog, ValueFilesShapeIntoSamples) {
  const Eigen::MatrixXd m = readValueFile(writeTemp("q.txt", "1\n2\n3\n4\n5\n6\n"), 3);
  ASSERT_EQ(m.rows(), 2);
  EXPECT_EQ(m(1, 0), 4.0);
  EXPECT_THROW(readValueFile(writeTemp("short.txt", "1\n2\n3\n4\n"), 3), ParseError);
  try {
    readValueFile(writeTemp("bad.txt", "1\n2\nx\n"), 1);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3);
  }
}

TEST(RawLog, SelectorsByNameIndexAndGlob) {
  const RawTable t = readRawTable(
      writeTemp("sel.csv", "time,q1,q2,q3,dq1,dq2,dq3,tau1,tau2,tau3\n0,1,2,3,4,5,6,7,8,9\n"));
  EXPECT_EQ(selectColumns(t, "q*", 3, "q"), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(selectColumns(t, "tau?", -1, "tau"), (std::vector<int>{7, 8, 9}));
  EXPECT_EQ(selectColumns(t, "1", 1, "time"), (std::vector<int>{0}));
  EXPECT_EQ(selectColumns(t, "dq3,dq1", 2, "dq"), (std::vector<int>{6, 4}));
  EXPECT_THROW(selectColumns(t, "q*", 2, "q"), ParseError);          // the wrong count
  EXPECT_THROW(selectColumns(t, "torque*", -1, "tau"), ParseError);  // matches nothing
  EXPECT_THROW(selectColumns(t, "q1,q*", -1, "q"), ParseError);      // q1 twice
  EXPECT_THROW(selectColumns(t, "11", 1, "time"), ParseError);       // out of range
}

}  // namespace
}  // namespace dynid
