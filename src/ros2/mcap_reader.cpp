#include "canopy/ros2/mcap_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <queue>
#include <set>
#include <tuple>

#include "canopy/ros2/compression.h"
#include "canopy/ros2/message_schemas.h"
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
constexpr std::size_t kReadAheadBytes = std::size_t(1) << 20;
// The smallest file: magic, an empty Header, Data End, Footer, magic.
constexpr std::uint64_t kMinFileBytes =
    2 * mcap::kMagicSize + mcap::kRecordPrefixSize + 8 + mcap::kDataEndRecordSize + mcap::kFooterRecordSize;
// Chunk fields before the records: start and end times, sizes, CRC, compression (empty), records length.
constexpr std::uint64_t kChunkFixedBytes = 8 + 8 + 8 + 4 + 4 + 8;

std::string bytes_text(std::uint64_t n) { return std::to_string(n) + " bytes"; }

// Compressed records may be a little larger than the data (incompressible data, frame headers).
std::uint64_t max_compressed_size(std::uint64_t uncompressed) { return uncompressed + uncompressed / 64 + (64 << 10); }

// A regular file read with pread; a read past its end is InputError (the file is cut short).
class File {
 public:
  File(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO does not hang the open
    if (fd_ < 0) {
      if (errno == ENOENT) throw InputError(path + ": no such file");
      throw InputError(path + ": cannot open: " + std::strerror(errno));
    }
    struct stat st;
    if (::fstat(fd_, &st) != 0) {
      const int err = errno;
      ::close(fd_);
      throw IoError(path + ": cannot read: " + std::strerror(err));
    }
    if (S_ISDIR(st.st_mode)) {
      ::close(fd_);
      throw InputError(path + ": is a folder, not an MCAP file");
    }
    if (!S_ISREG(st.st_mode)) {
      ::close(fd_);
      throw InputError(path + ": is not a regular file (a device or a pipe), not an MCAP file");
    }
    size_ = static_cast<std::uint64_t>(st.st_size);
  }
  ~File() {
    if (fd_ >= 0) ::close(fd_);
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  std::uint64_t size() const { return size_; }
  void read(std::uint64_t offset, std::size_t n, char* out) const {
    while (n > 0) {
      const ssize_t r = ::pread(fd_, out, n, static_cast<off_t>(offset));
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) throw IoError(path_ + ": cannot read: " + std::strerror(errno));
      if (r == 0)
        throw InputError(path_ + ": ends at byte " + std::to_string(offset) + " while more was expected (the file "
                         "shrank while being read?)");
      out += r;
      n -= static_cast<std::size_t>(r);
      offset += static_cast<std::uint64_t>(r);
    }
  }
  std::string read(std::uint64_t offset, std::size_t n) const {
    std::string s(n, '\0');
    read(offset, n, s.data());
    return s;
  }

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

// Small reads through a read-ahead buffer (record prefixes and message headers of a scan).
class Window {
 public:
  Window(const File& file, std::uint64_t end) : file_(file), end_(end) {}
  std::string_view get(std::uint64_t offset, std::size_t n) {
    if (offset < base_ || offset + n > base_ + buf_.size()) {
      const std::uint64_t avail = end_ - offset;  // callers check offset + n <= end
      buf_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(avail, std::max(n, kReadAheadBytes))));
      file_.read(offset, buf_.size(), buf_.data());
      base_ = offset;
    }
    return std::string_view(buf_).substr(static_cast<std::size_t>(offset - base_), n);
  }

 private:
  const File& file_;
  std::uint64_t end_;
  std::uint64_t base_ = 0;
  std::string buf_;
};

McapSchema parse_schema(std::string_view content) {
  mcap::Cursor c(content, "Schema");
  McapSchema s;
  s.id = c.u16();
  s.name = c.string();
  s.encoding = c.string();
  s.data = std::string(c.bytes(c.u32(), "the schema data"));
  return s;
}

McapChannel parse_channel(std::string_view content) {
  mcap::Cursor c(content, "Channel");
  McapChannel ch;
  ch.id = c.u16();
  ch.schema_id = c.u16();
  ch.topic = c.string();
  ch.message_encoding = c.string();
  mcap::Cursor m(c.bytes(c.u32(), "the metadata map"), "Channel");
  while (m.remaining() > 0) {
    std::string key = m.string();
    ch.metadata.emplace_back(std::move(key), m.string());
  }
  return ch;
}

struct ChunkHeader {
  std::uint64_t start_time = 0, end_time = 0, uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;
  std::uint64_t records_size = 0;
};

