#include "data/bags/mcap.hpp"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "core/memory.hpp"
#include "data/bags/bytes.hpp"

namespace dynid::bags {

static_assert(std::endian::native == std::endian::little, "MCAP is little-endian, as this host");

std::uint32_t crc32Of(std::string_view bytes, std::uint32_t crc) {
  // zlib's crc32 takes at most a uInt at a time.
  while (!bytes.empty()) {
    const auto n = static_cast<uInt>(std::min<std::size_t>(bytes.size(), 1u << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), n));
    bytes.remove_prefix(n);
  }
  return crc;
}

namespace {

constexpr char kMagic[] = "\x89MCAP0\r\n";
constexpr std::size_t kMagicSize = 8;

enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kDataEnd = 0x0F,
};

/// The chunk's records, decompressed: exactly `size` bytes or a ParseError.
std::string decompress(const std::string& file, std::uint64_t at, std::string_view compression,
                       std::string_view data, std::uint64_t size) {
  if (size > kMaxMcapRecord)
    throw ParseError(file, 0, "chunk",
                     "at byte " + std::to_string(at) + ": an uncompressed size of " +
                         std::to_string(size) + " bytes, above the 2 GiB a chunk may hold");
  // Robot data never compresses 1000:1; a size beyond that is a damaged field, refused before
  // the allocation it would cause.
  if (static_cast<double>(size) > 1000.0 * static_cast<double>(data.size()) + 1048576.0)
    throw ParseError(file, 0, "chunk",
                     "at byte " + std::to_string(at) + ": " + std::to_string(data.size()) +
                         " compressed bytes claim " + std::to_string(size) +
                         " uncompressed (more than 1000:1: damaged)");
  requireMemory(static_cast<double>(size), file + ": a chunk of " + std::to_string(size) +
                                               " bytes at byte " + std::to_string(at));
  std::string out;
  if (compression.empty()) {
    out.assign(data);
  } else if (compression == "zstd") {
    out.resize(static_cast<std::size_t>(size));
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), data.data(), data.size());
    if (ZSTD_isError(n))
      throw ParseError(file, 0, "chunk",
                       "at byte " + std::to_string(at) + ": zstd: " + ZSTD_getErrorName(n));
    out.resize(n);
  } else if (compression == "lz4") {
    out.resize(static_cast<std::size_t>(size));
    if (const std::string error = lz4Frame(data, out); !error.empty())
      throw ParseError(file, 0, "chunk", "at byte " + std::to_string(at) + ": " + error);
  } else {
    throw ParseError(file, 0, "chunk",
                     "at byte " + std::to_string(at) + ": unknown compression '" +
                         std::string(compression) + "' (dynid reads none, zstd and lz4)");
  }
  if (out.size() != size)
    throw ParseError(file, 0, "chunk",
                     "at byte " + std::to_string(at) + ": " + std::to_string(out.size()) +
                         " bytes after decompression, the chunk says " + std::to_string(size) +
                         " (a truncated or damaged chunk)");
  return out;
}

}  // namespace

McapReader::McapReader(std::string path) : path_(std::move(path)) {}

void McapReader::read(const std::function<void(const McapMessage&)>& on_message) {
  ByteFile in(path_);
  std::string magic = in.read(kMagicSize, "magic");
  if (magic != std::string_view(kMagic, kMagicSize))
    throw ParseError(path_, 0, "magic", "at byte 0: not an MCAP file (its first 8 bytes differ)");
  bool header = false;
  while (true) {
    if (in.atEnd())
      throw ParseError(path_, 0, "data end",
                       "at byte " + std::to_string(in.offset()) +
                           ": the file ends before its Data End record (a recording cut short? "
                           "`mcap recover` rewrites what it holds)");
    const std::uint64_t at = in.offset();
    const std::string prefix = in.read(9, "record");
    const auto op = static_cast<std::uint8_t>(prefix[0]);
    std::uint64_t length = 0;
    std::memcpy(&length, prefix.data() + 1, 8);
    if (length > kMaxMcapRecord || length > in.remaining())
      throw ParseError(path_, 0, "record",
                       "at byte " + std::to_string(at) + ": a record of " + std::to_string(length) +
                           " bytes, " +
                           (length > in.remaining() ? "past the end of the file"
                                                    : "above the 2 GiB a record may hold"));
    if (!header && op != kHeader)
      throw ParseError(path_, 0, "header",
                       "at byte " + std::to_string(at) + ": the first record is not a Header");
    header = true;
    if (op == kDataEnd || op == kFooter) return;  // the summary is an index: not needed
    if (op != kHeader && op != kSchema && op != kChannel && op != kMessage && op != kChunk) {
      in.skip(length);  // attachments, metadata, indexes, private records
      continue;
    }
    const std::string content = in.read(length, "record");
    Cursor r(content, path_, at + 9);
    if (op == kChunk) {
      r.get<std::uint64_t>("message_start_time");
      r.get<std::uint64_t>("message_end_time");
      const auto size = r.get<std::uint64_t>("uncompressed_size");
      const auto crc = r.get<std::uint32_t>("uncompressed_crc");
      const std::string_view compression = r.string("compression");
      const auto compressed = r.get<std::uint64_t>("records length");
      const std::string_view data = r.bytes(compressed, "records");
      const std::string plain = decompress(path_, at, compression, data, size);
      if (crc != 0 && crc32Of(plain) != crc)
        throw ParseError(path_, 0, "chunk",
                         "at byte " + std::to_string(at) +
                             ": the records' CRC does not match (a damaged chunk)");
      Cursor inner(plain, path_, at);
      while (!inner.done()) {
        const auto inner_op = inner.get<std::uint8_t>("opcode");
        const auto inner_length = inner.get<std::uint64_t>("record length");
        Cursor record = inner.sub(inner_length, "record");
        handle(inner_op, at, record, on_message);
      }
    } else {
      handle(op, at, r, on_message);
    }
  }
}

void McapReader::handle(std::uint8_t op, std::uint64_t at, Cursor& r,
                        const std::function<void(const McapMessage&)>& on_message) {
  if (op == kHeader) {
    profile_ = std::string(r.string("profile"));
  } else if (op == kSchema) {
    McapSchema s;
    s.id = r.get<std::uint16_t>("schema id");
    s.name = std::string(r.string("schema name"));
    s.encoding = std::string(r.string("schema encoding"));
    s.data = std::string(r.string("schema data"));
    if (s.id != 0) schemas_[s.id] = std::move(s);  // id 0 is invalid: ignored, as specified
  } else if (op == kChannel) {
    McapChannel ch;
    ch.id = r.get<std::uint16_t>("channel id");
    ch.schema_id = r.get<std::uint16_t>("schema id");
    ch.topic = std::string(r.string("topic"));
    ch.message_encoding = std::string(r.string("message encoding"));
    channels_[ch.id] = std::move(ch);
  } else if (op == kMessage) {
    McapMessage m;
    m.channel_id = r.get<std::uint16_t>("channel id");
    m.sequence = r.get<std::uint32_t>("sequence");
    m.log_time = r.get<std::uint64_t>("log time");
    m.publish_time = r.get<std::uint64_t>("publish time");
    m.data = r.rest();
    m.offset = at;
    if (channels_.count(m.channel_id) == 0)
      throw ParseError(path_, 0, "message",
                       "at byte " + std::to_string(at) + ": a message on channel " +
                           std::to_string(m.channel_id) +
                           ", which no Channel record before it "
                           "defines");
    on_message(m);
  }
  // Other records inside a chunk: skipped (the specification allows future and private ones).
}

}  // namespace dynid::bags
