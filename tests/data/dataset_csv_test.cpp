#include "data/dataset_csv.hpp"
#include "core/format.hpp"

#include <sys/resource.h>

#include <charconv>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

Trajectory sampleTrajectory() {
  std::mt19937_64 rng(1);
  Trajectory t;
  t.resize(2, 4);
  t.time << 0.0, 0.001, 0.002, 0.003;
  t.q = Eigen::MatrixXd::Random(2, 4);
  t.dq = Eigen::MatrixXd::Random(2, 4) * 1e-7;
  t.ddq = Eigen::MatrixXd::Random(2, 4) * 1e5;
  t.tau = Eigen::MatrixXd::Random(2, 4) / 3.0;
  return t;
}

TEST(DatasetCsv, RoundTripIsExact) {
  const std::string path = test::tempPath("round.csv");
  const Trajectory t = sampleTrajectory();
  writeDatasetCsv(path, t);
  const Trajectory back = readDatasetCsv(path, 2);
  EXPECT_EQ(back.time, t.time);
  EXPECT_EQ(back.q, t.q);
  EXPECT_EQ(back.dq, t.dq);
  EXPECT_EQ(back.ddq, t.ddq);
  EXPECT_EQ(back.tau, t.tau);
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t,q1,q2,dq1,dq2,ddq1,ddq2,tau1,tau2");
}

// Blocks of rows formatted on a pool's threads and written in order must give the bytes of one
// row after another: checked against rows spelled here, over many blocks (1260 rows each for 3
// joints) and rounds of them, a last partial block, and numbers of every length (negative zero,
// subnormals, the extremes).
TEST(DatasetCsv, RowsFormattedOnThreadsAreTheRowsInOrder) {
  const int samples = 25 * 1024 + 37;
  Trajectory t;
  t.resize(3, samples);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-320, 308);
  const double special[] = {-0.0,
                            0.0,
                            std::numeric_limits<double>::denorm_min(),
                            -std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::min(),
                            1.0 / 3.0};
  int k = 0;
  for (Eigen::MatrixXd* m : {&t.q, &t.dq, &t.ddq, &t.tau})
    for (Eigen::Index c = 0; c < m->cols(); ++c)
      for (Eigen::Index r = 0; r < m->rows(); ++r, ++k)
        (*m)(r, c) = k % 97 < 6 ? special[k % 97] : std::ldexp(mantissa(rng), exponent(rng));
  for (int i = 0; i < samples; ++i) t.time[i] = 1e9 + i * 1e-3;
  std::string expected = datasetHeader(3) + "\n";
  char number[32];
  const auto spell = [&](double x) {
    expected.append(number, std::to_chars(number, number + sizeof number, x).ptr);
  };
  for (int i = 0; i < samples; ++i) {
    spell(t.time[i]);
    for (const Eigen::MatrixXd* m : {&t.q, &t.dq, &t.ddq, &t.tau})
      for (int j = 0; j < 3; ++j) {
        expected += ',';
        spell((*m)(j, i));
      }
    expected += '\n';
  }
  for (int threads : {0, 1, 2, 3})          // 0: no pool
    for (bool from_rows : {false, true}) {  // the trajectory, or its rows handed over in blocks
      SCOPED_TRACE(std::to_string(threads) + (from_rows ? " from rows" : ""));
      const std::string path = test::tempPath("threads.csv");
      ThreadPool pool(std::max(threads, 1));
      AtomicWriter out(path);
      if (from_rows)
        writeDatasetCsv(
            out, 3, samples,
            [&](int first, int last, Trajectory& chunk) { chunk = t.samples(first, last - first); },
            threads > 0 ? &pool : nullptr);
      else
        writeDatasetCsv(out, t, threads > 0 ? &pool : nullptr);
      out.commit();
      std::ifstream in(path, std::ios::binary);
      const std::string written((std::istreambuf_iterator<char>(in)), {});
      ASSERT_EQ(written.size(), expected.size());
      EXPECT_TRUE(written == expected);
    }
}

