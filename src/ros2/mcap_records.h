#pragma once
// MCAP's record layout (mcap.dev specification, major version 0), shared by the writer and the
// reader: opcodes, fixed sizes, little-endian field writing, a cursor that reads fields from a
// record without ever reading past it, and the reader's parsers of the Schema, Channel and
// Chunk records. Internal to the ros2 module.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

namespace canopy::ros2 {
struct McapSchema;
struct McapChannel;
}  // namespace canopy::ros2

namespace canopy::ros2::mcap {

/// 0x89 "MCAP" '0' "\r\n": the first and the last 8 bytes of every MCAP file.
constexpr char kMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::size_t kMagicSize = sizeof(kMagic);

enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// The record name for messages ("Chunk", "opcode 0x81").
std::string opcode_name(std::uint8_t op);

/// Opcode (1 byte) and content length (uint64) before every record's content.
constexpr std::size_t kRecordPrefixSize = 9;
/// Footer content: summary_start, summary_offset_start, summary_crc.
constexpr std::size_t kFooterContentSize = 20;
constexpr std::size_t kFooterRecordSize = kRecordPrefixSize + kFooterContentSize;
/// Data End content: data_section_crc.
constexpr std::size_t kDataEndRecordSize = kRecordPrefixSize + 4;
/// Message content before its data: channel_id, sequence, log_time, publish_time.
constexpr std::size_t kMessageFixedSize = 2 + 4 + 8 + 8;

/// CRC-32 (ISO-HDLC, the one zlib and the MCAP specification use), continued from `crc`.
std::uint32_t crc32_update(std::uint32_t crc, std::string_view bytes);

// --- Writing: fields appended little-endian to a string -------------------------------------
template <class T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));  // little-endian hosts only (cdr.h)
}
inline void put_string(std::string& out, std::string_view s) {
  put<std::uint32_t>(out, static_cast<std::uint32_t>(s.size()));
  out.append(s);
}
/// Appends the opcode and a length to fill in; returns where the length lies.
inline std::size_t begin_record(std::string& out, std::uint8_t op) {
  out.push_back(static_cast<char>(op));
  const std::size_t at = out.size();
  put<std::uint64_t>(out, 0);
  return at;
}
/// Fills in the length of the record begun at `at` (everything appended since).
inline void end_record(std::string& out, std::size_t at) {
  const std::uint64_t n = out.size() - at - 8;
  std::memcpy(out.data() + at, &n, 8);
}

// --- Reading ---------------------------------------------------------------------------------
/// A malformed record: the reader adds the file and the record's place.
class FormatError : public std::runtime_error {
 public:
  explicit FormatError(const std::string& what) : std::runtime_error(what) {}
};

/// Reads fields in order from one record's content; a field past its end throws FormatError.
class Cursor {
 public:
  Cursor(std::string_view content, const char* record) : data_(content), record_(record) {}
  Cursor(std::string&& content, const char* record) = delete;  // would read a destroyed string
  std::uint8_t u8() { return fixed<std::uint8_t>(); }
  std::uint16_t u16() { return fixed<std::uint16_t>(); }
  std::uint32_t u32() { return fixed<std::uint32_t>(); }
  std::uint64_t u64() { return fixed<std::uint64_t>(); }
  /// A uint32-length-prefixed string.
  std::string string() {
    const std::uint32_t n = u32();
    return std::string(bytes(n, "a string"));
  }
  /// `n` bytes, checked against what is left.
  std::string_view bytes(std::uint64_t n, const char* what = "a field") {
    if (n > remaining())
      throw FormatError(std::string(what) + " of " + std::to_string(n) + " bytes runs past the end of its " +
                        record_ + " record (" + std::to_string(remaining()) + " bytes left)");
    const std::string_view out = data_.substr(pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return out;
  }
  std::size_t remaining() const { return data_.size() - pos_; }
  std::size_t pos() const { return pos_; }
  std::string_view rest() { return bytes(remaining()); }

 private:
  template <class T>
  T fixed() {
    if (sizeof(T) > remaining())
      throw FormatError(std::string("a ") + record_ + " record ends inside its fields (" +
                        std::to_string(data_.size()) + " bytes)");
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string_view data_;
  const char* record_;
  std::size_t pos_ = 0;
};

/// A Schema record's content; FormatError when a field runs past it.
McapSchema parse_schema(std::string_view content);
/// A Channel record's content, its metadata map included; FormatError when a field runs past it.
McapChannel parse_channel(std::string_view content);

/// A Chunk record's fields before its records.
struct ChunkHeader {
  std::uint64_t start_time = 0, end_time = 0, uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;
  std::uint64_t records_size = 0;
};
/// Reads a Chunk record's fields up to its records (which `c` is then at).
ChunkHeader parse_chunk_header(Cursor& c);

}  // namespace canopy::ros2::mcap
