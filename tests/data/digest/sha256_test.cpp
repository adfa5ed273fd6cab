// SHA-256 (data/digest/sha256.hpp) against FIPS 180-4's examples and NIST's long-message vector,
// fed whole and in uneven pieces (across the 64-byte blocks and the padding's boundary).
#include "data/digest/sha256.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Sha256, TheStandardsExamples) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256Hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// Both engines on the standard's examples, then the CPU's against the portable one on seeded bytes
// of every length up to 300 and on 3 MB fed in uneven pieces (the multi-block path).
TEST(Sha256, TheCpuExtensionsGiveThePortableDigest) {
  for (const Sha256::Engine e : {Sha256::Engine::kPortable, Sha256::Engine::kFastest}) {
    Sha256 abc(e);
    abc.update("abc");
    EXPECT_EQ(abc.hex(), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    Sha256 million(e);
    million.update(std::string(1000000, 'a'));
    EXPECT_EQ(million.hex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  }
  std::string bytes;
  std::uint64_t x = 88172645463325252ull;
  for (int i = 0; i < 3000000; ++i) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;  // xorshift64
    bytes += static_cast<char>(x & 0xff);
  }
  const auto digest = [&](Sha256::Engine e, std::size_t length, std::size_t piece) {
    Sha256 s(e);
    for (std::size_t at = 0; at < length; at += piece)
      s.update(std::string_view(bytes).substr(at, std::min(piece, length - at)));
    return s.hex();
  };
  for (std::size_t length = 0; length <= 300; ++length)
    EXPECT_EQ(digest(Sha256::Engine::kFastest, length, 1000),
              digest(Sha256::Engine::kPortable, length, 1000))
        << length;
  EXPECT_EQ(digest(Sha256::Engine::kFastest, bytes.size(), 65537),
            digest(Sha256::Engine::kPortable, bytes.size(), 4096));
  if (!Sha256::cpuExtensions()) GTEST_SKIP() << "no SHA extensions on this CPU: one engine";
}

TEST(Sha256, PiecesGiveTheWholesDigest) {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += static_cast<char>('a' + i * 7 % 26);
  const std::string whole = sha256Hex(text);
  // Lengths around the padding's boundaries (55, 56, 63, 64 bytes) and pieces of every size.
  for (std::size_t length : {55u, 56u, 63u, 64u, 65u, 119u, 120u, 1000u}) {
    const std::string message = text.substr(0, length);
    for (std::size_t piece : {1u, 3u, 63u, 64u, 100u}) {
      Sha256 s;
      for (std::size_t at = 0; at < message.size(); at += piece)
        s.update(std::string_view(message).substr(at, piece));
      EXPECT_EQ(s.hex(), sha256Hex(message)) << length << " in pieces of " << piece;
    }
  }
  const std::string file = test::tempPath("sha256.txt");
  writeFileAtomically(file, text);
  EXPECT_EQ(sha256OfFile(file), whole);
  EXPECT_THROW(sha256OfFile(test::tempPath("no_such_file")), InputError);
}

TEST(Sha256, AFileRewrittenInPlaceIsHashedAgain) {
  const std::string file = test::tempPath("sha256_rewritten.txt");
  { std::ofstream(file) << "first contents"; }
  EXPECT_EQ(sha256OfFile(file), sha256Hex("first contents"));
  EXPECT_EQ(sha256OfFile(file), sha256Hex("first contents"));  // unchanged: remembered
  // The same size, written in place (the same inode): its change time moves.
  { std::fstream(file, std::ios::in | std::ios::out) << "other"; }
  EXPECT_EQ(sha256OfFile(file), sha256Hex("other contents"));
  EXPECT_EQ(sha256OfStream(file), sha256Hex("other contents"));
}

}  // namespace
}  // namespace dynid