// Rows that fail to come (a scratch file that cannot be read) are the caller's error, after the
// round, and rows of the wrong shape are refused rather than formatted.
TEST(DatasetCsv, RowsThatFailToComeAreTheCallersError) {
  const std::string path = test::tempPath("rows.csv");
  ThreadPool pool(3);
  {
    AtomicWriter out(path);
    EXPECT_THROW(writeDatasetCsv(
                     out, 2, 100000,
                     [](int first, int, Trajectory&) {
                       if (first > 0) throw Error("the scratch file cannot be read");
                     },
                     &pool),
                 Error);
  }
  AtomicWriter out(path);
  EXPECT_THROW(writeDatasetCsv(
                   out, 2, 10, [](int, int, Trajectory& chunk) { chunk.resize(2, 3); }, &pool),
               InputError);
}

// A write that fails while the pool formats (here: the file-size limit, EFBIG) is the caller's
// Error naming the file, after the round, not a std::terminate on a worker; the temporary goes
// with the writer and nothing is left in the folder.
TEST(DatasetCsv, AWriteThatFailsOnThePoolPathIsAnErrorAndLeavesNothing) {
  Trajectory t;
  t.resize(7, 20000);  // about 8 MB of text, 36 blocks
  for (int i = 0; i < 20000; ++i) t.time[i] = i * 1e-3;
  t.q.setConstant(1.0 / 3.0);
  t.dq = t.q;
  t.ddq = t.q;
  t.tau = t.q;
  const std::filesystem::path dir = test::tempPath("fsize");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "train.csv").string();
  rlimit previous{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &previous), 0);
  void (*const previous_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit = previous;
  limit.rlim_cur = 3 << 20;  // 3 MB: a few rounds in
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string message;
  {
    ThreadPool pool(2);
    AtomicWriter out(path);
    try {
      writeDatasetCsv(out, t, &pool);  // itself, not the commit after it
    } catch (const Error& e) {
      message = e.what();
    }
  }
  setrlimit(RLIMIT_FSIZE, &previous);
  std::signal(SIGXFSZ, previous_handler);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

void expectError(const std::string& content, int expected_joints, const std::string& fragment) {
  const std::string path = test::tempPath("bad.csv");
  std::ofstream(path) << content;
  try {
    readDatasetCsv(path, expected_joints);
    FAIL() << "expected ParseError containing " << fragment;
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), path);
  }
}

TEST(DatasetCsv, ErrorsNameTheLineAndColumn) {
  const std::string header = "t,q1,dq1,ddq1,tau1\n";
  expectError(header + "0,1,2,3,4\n0.1,1,2,x,4\n", -1, ":3: ddq1: 'x' is not a number");
  expectError(header + "0,1,2,3,4\n0.1,1,2,3\n", -1, ":3: row has 4 fields, the header has 5");
  expectError(header + "0,1,nan,3,4\n", -1, ":2: dq1: 'nan' is not finite");
  expectError(header + "0,1,2,3,4\n0,1,2,3,4\n", -1, ":3: t: time must increase strictly");
  expectError("t,q1,dq1,ddq1,torque1\n0,1,2,3,4\n", -1,
              ":1: column 5: expected 'tau1', found 'torque1'");
  expectError("t,q1,q2\n", -1, ":1: header has 3 columns");
  expectError(header + "0,1,2,3,4\n", 6, "header describes 1 joints, the model has 6");
  expectError("", -1, "empty file");
  expectError(header, -1, "no data rows");
  expectError(header + "0,1,2,3,4\n\n0.1,1,2,3,4\n", -1, ":3: row has 1 fields");
}

TEST(DatasetCsv, AcceptsCrlfAndTrailingBlankLines) {
  const std::string path = test::tempPath("crlf.csv");
  std::ofstream(path) << "t,q1,dq1,ddq1,tau1\r\n0,1,2,3,4\r\n0.5,1,2,3,4e-3\r\n\r\n";
  const Trajectory t = readDatasetCsv(path);
  EXPECT_EQ(t.numSamples(), 2);
  EXPECT_DOUBLE_EQ(t.tau(0, 1), 4e-3);
}

