#pragma once
// The MCAP reader's state, shared by its two units: mcap_reader.cpp opens the file (Header,
// Footer, summary) and delivers messages; mcap_blocks.cpp reads the data section a block at a
// time (a chunk read and checked, a file without a summary scanned, a block's messages opened).
// Internal to the ros2 module.

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/ros2/compression.h"
#include "canopy/ros2/mcap_reader.h"
#include "mcap_input.h"
#include "mcap_records.h"

namespace canopy::ros2 {

// Named (not anonymous): the Impl's members are of these types.
namespace reader_detail {

constexpr std::uint64_t kMaxHeaderBytes = std::uint64_t(1) << 20;  // profile and library strings
constexpr std::uint64_t kMaxSummaryBytes = std::uint64_t(1) << 30;
constexpr std::uint64_t kMaxSchemaOrChannelBytes = std::uint64_t(256) << 20;
// Messages held at once where chunks overlap in log time (their chunks and entries).
constexpr std::uint64_t kMaxOpenBytes = std::uint64_t(2) << 30;
// A scan groups records into blocks of about this many uncompressed bytes.
constexpr std::uint64_t kScanBlockBytes = std::uint64_t(64) << 20;
// The smallest file: magic, an empty Header, Data End, Footer, magic.
constexpr std::uint64_t kMinFileBytes =
    2 * mcap::kMagicSize + mcap::kRecordPrefixSize + 8 + mcap::kDataEndRecordSize + mcap::kFooterRecordSize;
// Chunk fields before the records: start and end times, sizes, CRC, compression (empty), records length.
constexpr std::uint64_t kChunkFixedBytes = 8 + 8 + 8 + 4 + 4 + 8;

inline std::string bytes_text(std::uint64_t n) { return std::to_string(n) + " bytes"; }

// Compressed records may be a little larger than the data (incompressible data, frame headers).
inline std::uint64_t max_compressed_size(std::uint64_t uncompressed) {
  return uncompressed + uncompressed / 64 + (64 << 10);
}

// A part of the data section whose messages are read together: one chunk (from the summary's
// chunk index), or a run of chunks and loose messages (from a scan).
struct Block {
  std::uint64_t begin = 0, end = 0;  // file range of its records
  std::uint64_t start_time = 0, end_time = 0;
  std::vector<std::uint16_t> channels;  // channels with messages in it (empty: not known)
  bool from_index = false;
  mcap::ChunkHeader index;  // with from_index: what the chunk index says of the chunk
  std::uint64_t chunk_length = 0;
};

// A message of an open block: where its data lies in the block's buffers.
struct Entry {
  std::uint64_t log_time, publish_time;
  std::uint32_t sequence;
  std::uint16_t channel;
  std::uint32_t buffer;
  std::size_t offset, size;
};

struct OpenBlock {
  std::uint64_t begin = 0;
  std::vector<std::string> buffers;
  std::vector<Entry> entries;
  std::size_t next = 0;
  std::uint64_t bytes = 0;
};

}  // namespace reader_detail

// The reader's state: what open() learnt of the file, and the data section's blocks.
struct McapReader::Impl {
  std::string path;
  reader_detail::File file;
  std::string profile, library;
  bool indexed = false;
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
  std::optional<std::uint64_t> message_count;
  std::map<std::uint16_t, std::uint64_t> channel_counts;  // with counts_known
  bool counts_known = false;
  std::uint64_t data_start = 0;  // after the Header
  std::uint64_t data_end = 0;    // where the Data End record starts
  std::uint32_t data_crc = 0;
  std::vector<reader_detail::Block> blocks;  // in file order
  mutable Decompressor decompressor;  // one context for every chunk

  explicit Impl(std::string p) : path(std::move(p)), file(path) {}

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path + ": " + what); }
  [[noreturn]] void fail_at(std::uint64_t offset, const std::string& what) const {
    fail("corrupt MCAP at byte " + std::to_string(offset) + ": " + what);
  }

  void open();
  void read_summary(std::uint64_t summary_start, std::uint64_t footer_offset, std::uint32_t summary_crc,
                    std::string_view footer_prefix);
  void scan();
  void add_schema(McapSchema s, std::uint64_t at);
  void add_channel(McapChannel c, std::uint64_t at);
  // Reads the chunk whose content starts at `content_at`, checks it and calls `on_record(op,
  // content, offset in the records)` for each record inside. Returns the buffer holding the records.
  template <class OnRecord>
  std::string read_chunk(std::uint64_t record_at, std::uint64_t content_size, const reader_detail::Block* indexed_block,
                         mcap::ChunkHeader& header, std::size_t& records_offset, OnRecord&& on_record) const;
  std::unique_ptr<reader_detail::OpenBlock> open_block(const reader_detail::Block& b,
                                                        const std::set<std::uint16_t>* wanted) const;
};

}  // namespace canopy::ros2