ChunkHeader parse_chunk_header(mcap::Cursor& c) {
  ChunkHeader h;
  h.start_time = c.u64();
  h.end_time = c.u64();
  h.uncompressed_size = c.u64();
  h.uncompressed_crc = c.u32();
  const std::uint32_t n = c.u32();
  h.compression = std::string(c.bytes(n, "the compression name"));
  h.records_size = c.u64();
  return h;
}

// A part of the data section whose messages are read together: one chunk (from the summary's
// chunk index), or a run of chunks and loose messages (from a scan).
struct Block {
  std::uint64_t begin = 0, end = 0;  // file range of its records
  std::uint64_t start_time = 0, end_time = 0;
  std::vector<std::uint16_t> channels;  // channels with messages in it (empty: not known)
  bool from_index = false;
  ChunkHeader index;  // with from_index: what the chunk index says of the chunk
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
using namespace reader_detail;

struct McapReader::Impl {
  std::string path;
  File file;
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
  std::vector<Block> blocks;  // in file order
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
  std::string read_chunk(std::uint64_t record_at, std::uint64_t content_size, const Block* indexed_block,
                         ChunkHeader& header, std::size_t& records_offset, OnRecord&& on_record) const;
  std::unique_ptr<OpenBlock> open_block(const Block& b, const std::set<std::uint16_t>* wanted) const;
};

void McapReader::Impl::add_schema(McapSchema s, std::uint64_t at) {
  if (s.id == 0) return;  // the specification: a schema id of 0 is invalid and ignored
  const auto it = schemas.find(s.id);
  if (it == schemas.end()) {
    schemas.emplace(s.id, std::move(s));
  } else if (it->second.name != s.name || it->second.encoding != s.encoding || it->second.data != s.data) {
    fail_at(at, "two different schemas share the id " + std::to_string(s.id));
  }
}

void McapReader::Impl::add_channel(McapChannel c, std::uint64_t at) {
  const auto it = channels.find(c.id);
  if (it == channels.end()) {
    channels.emplace(c.id, std::move(c));
  } else if (it->second.topic != c.topic || it->second.schema_id != c.schema_id ||
             it->second.message_encoding != c.message_encoding) {
    fail_at(at, "two different channels share the id " + std::to_string(c.id));
  }
}

void McapReader::Impl::open() {
  const std::uint64_t size = file.size();
  const std::string head = file.read(0, static_cast<std::size_t>(std::min<std::uint64_t>(size, mcap::kMagicSize)));
  if (head.size() < mcap::kMagicSize || std::memcmp(head.data(), mcap::kMagic, mcap::kMagicSize) != 0)
    fail("not an MCAP file (it does not begin with the MCAP magic bytes)");
  if (size < kMinFileBytes) fail("truncated MCAP file: " + bytes_text(size) + ", fewer than any MCAP file has");
  const std::string tail = file.read(size - mcap::kMagicSize, mcap::kMagicSize);
  if (std::memcmp(tail.data(), mcap::kMagic, mcap::kMagicSize) != 0)
    fail("truncated MCAP file: it does not end with the MCAP magic bytes (a recording cut short or not closed)");

  // Header.
  {
    const std::string header_prefix = file.read(mcap::kMagicSize, mcap::kRecordPrefixSize);
    mcap::Cursor prefix(header_prefix, "Header");
    const std::uint8_t op = prefix.u8();
    const std::uint64_t length = prefix.u64();
    if (op != mcap::kHeader) fail_at(mcap::kMagicSize, "the first record is a " + mcap::opcode_name(op) + ", not the Header");
    if (length > kMaxHeaderBytes || length > size - kMinFileBytes + 8)
      fail_at(mcap::kMagicSize, "the Header record claims " + bytes_text(length));
    data_start = mcap::kMagicSize + mcap::kRecordPrefixSize + length;
    try {
      const std::string header = file.read(mcap::kMagicSize + mcap::kRecordPrefixSize, static_cast<std::size_t>(length));
      mcap::Cursor c(header, "Header");
      profile = c.string();
      library = c.string();
    } catch (const mcap::FormatError& e) {
      fail_at(mcap::kMagicSize, e.what());
    }
  }
  if (profile != "ros2")
    fail("an MCAP file of profile '" + profile + "', not ros2 (canopy reads ROS 2 recordings: ros2msg schemas, CDR)");

  // Footer, then the Data End record before the summary.
  const std::uint64_t footer_offset = size - mcap::kMagicSize - mcap::kFooterRecordSize;
  const std::string footer = file.read(footer_offset, mcap::kFooterRecordSize);
  mcap::Cursor f(footer, "Footer");
  const std::uint8_t footer_op = f.u8();
  const std::uint64_t footer_length = f.u64();
  if (footer_op != mcap::kFooter || footer_length != mcap::kFooterContentSize)
    fail_at(footer_offset, "no Footer record before the closing magic bytes (a cut or damaged file)");
  const std::uint64_t summary_start = f.u64();
  const std::uint64_t summary_offset_start = f.u64();
  const std::uint32_t summary_crc = f.u32();
  const std::uint64_t sections_end = summary_offset_start != 0 ? summary_offset_start : footer_offset;
  if (summary_offset_start != 0 &&
      (summary_offset_start > footer_offset || summary_offset_start < data_start + mcap::kDataEndRecordSize))
    fail_at(footer_offset, "the Footer's summary offset start (" + std::to_string(summary_offset_start) +
                               ") lies outside the file");
  if (summary_start != 0 &&
      (summary_start > sections_end || summary_start < data_start + mcap::kDataEndRecordSize))
    fail_at(footer_offset, "the Footer's summary start (" + std::to_string(summary_start) + ") lies outside the file");
  data_end = (summary_start != 0 ? summary_start : sections_end) - mcap::kDataEndRecordSize;
  if (data_end < data_start) fail_at(footer_offset, "the Footer's offsets overlap the Header");
  {
    const std::string data_end_record = file.read(data_end, mcap::kDataEndRecordSize);
    mcap::Cursor d(data_end_record, "Data End");
    const std::uint8_t op = d.u8();
    const std::uint64_t length = d.u64();
    if (op != mcap::kDataEnd || length != 4)
      fail_at(data_end, "no Data End record where the data section ends (found a " + mcap::opcode_name(op) + ")");
    data_crc = d.u32();
  }

  if (summary_start != 0)
    read_summary(summary_start, footer_offset, summary_crc,
                 std::string_view(footer).substr(0, mcap::kRecordPrefixSize + 16));
  // Without chunk indexes the messages (loose, or in chunks nobody indexed) are found by a scan.
  const bool empty = message_count && *message_count == 0;
  if (blocks.empty() && !empty) scan();

  for (const auto& [id, ch] : channels)
    if (ch.schema_id != 0 && schemas.count(ch.schema_id) == 0)
      fail("channel " + std::to_string(id) + " (" + ch.topic + ") names schema " + std::to_string(ch.schema_id) +
           ", which the file does not hold");
}

void McapReader::Impl::read_summary(std::uint64_t summary_start, std::uint64_t footer_offset,
                                    std::uint32_t summary_crc, std::string_view footer_prefix) {
  const std::uint64_t length = footer_offset - summary_start;
  if (length > kMaxSummaryBytes)
    fail_at(summary_start, "a summary section of " + bytes_text(length) + " (canopy reads at most 1 GiB)");
  const std::string summary = file.read(summary_start, static_cast<std::size_t>(length));
  if (summary_crc != 0) {
    const std::uint32_t crc = mcap::crc32_update(mcap::crc32_update(0, summary), footer_prefix);
    if (crc != summary_crc) fail_at(summary_start, "the summary section fails its CRC (a damaged file)");
  }
  std::vector<Block> indexed_blocks;
  std::size_t pos = 0;
  while (pos < summary.size()) {
    const std::uint64_t at = summary_start + pos;
    try {
      mcap::Cursor prefix(std::string_view(summary).substr(pos), "summary");
      const std::uint8_t op = prefix.u8();
      const std::uint64_t size = prefix.u64();
      const std::string_view content = prefix.bytes(size, "a record");
      pos += mcap::kRecordPrefixSize + content.size();
      switch (op) {
        case mcap::kSchema:
          add_schema(parse_schema(content), at);
          break;
        case mcap::kChannel:
          add_channel(parse_channel(content), at);
          break;
        case mcap::kStatistics: {
          mcap::Cursor c(content, "Statistics");
          message_count = c.u64();
          c.u16();  // schemas
          c.u32();  // channels
          c.u32();  // attachments
          c.u32();  // metadata
          c.u32();  // chunks
          c.u64();  // start time
          c.u64();  // end time
          mcap::Cursor m(c.bytes(c.u32(), "the channel message counts"), "Statistics");
          while (m.remaining() > 0) {
            const std::uint16_t channel = m.u16();
            channel_counts[channel] = m.u64();
          }
          counts_known = !channel_counts.empty();
          break;
        }
        case mcap::kChunkIndex: {
          mcap::Cursor c(content, "Chunk Index");
          Block b;
          b.from_index = true;
          b.start_time = c.u64();
          b.end_time = c.u64();
          b.begin = c.u64();
          b.chunk_length = c.u64();
          mcap::Cursor m(c.bytes(c.u32(), "the message index offsets"), "Chunk Index");
          while (m.remaining() > 0) {
            b.channels.push_back(m.u16());
            m.u64();
          }
          c.u64();  // message index length
          b.index.compression = c.string();
          b.index.records_size = c.u64();
          b.index.uncompressed_size = c.u64();
          b.index.start_time = b.start_time;
          b.index.end_time = b.end_time;
          if (!parse_compression(b.index.compression))
            fail_at(at, "a chunk compressed with '" + b.index.compression + "', which canopy cannot read (it reads "
                        "none, lz4 and zstd)");
          if (b.index.uncompressed_size > kMaxChunkUncompressedBytes)
            fail_at(at, "a chunk of " + bytes_text(b.index.uncompressed_size) +
                            " uncompressed (canopy reads chunks of at most 1 GiB)");
          if (b.begin < data_start || b.chunk_length < mcap::kRecordPrefixSize + kChunkFixedBytes ||
              b.chunk_length > data_end - data_start || b.begin > data_end - b.chunk_length)
            fail_at(at, "a chunk index points outside the data section (chunk at byte " + std::to_string(b.begin) +
                            ", " + bytes_text(b.chunk_length) + ")");
          if (b.start_time > b.end_time) fail_at(at, "a chunk index whose time range ends before it starts");
          b.end = b.begin + b.chunk_length;
          std::sort(b.channels.begin(), b.channels.end());
          indexed_blocks.push_back(std::move(b));
          break;
        }
        default:
          break;  // summary offsets, attachment and metadata indexes, records of later versions
      }
    } catch (const mcap::FormatError& e) {
      fail_at(at, e.what());
    }
  }
  std::sort(indexed_blocks.begin(), indexed_blocks.end(), [](const Block& a, const Block& b) { return a.begin < b.begin; });
  for (std::size_t i = 1; i < indexed_blocks.size(); ++i)
    if (indexed_blocks[i].begin < indexed_blocks[i - 1].end)
      fail_at(indexed_blocks[i].begin, "two chunk indexes point at overlapping chunks");
  blocks = std::move(indexed_blocks);
  indexed = !blocks.empty() || (message_count && *message_count == 0);
}

template <class OnRecord>
std::string McapReader::Impl::read_chunk(std::uint64_t record_at, std::uint64_t content_size, const Block* indexed_block,
                                         ChunkHeader& h, std::size_t& records_offset, OnRecord&& on_record) const {
  if (content_size > max_compressed_size(kMaxChunkUncompressedBytes) + 4096)
    fail_at(record_at, "a Chunk record of " + bytes_text(content_size) + " (canopy reads chunks of at most 1 GiB)");
  std::string content = file.read(record_at + mcap::kRecordPrefixSize, static_cast<std::size_t>(content_size));
  std::string_view records;
  try {
    mcap::Cursor c(content, "Chunk");
    h = parse_chunk_header(c);
    records = c.bytes(h.records_size, "the chunk's records");
  } catch (const mcap::FormatError& e) {
    fail_at(record_at, e.what());
  }
  const auto compression = parse_compression(h.compression);
  if (!compression)
    fail_at(record_at, "a chunk compressed with '" + h.compression + "', which canopy cannot read (it reads none, lz4 "
                       "and zstd)");
  if (h.uncompressed_size > kMaxChunkUncompressedBytes)
    fail_at(record_at, "a chunk of " + bytes_text(h.uncompressed_size) + " uncompressed (canopy reads chunks of at "
                       "most 1 GiB)");
  if (h.start_time > h.end_time) fail_at(record_at, "a chunk whose time range ends before it starts");
  if (indexed_block != nullptr) {
    const ChunkHeader& x = indexed_block->index;
    if (h.compression != x.compression || h.uncompressed_size != x.uncompressed_size ||
        h.records_size != x.records_size || h.start_time != x.start_time || h.end_time != x.end_time)
      fail_at(record_at, "the chunk does not match its chunk index in the summary");
  }
  if (*compression != Compression::kNone && h.records_size > max_compressed_size(h.uncompressed_size))
    fail_at(record_at, "a chunk of " + bytes_text(h.records_size) + " compressed, far more than its " +
                           bytes_text(h.uncompressed_size) + " uncompressed");

  std::string buffer;
  if (*compression == Compression::kNone) {
    if (h.records_size != h.uncompressed_size)
      fail_at(record_at, "an uncompressed chunk of " + bytes_text(h.records_size) + " that declares " +
                             bytes_text(h.uncompressed_size));
    records_offset = static_cast<std::size_t>(records.data() - content.data());
    buffer = std::move(content);  // the records stay where they were read
  } else {
    try {
      Decompressor::check_declared_size(*compression, records, static_cast<std::size_t>(h.uncompressed_size));
    } catch (const InputError& e) {
      fail_at(record_at, std::string("chunk: ") + e.what());
    }
    buffer.resize(static_cast<std::size_t>(h.uncompressed_size));
    try {
      decompressor.decompress(*compression, records, buffer.data(), buffer.size());
    } catch (const InputError& e) {
      fail_at(record_at, std::string("chunk: ") + e.what());
    }
    records_offset = 0;
    content = std::string();
  }
  const std::string_view view = std::string_view(buffer).substr(records_offset, static_cast<std::size_t>(h.uncompressed_size));
  if (h.uncompressed_crc != 0 && mcap::crc32_update(0, view) != h.uncompressed_crc)
    fail_at(record_at, "the chunk fails its CRC (a damaged file)");
  std::size_t pos = 0;
  try {
    while (pos < view.size()) {
      mcap::Cursor prefix(view.substr(pos), "chunk's");
      const std::uint8_t op = prefix.u8();
      const std::uint64_t size = prefix.u64();
      const std::string_view inner = prefix.bytes(size, "a record");
      on_record(op, inner, pos);
      pos += mcap::kRecordPrefixSize + inner.size();
    }
  } catch (const mcap::FormatError& e) {
    fail_at(record_at, std::string("inside the chunk, at its byte ") + std::to_string(pos) + ": " + e.what());
  }
  return buffer;
}

void McapReader::Impl::scan() {
  Window window(file, data_end);
  std::uint64_t counted = 0;
  channel_counts.clear();
  Block block;
  std::uint64_t block_bytes = 0;
  bool block_has_messages = false;
  std::set<std::uint16_t> block_channels;
  const auto note_message = [&](std::uint16_t channel, std::uint64_t time) {
    block.start_time = block_has_messages ? std::min(block.start_time, time) : time;
    block.end_time = block_has_messages ? std::max(block.end_time, time) : time;
    block_has_messages = true;
    block_channels.insert(channel);
    ++channel_counts[channel];
    ++counted;
  };
  const auto close_block = [&](std::uint64_t end) {
    if (block_has_messages) {
      block.end = end;
      block.channels.assign(block_channels.begin(), block_channels.end());
      blocks.push_back(block);
    }
    block = Block();
    block_bytes = 0;
    block_has_messages = false;
    block_channels.clear();
  };

  std::uint64_t pos = data_start;
  while (pos < data_end) {
    if (data_end - pos < mcap::kRecordPrefixSize)
      fail_at(pos, "a record runs past the end of the data section");
    mcap::Cursor prefix(window.get(pos, mcap::kRecordPrefixSize), "record");
    const std::uint8_t op = prefix.u8();
    const std::uint64_t size = prefix.u64();
    if (size > data_end - pos - mcap::kRecordPrefixSize)
      fail_at(pos, "a " + mcap::opcode_name(op) + " record of " + bytes_text(size) +
                       " runs past the end of the data section (a cut or damaged file)");
    const std::uint64_t content_at = pos + mcap::kRecordPrefixSize;
    const std::uint64_t next = content_at + size;
    if (!block_has_messages) block.begin = pos;
    try {
      switch (op) {
        case mcap::kSchema:
        case mcap::kChannel: {
          if (size > kMaxSchemaOrChannelBytes)
            fail_at(pos, "a " + mcap::opcode_name(op) + " record of " + bytes_text(size));
          const std::string content = file.read(content_at, static_cast<std::size_t>(size));
          if (op == mcap::kSchema)
            add_schema(parse_schema(content), pos);
          else
            add_channel(parse_channel(content), pos);
          break;
        }
        case mcap::kMessage: {
          if (size < mcap::kMessageFixedSize) fail_at(pos, "a Message record shorter than its fields");
          mcap::Cursor c(window.get(content_at, mcap::kMessageFixedSize), "Message");
          const std::uint16_t channel = c.u16();
          c.u32();
          note_message(channel, c.u64());
          block_bytes += mcap::kRecordPrefixSize + size;
          break;
        }
        case mcap::kChunk: {
          ChunkHeader h;
          std::size_t records_offset = 0;
          read_chunk(pos, size, nullptr, h, records_offset, [&](std::uint8_t inner_op, std::string_view inner, std::size_t) {
            if (inner_op == mcap::kSchema) {
              add_schema(parse_schema(inner), pos);
            } else if (inner_op == mcap::kChannel) {
              add_channel(parse_channel(inner), pos);
            } else if (inner_op == mcap::kMessage) {
              mcap::Cursor c(inner, "Message");
              const std::uint16_t channel = c.u16();
              c.u32();
              const std::uint64_t time = c.u64();
              if (time < h.start_time || time > h.end_time)
                fail_at(pos, "a message at " + std::to_string(time) + " ns outside its chunk's time range");
              note_message(channel, time);
            }
          });
          block_bytes += h.uncompressed_size;
          break;
        }
        case mcap::kHeader:
        case mcap::kFooter:
        case mcap::kDataEnd:
          fail_at(pos, "a " + mcap::opcode_name(op) + " record inside the data section");
        default:
          break;  // message indexes, attachments, metadata, records of later versions
      }
    } catch (const mcap::FormatError& e) {
      fail_at(pos, e.what());
    }
    pos = next;
    if (block_bytes >= kScanBlockBytes) close_block(pos);
  }
  close_block(pos);
  message_count = counted;
  for (const auto& [id, ch] : channels) channel_counts.emplace(id, 0);
  counts_known = true;
}

std::unique_ptr<OpenBlock> McapReader::Impl::open_block(const Block& b, const std::set<std::uint16_t>* wanted) const {
  auto open = std::make_unique<OpenBlock>();
  open->begin = b.begin;
  std::string loose;  // loose messages' records, in one buffer
  std::vector<std::size_t> loose_entries;
  const auto check_channel = [&](std::uint16_t channel, std::uint64_t at) {
    if (channels.count(channel) == 0)
      fail_at(at, "a message on channel " + std::to_string(channel) + ", which the file never defines");
    return wanted == nullptr || wanted->count(channel) > 0;
  };
  Window window(file, b.end);
  std::uint64_t pos = b.begin;
  while (pos < b.end) {
    if (b.end - pos < mcap::kRecordPrefixSize) fail_at(pos, "a record runs past the end of its section");
    mcap::Cursor prefix(window.get(pos, mcap::kRecordPrefixSize), "record");
    const std::uint8_t op = prefix.u8();
    const std::uint64_t size = prefix.u64();
    if (size > b.end - pos - mcap::kRecordPrefixSize)
      fail_at(pos, "a " + mcap::opcode_name(op) + " record of " + bytes_text(size) + " runs past the end of its section");
    if (b.from_index && (op != mcap::kChunk || mcap::kRecordPrefixSize + size != b.chunk_length))
      fail_at(pos, "the summary's chunk index points at a " + mcap::opcode_name(op) + " record, not its chunk");
    if (op == mcap::kChunk) {
      ChunkHeader h;
      std::size_t records_offset = 0;
      const auto buffer_index = static_cast<std::uint32_t>(open->buffers.size());
      const std::size_t first = open->entries.size();
      std::string buffer = read_chunk(
          pos, size, b.from_index ? &b : nullptr, h, records_offset,
          [&](std::uint8_t inner_op, std::string_view inner, std::size_t offset) {
            if (inner_op != mcap::kMessage) return;
            mcap::Cursor c(inner, "Message");
            Entry e;
            e.channel = c.u16();
            e.sequence = c.u32();
            e.log_time = c.u64();
            e.publish_time = c.u64();
            if (e.log_time < h.start_time || e.log_time > h.end_time)
              fail_at(pos, "a message at " + std::to_string(e.log_time) + " ns outside its chunk's time range");
            if (!check_channel(e.channel, pos)) return;
            e.buffer = buffer_index;
            e.offset = records_offset + offset + mcap::kRecordPrefixSize + mcap::kMessageFixedSize;
            e.size = inner.size() - mcap::kMessageFixedSize;  // the cursor read the fixed fields
            open->entries.push_back(e);
          });
      if (open->entries.size() > first) {
        open->bytes += buffer.size();
        open->buffers.push_back(std::move(buffer));
      }
    } else if (op == mcap::kMessage) {
      if (size < mcap::kMessageFixedSize) fail_at(pos, "a Message record shorter than its fields");
      mcap::Cursor c(window.get(pos + mcap::kRecordPrefixSize, mcap::kMessageFixedSize), "Message");
      Entry e;
      e.channel = c.u16();
      e.sequence = c.u32();
      e.log_time = c.u64();
      e.publish_time = c.u64();
      if (check_channel(e.channel, pos)) {
        if (size > kMaxChunkUncompressedBytes) fail_at(pos, "a message of " + bytes_text(size));
        e.size = static_cast<std::size_t>(size - mcap::kMessageFixedSize);
        e.offset = loose.size();
        loose.resize(loose.size() + e.size);
        file.read(pos + mcap::kRecordPrefixSize + mcap::kMessageFixedSize, e.size, loose.data() + e.offset);
        loose_entries.push_back(open->entries.size());
        open->entries.push_back(e);
      }
    }
    pos += mcap::kRecordPrefixSize + size;
    if (open->bytes + loose.size() + open->entries.size() * sizeof(Entry) > kMaxOpenBytes)
      fail("messages overlapping in log time take more than 2 GiB; read the file in file order");
  }
  if (!loose_entries.empty()) {
    const auto index = static_cast<std::uint32_t>(open->buffers.size());
    for (const std::size_t i : loose_entries) open->entries[i].buffer = index;
    open->bytes += loose.size();
    open->buffers.push_back(std::move(loose));
  }
  open->bytes += open->entries.size() * sizeof(Entry);
  return open;
}

McapReader::McapReader(std::string path) : impl_(std::make_unique<Impl>(std::move(path))) { impl_->open(); }
McapReader::~McapReader() = default;

const std::string& McapReader::path() const { return impl_->path; }
const std::string& McapReader::profile() const { return impl_->profile; }
const std::string& McapReader::library() const { return impl_->library; }
bool McapReader::indexed() const { return impl_->indexed; }
const std::map<std::uint16_t, McapSchema>& McapReader::schemas() const { return impl_->schemas; }
const std::map<std::uint16_t, McapChannel>& McapReader::channels() const { return impl_->channels; }
std::optional<std::uint64_t> McapReader::message_count() const { return impl_->message_count; }

std::vector<McapTopic> McapReader::topics() const {
  std::vector<McapTopic> out;
  for (const auto& [id, ch] : impl_->channels) {
    McapTopic t;
    t.topic = ch.topic;
    t.channel_id = id;
    t.message_encoding = ch.message_encoding;
    const auto schema = impl_->schemas.find(ch.schema_id);
    if (schema != impl_->schemas.end()) t.type = schema->second.name;
    if (impl_->counts_known) {
      const auto count = impl_->channel_counts.find(id);
      t.message_count = count == impl_->channel_counts.end() ? 0 : count->second;
    }
    out.push_back(std::move(t));
  }
  std::sort(out.begin(), out.end(), [](const McapTopic& a, const McapTopic& b) {
    return std::tie(a.topic, a.channel_id) < std::tie(b.topic, b.channel_id);
  });
  return out;
}

void McapReader::for_each_message(const McapMessageCallback& callback, const McapReadOptions& options) const {
  const Impl& d = *impl_;
  std::set<std::uint16_t> wanted;
  for (const std::string& topic : options.topics) {
    bool found = false;
    for (const auto& [id, ch] : d.channels)
      if (ch.topic == topic) {
        wanted.insert(id);
        found = true;
      }
    if (!found) {
      std::string known;
      for (const McapTopic& t : topics()) known += (known.empty() ? "" : ", ") + t.topic;
      d.fail("no topic " + topic + " in the recording (its topics: " + (known.empty() ? "none" : known) + ")");
    }
  }
  const std::set<std::uint16_t>* filter = options.topics.empty() ? nullptr : &wanted;
  std::vector<const Block*> order;
  for (const Block& b : d.blocks) {
    const bool skip = filter != nullptr && !b.channels.empty() &&
                      std::none_of(b.channels.begin(), b.channels.end(),
                                   [&](std::uint16_t c) { return wanted.count(c) > 0; });
    if (!skip) order.push_back(&b);
  }

  std::uint64_t delivered = 0;
  const auto deliver = [&](const OpenBlock& open, const Entry& e) {
    McapMessage m;
    m.channel = &d.channels.at(e.channel);
    const auto schema = d.schemas.find(m.channel->schema_id);
    m.schema = schema == d.schemas.end() ? nullptr : &schema->second;
    m.sequence = e.sequence;
    m.log_time_ns = e.log_time;
    m.publish_time_ns = e.publish_time;
    m.data = std::string_view(open.buffers[e.buffer]).substr(e.offset, e.size);
    ++delivered;
    return callback(m);
  };

  if (options.order == McapOrder::kFile) {
    for (const Block* b : order) {
      const auto open = d.open_block(*b, filter);
      for (const Entry& e : open->entries)
        if (!deliver(*open, e)) return;
    }
  } else {
    std::sort(order.begin(), order.end(), [](const Block* a, const Block* b) {
      return std::tie(a->start_time, a->begin) < std::tie(b->start_time, b->begin);
    });
    // A min-heap of the open blocks' next messages: (log time, block's place in the file, index).
    using Key = std::tuple<std::uint64_t, std::uint64_t, std::size_t, OpenBlock*>;
    std::priority_queue<Key, std::vector<Key>, std::greater<Key>> heap;
    std::map<OpenBlock*, std::unique_ptr<OpenBlock>> open_blocks;
    std::uint64_t open_bytes = 0;
    std::size_t next_block = 0;
    while (true) {
      // Open every block that may hold a message at or before the earliest one open.
      while (next_block < order.size() && (heap.empty() || order[next_block]->start_time <= std::get<0>(heap.top()))) {
        auto open = d.open_block(*order[next_block++], filter);
        if (open->entries.empty()) continue;
        std::stable_sort(open->entries.begin(), open->entries.end(),
                         [](const Entry& a, const Entry& b) { return a.log_time < b.log_time; });
        open_bytes += open->bytes;
        if (open_bytes > kMaxOpenBytes)
          d.fail("chunks overlapping in log time hold more than 2 GiB of messages; canopy reads this file only in "
                 "file order");
        OpenBlock* raw = open.get();
        heap.emplace(raw->entries[0].log_time, raw->begin, 0, raw);
        open_blocks.emplace(raw, std::move(open));
      }
      if (heap.empty()) break;
      const auto [time, begin, index, block] = heap.top();
      heap.pop();
      if (!deliver(*block, block->entries[index])) return;
      if (index + 1 < block->entries.size()) {
        heap.emplace(block->entries[index + 1].log_time, begin, index + 1, block);
      } else {
        open_bytes -= block->bytes;
        open_blocks.erase(block);
      }
    }
  }
  if (filter == nullptr && d.message_count && delivered != *d.message_count)
    d.fail("its statistics count " + std::to_string(*d.message_count) + " messages, but its chunks hold " +
           std::to_string(delivered) + " (a damaged summary, or messages outside the indexed chunks)");
}

void McapReader::verify() const {
  const Impl& d = *impl_;
  if (d.data_crc == 0) return;  // the writer did not compute it
  std::uint32_t crc = 0;
  std::string buf;
  for (std::uint64_t pos = 0; pos < d.data_end;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(d.data_end - pos, 4u << 20));
    buf.resize(n);
    d.file.read(pos, n, buf.data());
    crc = mcap::crc32_update(crc, buf);
    pos += n;
  }
  if (crc != d.data_crc) d.fail("corrupt MCAP: the data section fails its CRC (a damaged file)");
}

