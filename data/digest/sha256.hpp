// Content digests: SHA-256 (FIPS 180-4) of bytes and of files, as the documents record their
// inputs' (a robot file's, a log's) so that a reader can tell the same input from a changed one.
// Written from the standard; checked against its test vectors (tests/digest/sha256_test.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace dynid {

/// SHA-256 fed in pieces: update() any number of times, then hex() once. The compression runs on
/// the CPU's SHA extensions (x86 SHA-NI) where it has them, else portably (the same digest).
class Sha256 {
 public:
  enum class Engine {
    kFastest,   // SHA-NI when the CPU has it, else portable
    kPortable,  // FIPS 180-4's rounds in plain C++ (the reference the tests compare with)
  };
  explicit Sha256(Engine engine = Engine::kFastest);
  /// Whether kFastest runs on the CPU's SHA extensions here.
  static bool cpuExtensions();
  void update(std::string_view bytes);
  /// The digest as 64 lowercase hexadecimal digits; the object is spent afterwards.
  std::string hex();

 private:
  /// Compresses `count` 64-byte blocks from `p` into h_.
  void blocks(const unsigned char* p, std::size_t count);
  void block(const unsigned char* p);  // the portable compression of one block
  bool cpu_ = false;
  std::array<std::uint32_t, 8> h_;
  std::array<unsigned char, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t length_ = 0;  // bytes fed
};

/// SHA-256 of `bytes`, as 64 lowercase hexadecimal digits.
std::string sha256Hex(std::string_view bytes);
/// SHA-256 of the file's contents, read in pieces. Throws InputError naming a file it cannot read.
/// A regular file this process hashed before is not read again while its device, inode, size,
/// modification and change times are the same.
std::string sha256OfFile(const std::string& file);
/// The same, always read.
std::string sha256OfStream(const std::string& file);

}  // namespace dynid