// Rows in the common form take a one-pass parse; any other accepted spelling takes the checked
// one. Both must read the same numbers, and a row the one-pass parse cannot take must still be
// checked field by field.
TEST(DatasetCsv, EverySpellingOfARowReadsTheSameNumbers) {
  const std::string path = test::tempPath("spellings.csv");
  std::ofstream(path) << "t,q1,dq1,ddq1,tau1\n"
                      << "0,1.5,-2,3e-3,0.25\n"                      // plain
                      << "1, 1.5,-2,3e-3,0.25\n"                     // a blank before a field
                      << "2,1.5 ,-2,3e-3,0.25\n"                     // a blank after one
                      << "3,+1.5,-2,3e-3,0.25\n"                     // a '+'
                      << "4,1.5,-2,3e-3,0.25 \t\r\n"                 // trailing blanks
                      << "5,1.5,-2,3e-3,\t0.25\n"                    // a tab before the last
                      << "6,1.5,-2,3e-3,1e-400\n"                    // underflow: 0
                      << "7,1.5,-2,3e-3,4.9406564584124654e-324\n";  // the least subnormal
  const Trajectory t = readDatasetCsv(path, 1);
  ASSERT_EQ(t.numSamples(), 8);
  for (int k = 0; k < 8; ++k) {
    EXPECT_EQ(t.time[k], k);
    EXPECT_EQ(t.q(0, k), 1.5) << k;
    EXPECT_EQ(t.dq(0, k), -2.0) << k;
    EXPECT_EQ(t.ddq(0, k), 3e-3) << k;
  }
  for (int k = 0; k < 6; ++k) EXPECT_EQ(t.tau(0, k), 0.25) << k;
  EXPECT_EQ(t.tau(0, 6), 0.0);
  EXPECT_EQ(t.tau(0, 7), std::numeric_limits<double>::denorm_min());
}

TEST(DatasetCsv, RowsTheOnePassParseRefusesAreNamed) {
  const std::string header = "t,q1,dq1,ddq1,tau1\n";
  expectError(header + "0,1,2,3,4,5\n", -1, ":2: row has 6 fields, the header has 5");
  expectError(header + "0,1,2,3,4 x\n", -1, ":2: tau1: '4 x' is not a number");
  expectError(header + "0,1,2,3,4x\n", -1, ":2: tau1: '4x' is not a number");
  expectError(header + "0,1,,3,4\n", -1, ":2: dq1: '' is not a number");
  expectError(header + "0,1,2,3,inf\n", -1, ":2: tau1: 'inf' is not finite");
  expectError(header + "0,1e999,2,3,4\n", -1, ":2: q1: '1e999' is not finite");
  expectError(header + "0,+-1,2,3,4\n", -1, ":2: q1: '+-1' is not a number");
  expectError(header + "0,1,2,3,\n", -1, ":2: tau1: '' is not a number");
}

TEST(DatasetCsv, AcceptsAByteOrderMark) {
  const std::string path = test::tempPath("bom.csv");
  const Trajectory t = sampleTrajectory();
  writeDatasetCsv(path, t);
  const std::string text = "\xEF\xBB\xBF" + readFile(path);
  writeFileAtomically(path, text);
  EXPECT_EQ(readDatasetCsv(path).q, t.q);
}

TEST(DatasetCsv, UnwritablePathLeavesNoFile) {
  const std::string path = test::tempPath("missing-dir") + "/out.csv";
  EXPECT_THROW(writeDatasetCsv(path, sampleTrajectory()), Error);
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::path(path).parent_path()));
}

/// A longer trajectory of 2 joints: 1000 samples.
Trajectory longTrajectory() {
  Trajectory t;
  t.resize(2, 1000);
  t.time = Eigen::VectorXd::LinSpaced(1000, 0.0, 0.999);
  t.q = Eigen::MatrixXd::Random(2, 1000);
  t.dq = Eigen::MatrixXd::Random(2, 1000);
  t.ddq = Eigen::MatrixXd::Random(2, 1000);
  t.tau = Eigen::MatrixXd::Random(2, 1000);
  return t;
}

