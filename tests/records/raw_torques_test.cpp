// validate_raw.csv read back (analysis/records/raw_torques.hpp).
#include "analysis/records/raw_torques.hpp"

#include <gtest/gtest.h>

#include <string>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(RawTorques, TheRawFileIsCheckedAtTheBoundary) {
  const std::string path = test::tempPath("validate_raw.csv");
  writeFileAtomically(path, "t,tau1,tau2\n0,1,2\n0.001,1,2\n");
  EXPECT_EQ(readRawTorques(path, 2).tau.cols(), 2);
  EXPECT_THROW(readRawTorques(path, 3), ParseError);  // another robot's joint count
  writeFileAtomically(path, "t,tau1,tau2\n0,1,2\n0,1,2\n");
  EXPECT_THROW(readRawTorques(path, 2), ParseError);  // times that do not increase
  writeFileAtomically(path, "t,q1,q2\n0,1,2\n");
  EXPECT_THROW(readRawTorques(path, 2), ParseError);  // a dataset, not raw torques
}

}  // namespace
}  // namespace dynid