void McapReader::check_type(const McapMessage& message, const char* type_name) const {
  const std::string type = message.schema != nullptr ? message.schema->name : "";
  if (type != type_name)
    throw InputError(message_context(message) + ": a message of type '" + type + "', not " + type_name);
  if (message.channel->message_encoding != kCdrMessageEncoding)
    throw InputError(message_context(message) + ": messages encoded as '" + message.channel->message_encoding +
                     "', not cdr");
}

std::string McapReader::message_context(const McapMessage& message) const {
  return impl_->path + ": " + message.channel->topic + " at " + std::to_string(message.log_time_ns) + " ns";
}

bool is_canopy_mcap(const std::string& path) {
  try {
    const File file(path);
    if (file.size() < kMinFileBytes) return false;
    const std::string head = file.read(0, mcap::kMagicSize + mcap::kRecordPrefixSize);
    mcap::Cursor c(head, "Header");
    if (std::memcmp(c.bytes(mcap::kMagicSize).data(), mcap::kMagic, mcap::kMagicSize) != 0) return false;
    if (c.u8() != mcap::kHeader) return false;
    const std::uint64_t length = c.u64();
    if (length > kMaxHeaderBytes || length > file.size() - mcap::kMagicSize - mcap::kRecordPrefixSize) return false;
    const std::string header = file.read(mcap::kMagicSize + mcap::kRecordPrefixSize, static_cast<std::size_t>(length));
    mcap::Cursor h(header, "Header");
    h.string();  // profile
    const std::string library = h.string();
    return library.rfind("canopy", 0) == 0;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace canopy::ros2
