#include "data/digest/sha256.hpp"

#include <cstring>
#include <fstream>
#include <map>
#include <mutex>

#include <sys/stat.h>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#include <immintrin.h>
#endif

#include "core/errors.hpp"

namespace dynid {

namespace {

// FIPS 180-4, 4.2.2: the first 32 bits of the fractional parts of the cube roots of the first 64
// primes.
constexpr std::array<std::uint32_t, 64> kRound = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

constexpr std::uint32_t rotr(std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

#if defined(__x86_64__) || defined(__i386__)
/// The CPU has the SHA extensions and the SSSE3 and SSE4.1 shuffles they go with (CPUID leaf 7
/// EBX bit 29; leaf 1 ECX bits 9 and 19).
bool detectShaNi() {
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (!__get_cpuid(1, &a, &b, &c, &d) || !(c & (1u << 9)) || !(c & (1u << 19))) return false;
  if (!__get_cpuid_count(7, 0, &a, &b, &c, &d)) return false;
  return (b & (1u << 29)) != 0;
}

/// FIPS 180-4's compression of `count` blocks on the SHA extensions. The state lives in two
/// registers as the instructions take it, ABEF and CDGH; each sha256rnds2 does two rounds with
/// the low two words of its message operand (W[t] + K[t]); sha256msg1 and sha256msg2 compute the
/// schedule's sigma0 and sigma1 parts, four words at a time (W[t-7] added between them).
__attribute__((target("sha,sse4.1,ssse3"))) void shaNiBlocks(std::uint32_t* h,
                                                             const unsigned char* p,
                                                             std::size_t count) {
  const __m128i byte_swap = _mm_set_epi64x(0x0c0d0e0f08090a0bLL, 0x0405060700010203LL);
  __m128i dcba = _mm_loadu_si128(reinterpret_cast<const __m128i*>(h));
  __m128i hgfe = _mm_loadu_si128(reinterpret_cast<const __m128i*>(h + 4));
  const __m128i cdab = _mm_shuffle_epi32(dcba, 0xB1);
  const __m128i efgh = _mm_shuffle_epi32(hgfe, 0x1B);
  __m128i abef = _mm_alignr_epi8(cdab, efgh, 8);
  __m128i cdgh = _mm_blend_epi16(efgh, cdab, 0xF0);
  for (; count > 0; --count, p += 64) {
    const __m128i abef_in = abef, cdgh_in = cdgh;
    __m128i w[4];  // the schedule's last 16 words, four to a register, as a ring
    for (int g = 0; g < 16; ++g) {
      __m128i& now = w[g % 4];
      if (g < 4) {
        now = _mm_shuffle_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16 * g)),
                               byte_swap);
      } else {  // W[t] = sigma1(W[t-2]) + W[t-7] + sigma0(W[t-15]) + W[t-16], t = 4g .. 4g+3
        const __m128i& w4 = w[(g + 3) % 4];          // W[t-4 .. t-1]
        const __m128i& w8 = w[(g + 2) % 4];          // W[t-8 .. t-5]
        const __m128i& w12 = w[(g + 1) % 4];         // W[t-12 .. t-9]
        __m128i x = _mm_sha256msg1_epu32(now, w12);  // now holds W[t-16 .. t-13]
        x = _mm_add_epi32(x, _mm_alignr_epi8(w4, w8, 4));
        now = _mm_sha256msg2_epu32(x, w4);
      }
      __m128i msg = _mm_add_epi32(
          now, _mm_loadu_si128(reinterpret_cast<const __m128i*>(kRound.data() + 4 * g)));
      cdgh = _mm_sha256rnds2_epu32(cdgh, abef, msg);
      msg = _mm_shuffle_epi32(msg, 0x0E);
      abef = _mm_sha256rnds2_epu32(abef, cdgh, msg);
    }
    abef = _mm_add_epi32(abef, abef_in);
    cdgh = _mm_add_epi32(cdgh, cdgh_in);
  }
  const __m128i feba = _mm_shuffle_epi32(abef, 0x1B);
  const __m128i dchg = _mm_shuffle_epi32(cdgh, 0xB1);
  dcba = _mm_blend_epi16(feba, dchg, 0xF0);
  hgfe = _mm_alignr_epi8(dchg, feba, 8);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(h), dcba);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(h + 4), hgfe);
}
#else
bool detectShaNi() { return false; }
void shaNiBlocks(std::uint32_t*, const unsigned char*, std::size_t) {}
#endif

}  // namespace

bool Sha256::cpuExtensions() {
  static const bool has = detectShaNi();
  return has;
}

Sha256::Sha256(Engine engine)
    : cpu_(engine == Engine::kFastest && cpuExtensions()),
      // 5.3.3: the first 32 bits of the fractional parts of the square roots of the first 8
      // primes.
      h_{0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
         0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19} {}

