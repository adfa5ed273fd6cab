#include "data/digest/base64.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(Base64, EncodesAndDecodesTheRfcVectors) {
  // RFC 4648, section 10.
  const std::vector<std::pair<std::string, std::string>> vectors = {{"", ""},
                                                                    {"f", "Zg=="},
                                                                    {"fo", "Zm8="},
                                                                    {"foo", "Zm9v"},
                                                                    {"foob", "Zm9vYg=="},
                                                                    {"fooba", "Zm9vYmE="},
                                                                    {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : vectors) {
    EXPECT_EQ(base64Encode(plain), coded);
    EXPECT_EQ(base64Decode(coded), plain);
  }
}

TEST(Base64, RefusesWhatIsNotBase64) {
  for (const char* bad : {"Zg=", "Zg=a", "Z===", "Zm9v!mFy", "=Zm9", "Zh==", "Zm9=Zm9v"})
    EXPECT_THROW(base64Decode(bad), InputError) << bad;
}

TEST(Base64, CarriesDoublesBitForBit) {
  const std::vector<double> values = {0.0,
                                      -0.0,
                                      1.0 / 3.0,
                                      -2.5e-300,
                                      1e308,
                                      std::numeric_limits<double>::denorm_min(),
                                      std::numeric_limits<double>::infinity()};
  const std::string text = doublesToBase64(values.data(), values.size());
  const std::vector<double> back = doublesFromBase64(text);
  ASSERT_EQ(back.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    EXPECT_EQ(std::signbit(back[i]), std::signbit(values[i]));
    EXPECT_EQ(back[i], values[i]);
  }
  // Little-endian: 1.0 is 0x3ff0000000000000, its bytes 00 .. 00 f0 3f.
  const double one = 1.0;
  EXPECT_EQ(base64Decode(doublesToBase64(&one, 1)), std::string("\0\0\0\0\0\0\xf0\x3f", 8));
  EXPECT_THROW(doublesFromBase64("Zm9v"), InputError);  // 3 bytes
}

}  // namespace
}  // namespace dynid
