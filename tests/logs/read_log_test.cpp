#include "analysis/logs/read_log.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::writeTemp;

TEST(ReadLog, ATableInItsOwnUnitsWithLinesForMessages) {
  LogSource source;
  source.tables = {writeTemp("read_log.csv",
                             "t,q1,q2,dq1,dq2,tau1,tau2\n"
                             "0,10,20,1,2,0.5,0.6\n"
                             "5,11,21,3,4,0.7,0.8\n")};
  // Moved in, not assigned from a literal: GCC 12 warns (-Wrestrict, falsely) on the latter here.
  source.time_column = std::string(1, 't');
  source.q_columns = "q*";
  source.dq_columns = "dq*";
  source.tau_columns = "tau*";
  const RawSignals s = readLog(source, source.tables[0]);
  EXPECT_EQ(s.n, 2);
  EXPECT_EQ(s.rows, 2);
  EXPECT_TRUE(s.has_dq);
  EXPECT_FALSE(s.has_ddq);
  EXPECT_EQ(s.file, source.tables[0]);
  // Columns time, q, tau, dq in that order, and no unit applied (a 5 in the time column is 5).
  EXPECT_EQ(s.time()[1], 5.0);
  EXPECT_EQ(s.q()(1, 1), 21.0);
  EXPECT_EQ(s.tau()(0, 1), 0.6);
  EXPECT_EQ(s.dq()(1, 0), 3.0);
  EXPECT_EQ(s.ddq_at, 1 + 3 * 2);
  EXPECT_EQ(s.line_of(1), 3);  // the header is line 1
}

TEST(ReadLog, OneFilePerSignal) {
  LogSource source;
  source.num_joints = 2;
  source.time_file = writeTemp("read_log_t.txt", "0\n0.001\n0.002\n");
  source.q_file = writeTemp("read_log_q.txt", "1\n2\n3\n4\n5\n6\n");
  source.tau_file = writeTemp("read_log_tau.txt", "7\n8\n9\n10\n11\n12\n");
  const RawSignals s = readLog(source, "");
  EXPECT_EQ(s.rows, 3);
  EXPECT_FALSE(s.has_dq);
  EXPECT_EQ(s.q()(2, 1), 6.0);  // n values per sample, joint after joint
  EXPECT_EQ(s.tau()(0, 0), 7.0);
  EXPECT_EQ(s.file, source.time_file);
  EXPECT_EQ(s.tau_file, source.tau_file);
}

TEST(ReadLog, SourcesThatNameTooLittleOrDisagree) {
  LogSource files;
  files.time_file = writeTemp("read_log_t2.txt", "0\n1\n");
  files.q_file = writeTemp("read_log_q2.txt", "1\n2\n");
  files.tau_file = writeTemp("read_log_tau2.txt", "1\n2\n3\n");
  EXPECT_THROW(readLog(files, ""), InputError);  // no joint count
  files.num_joints = 1;
  try {
    readLog(files, "");  // tau has 3 samples, time 2
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), files.tau_file);
  }
  files.q_file.clear();
  EXPECT_THROW(readLog(files, ""), InputError);
}

}  // namespace
}  // namespace dynid