void Sha256::blocks(const unsigned char* p, std::size_t count) {
  if (cpu_) {
    shaNiBlocks(h_.data(), p, count);
    return;
  }
  for (; count > 0; --count, p += 64) block(p);
}

void Sha256::block(const unsigned char* p) {
  std::array<std::uint32_t, 64> w;  // 6.2.2, the message schedule
  for (int t = 0; t < 16; ++t)
    w[t] = (std::uint32_t{p[4 * t]} << 24) | (std::uint32_t{p[4 * t + 1]} << 16) |
           (std::uint32_t{p[4 * t + 2]} << 8) | std::uint32_t{p[4 * t + 3]};
  for (int t = 16; t < 64; ++t) {
    const std::uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
    const std::uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
    w[t] = w[t - 16] + s0 + w[t - 7] + s1;
  }
  std::uint32_t a = h_[0], b = h_[1], c = h_[2], d = h_[3], e = h_[4], f = h_[5], g = h_[6],
                h = h_[7];
  for (int t = 0; t < 64; ++t) {
    const std::uint32_t t1 =
        h + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + kRound[t] + w[t];
    const std::uint32_t t2 =
        (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
    h = g, g = f, f = e, e = d + t1, d = c, c = b, b = a, a = t1 + t2;
  }
  h_[0] += a, h_[1] += b, h_[2] += c, h_[3] += d, h_[4] += e, h_[5] += f, h_[6] += g, h_[7] += h;
}

void Sha256::update(std::string_view bytes) {
  length_ += bytes.size();
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t left = bytes.size();
  if (buffered_ > 0) {
    const std::size_t take = std::min(left, 64 - buffered_);
    std::memcpy(buffer_.data() + buffered_, p, take);
    buffered_ += take, p += take, left -= take;
    if (buffered_ < 64) return;
    blocks(buffer_.data(), 1);
    buffered_ = 0;
  }
  const std::size_t whole = left / 64;
  blocks(p, whole);
  p += 64 * whole, left -= 64 * whole;
  std::memcpy(buffer_.data(), p, left);
  buffered_ = left;
}

std::string Sha256::hex() {
  // 5.1.1: a 1 bit, zeros to 56 bytes mod 64, the message's length in bits (64-bit big-endian).
  const std::uint64_t bits = length_ * 8;
  unsigned char pad[72] = {0x80};
  const std::size_t zeros = (buffered_ < 56 ? 56 : 120) - buffered_;
  for (int i = 0; i < 8; ++i) pad[zeros + i] = static_cast<unsigned char>(bits >> (56 - 8 * i));
  update(std::string_view(reinterpret_cast<const char*>(pad), zeros + 8));
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (std::uint32_t word : h_)
    for (int shift = 28; shift >= 0; shift -= 4) out += digits[(word >> shift) & 0xf];
  return out;
}

std::string sha256Hex(std::string_view bytes) {
  Sha256 s;
  s.update(bytes);
  return s.hex();
}

namespace {

/// What identifies a file's contents without reading them: its device and inode, size and
/// modification and change times (ctime moves on every write and cannot be set back).
using FileKey = std::array<long long, 7>;

bool fileKey(const std::string& file, FileKey& key) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  key = {static_cast<long long>(st.st_dev),          static_cast<long long>(st.st_ino),
         static_cast<long long>(st.st_size),         static_cast<long long>(st.st_mtim.tv_sec),
         static_cast<long long>(st.st_mtim.tv_nsec), static_cast<long long>(st.st_ctim.tv_sec),
         static_cast<long long>(st.st_ctim.tv_nsec)};
  return true;
}

}  // namespace

std::string sha256OfFile(const std::string& file) {
  // A file hashed before in this process, unchanged since (its key), is not read again: a
  // command that records a log's digest in its document and in its provenance reads it once.
  static std::mutex mutex;
  static std::map<std::pair<std::string, FileKey>, std::string> known;
  FileKey before{};
  const bool keyed = fileKey(file, before);
  if (keyed) {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = known.find({file, before}); it != known.end()) return it->second;
  }
  const std::string digest = sha256OfStream(file);
  FileKey after{};
  if (keyed && fileKey(file, after) && after == before) {
    const std::lock_guard<std::mutex> lock(mutex);
    known[{file, before}] = digest;
  }
  return digest;
}

std::string sha256OfStream(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("cannot read '" + file + "'");
  Sha256 s;
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    s.update(std::string_view(buffer.data(), static_cast<std::size_t>(in.gcount())));
  }
  if (in.bad()) throw InputError("cannot read '" + file + "'");
  return s.hex();
}

}  // namespace dynid