TEST(DatasetReader, ChunksOfAnySizeGiveTheWholeFile) {
  const std::string path = test::tempPath("chunks.csv");
  const Trajectory t = longTrajectory();
  writeDatasetCsv(path, t);
  ThreadPool pool(3);
  for (auto [size, threads] : {std::pair{1, 1}, {7, 1}, {999, 3}, {1000, 1}, {4096, 3}}) {
    DatasetReader reader(path, 2);
    EXPECT_EQ(reader.numJoints(), 2);
    Trajectory chunk;
    int at = 0;
    while (const int got = reader.read(chunk, size, threads > 1 ? &pool : nullptr)) {
      ASSERT_LE(at + got, 1000);
      EXPECT_EQ(chunk.numSamples(), got);
      EXPECT_EQ(chunk.time, t.time.segment(at, got)) << size;
      EXPECT_EQ(chunk.tau, t.tau.middleCols(at, got)) << size;
      EXPECT_EQ(chunk.ddq, t.ddq.middleCols(at, got)) << size;
      at += got;
    }
    EXPECT_EQ(at, 1000);
    EXPECT_EQ(reader.samplesRead(), 1000);
    EXPECT_EQ(reader.read(chunk, size), 0);  // stays at the end
  }
}

TEST(DatasetReader, ErrorsAcrossChunksNameTheirLine) {
  const std::string path = test::tempPath("chunk_errors.csv");
  const Trajectory t = longTrajectory();
  writeDatasetCsv(path, t);
  std::string text = readFile(path);
  // Line 502 (the 501st sample) repeats the time of line 501: found across a chunk boundary.
  std::size_t at = 0;
  for (int line = 1; line < 502; ++line) at = text.find('\n', at) + 1;
  text.replace(at, text.find(',', at) - at, formatNumber(t.time[499]));
  // And line 900's first field is not a number: later in the file, reported second.
  for (int line = 502; line < 900; ++line) at = text.find('\n', at) + 1;
  text.replace(at, text.find(',', at) - at, "x");
  writeFileAtomically(path, text);
  ThreadPool pool(2);
  for (ThreadPool* threads : {static_cast<ThreadPool*>(nullptr), &pool}) {
    DatasetReader reader(path, 2);
    Trajectory chunk;
    EXPECT_EQ(reader.read(chunk, 500, threads), 500);  // lines 2..501
    try {
      reader.read(chunk, 500, threads);  // blocks of rows parsed on two threads
      FAIL() << "expected a ParseError";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), 502) << e.what();
      EXPECT_EQ(e.element(), "t");
    }
  }
  // Without the time error, the parse error's line.
  text = readFile(path);
  at = 0;
  for (int line = 1; line < 502; ++line) at = text.find('\n', at) + 1;
  text.replace(at, text.find(',', at) - at, formatNumber(t.time[500]));
  writeFileAtomically(path, text);
  DatasetReader reader(path, 2);
  Trajectory chunk;
  try {
    while (reader.read(chunk, 4096, &pool) > 0) {
    }
    FAIL() << "expected a ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 900) << e.what();
    EXPECT_EQ(e.element(), "t");
  }
}

TEST(DatasetReader, AFileThatChangesWhileReadIsAnError) {
  const std::string path = test::tempPath("growing.csv");
  const Trajectory t = longTrajectory();
  for (bool grow : {true, false}) {
    writeDatasetCsv(path, t);
    DatasetReader reader(path, 2);
    Trajectory chunk;
    reader.read(chunk, 10);
    if (grow)
      std::ofstream(path, std::ios::app) << "5,1,2,3,4,5,6,7,8\n";
    else
      std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
    try {
      while (reader.read(chunk, 100) > 0) {
      }
      FAIL() << "a file that " << (grow ? "grew" : "shrank") << " was read as if whole";
    } catch (const ParseError& e) {  // a shrunk file may end inside a row
      EXPECT_FALSE(grow) << e.what();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("changed while it was read"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace dynid
