#include "canopy/ros2/mcap_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>

#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/ros2/mcap_reader.h"
#include "canopy/ros2/message_schemas.h"
#include "mcap_records.h"

#ifndef CANOPY_VERSION
#error "CANOPY_VERSION is set by src/ros2/CMakeLists.txt"
#endif

namespace canopy::ros2 {

// Named (not anonymous): the Impl's members are of these types.
namespace writer_detail {

constexpr std::size_t kOutputBufferBytes = std::size_t(1) << 20;

struct SchemaEntry {
  std::uint16_t id;
  std::string name, encoding, data;
};

struct ChannelEntry {
  std::uint16_t id;
  std::uint16_t schema_id;
  std::string topic, message_encoding;
  std::vector<std::pair<std::string, std::string>> metadata;
  std::string type_name;  // the schema's name ("" without a schema)
  std::uint32_t next_sequence = 0;
  std::uint64_t messages = 0;
};

struct ChunkIndexEntry {
  std::uint64_t start_time, end_time, chunk_start, chunk_length;
  std::vector<std::pair<std::uint16_t, std::uint64_t>> message_index_offsets;
  std::uint64_t message_index_length, compressed_size, uncompressed_size;
};

void put_map_string(std::string& out, const std::vector<std::pair<std::string, std::string>>& m) {
  std::string body;
  for (const auto& [k, v] : m) {
    mcap::put_string(body, k);
    mcap::put_string(body, v);
  }
  mcap::put<std::uint32_t>(out, static_cast<std::uint32_t>(body.size()));
  out += body;
}

std::string schema_record(const SchemaEntry& s) {
  std::string r;
  const auto at = mcap::begin_record(r, mcap::kSchema);
  mcap::put<std::uint16_t>(r, s.id);
  mcap::put_string(r, s.name);
  mcap::put_string(r, s.encoding);
  mcap::put_string(r, s.data);  // uint32-length-prefixed bytes: the same layout as a string
  mcap::end_record(r, at);
  return r;
}

std::string channel_record(const ChannelEntry& c) {
  std::string r;
  const auto at = mcap::begin_record(r, mcap::kChannel);
  mcap::put<std::uint16_t>(r, c.id);
  mcap::put<std::uint16_t>(r, c.schema_id);
  mcap::put_string(r, c.topic);
  mcap::put_string(r, c.message_encoding);
  put_map_string(r, c.metadata);
  mcap::end_record(r, at);
  return r;
}

// Refuses to let `path` be replaced unless it is absent or an MCAP canopy wrote.
void check_replaceable(const std::string& path) {
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return;
    throw IoError("cannot write " + path + ": " + std::strerror(errno));
  }
  if (S_ISLNK(st.st_mode))
    throw InputError(path + " is a symbolic link; canopy writes a recording only to a new name or over its own");
  if (S_ISDIR(st.st_mode)) throw InputError(path + " is a folder; give the recording a file name");
  if (!S_ISREG(st.st_mode)) throw InputError(path + " exists and is not a regular file; canopy never replaces it");
  if (!is_canopy_mcap(path))
    throw InputError(path + " exists and is not an MCAP canopy wrote; canopy never replaces it (remove it or "
                     "choose another name)");
}

}  // namespace writer_detail
using namespace writer_detail;

std::string mcap_library_name() { return std::string("canopy ") + CANOPY_VERSION; }

struct McapWriter::State {
  McapWriterOptions options;
  std::string partial;  // <path>.partial, renamed to <path> by close()
  LockFile lock;        // <path>.lock: one canopy writer per path
  int fd = -1;
  bool closed = false;
  bool failed = false;

  // The file so far: bytes not yet handed to write(2), the position, and the CRCs.
  std::string out;
  std::uint64_t position = 0;
  bool in_summary = false;
  std::uint32_t data_crc = 0;
  std::uint32_t summary_crc = 0;

  std::vector<SchemaEntry> schemas;
  std::vector<ChannelEntry> channels;  // channel id - 1

  // The open chunk.
  Compressor compressor;
  std::string chunk;  // uncompressed records
  std::string compressed;
  std::uint64_t chunk_start_time = 0, chunk_end_time = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index;  // log time, offset
  std::vector<ChunkIndexEntry> chunk_indexes;

  std::uint64_t start_time = 0, end_time = 0;

  explicit State(const McapWriterOptions& o) : options(o), compressor(o.compression, o.compression_level) {}
  // Not closed (an error, an exception, no close() call): the partial file goes, nothing is left.
  ~State() {
    if (fd >= 0) ::close(fd);
    if (!closed && !partial.empty()) ::unlink(partial.c_str());
  }

  void write_fd(const char* p, std::size_t n, const std::string& path) {
    while (n > 0) {
      const ssize_t w = ::write(fd, p, n);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        failed = true;
        const int err = w < 0 ? errno : ENOSPC;
        throw IoError("cannot write " + path + ": " + std::strerror(err) + "; no recording written");
      }
      p += w;
      n -= static_cast<std::size_t>(w);
    }
  }
  void flush(const std::string& path) {
    write_fd(out.data(), out.size(), path);
    out.clear();
  }
  // Appends bytes to the file, in order, counting them into the section's CRC.
  void emit(std::string_view bytes, const std::string& path) {
    if (in_summary)
      summary_crc = mcap::crc32_update(summary_crc, bytes);
    else
      data_crc = mcap::crc32_update(data_crc, bytes);
    position += bytes.size();
    if (out.size() + bytes.size() <= kOutputBufferBytes) {
      out.append(bytes);
      return;
    }
    flush(path);
    if (bytes.size() < kOutputBufferBytes)
      out.append(bytes);
    else
      write_fd(bytes.data(), bytes.size(), path);
  }

  void flush_chunk(const std::string& path, McapWriteStats& stats) {
    if (chunk.empty()) return;
    const std::uint32_t crc = mcap::crc32_update(0, chunk);
    compressor.compress(chunk, compressed);
    const std::string_view compression = compression_name(options.compression);

    ChunkIndexEntry index;
    index.start_time = chunk_start_time;
    index.end_time = chunk_end_time;
    index.chunk_start = position;
    index.compressed_size = compressed.size();
    index.uncompressed_size = chunk.size();

    std::string head;
    mcap::put<std::uint8_t>(head, mcap::kChunk);
    mcap::put<std::uint64_t>(head, 8 + 8 + 8 + 4 + 4 + compression.size() + 8 + compressed.size());
    mcap::put<std::uint64_t>(head, chunk_start_time);
    mcap::put<std::uint64_t>(head, chunk_end_time);
    mcap::put<std::uint64_t>(head, chunk.size());
    mcap::put<std::uint32_t>(head, crc);
    mcap::put_string(head, compression);
    mcap::put<std::uint64_t>(head, compressed.size());
    emit(head, path);
    emit(compressed, path);
    index.chunk_length = position - index.chunk_start;

    // One Message Index record per channel in the chunk, entries in log-time order.
    const std::uint64_t indexes_start = position;
    for (auto& [channel, entries] : chunk_index) {
      std::stable_sort(entries.begin(), entries.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      std::string r;
      const auto at = mcap::begin_record(r, mcap::kMessageIndex);
      mcap::put<std::uint16_t>(r, channel);
      mcap::put<std::uint32_t>(r, static_cast<std::uint32_t>(entries.size() * 16));
      for (const auto& [time, offset] : entries) {
        mcap::put<std::uint64_t>(r, time);
        mcap::put<std::uint64_t>(r, offset);
      }
      mcap::end_record(r, at);
      index.message_index_offsets.emplace_back(channel, position);
      emit(r, path);
    }
    index.message_index_length = position - indexes_start;
    chunk_indexes.push_back(std::move(index));
    ++stats.chunks;

    chunk.clear();
    chunk_index.clear();
  }
};

McapWriter::McapWriter(std::string path, McapWriterOptions options) : path_(std::move(path)) {
  if (options.chunk_size_bytes == 0) options.chunk_size_bytes = 1;
  check_replaceable(path_);
  state_ = std::make_unique<State>(options);
  State& s = *state_;
  if (!s.lock.try_lock(path_ + ".lock", path_))
    throw InputError(path_ + ": another canopy process is writing this recording");
  const std::string partial = path_ + ".partial";
  // O_NOFOLLOW: a link planted at the partial name is refused, never followed; a partial file
  // a killed writer left is canopy's own (the lock is ours) and is overwritten.
  s.fd = ::open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0666);
  if (s.fd < 0) {
    if (errno == ELOOP) throw InputError(partial + " is a symbolic link; remove it");
    throw IoError("cannot write " + path_ + ": cannot create " + partial + ": " + std::strerror(errno));
  }
  struct stat st;
  if (::fstat(s.fd, &st) != 0 || !S_ISREG(st.st_mode)) throw InputError(partial + " is not a plain file; remove it");
  s.partial = partial;
  std::string head(mcap::kMagic, mcap::kMagicSize);
  const auto at = mcap::begin_record(head, mcap::kHeader);
  mcap::put_string(head, "ros2");
  mcap::put_string(head, mcap_library_name());
  mcap::end_record(head, at);
  s.emit(head, path_);
}

McapWriter::~McapWriter() = default;

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, std::string_view data) {
  State& s = *state_;
  CANOPY_CHECK(!s.closed, "McapWriter::add_schema after close()");
  for (const SchemaEntry& e : s.schemas)
    if (e.name == name && e.encoding == encoding && e.data == data) return e.id;
  CANOPY_CHECK(s.schemas.size() < 65535, "an MCAP file holds at most 65535 schemas");
  SchemaEntry e{static_cast<std::uint16_t>(s.schemas.size() + 1), name, encoding, std::string(data)};
  // Written into the data section at once: it precedes every chunk that uses it.
  s.emit(schema_record(e), path_);
  s.schemas.push_back(std::move(e));
  return s.schemas.back().id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, const std::string& topic,
                                      const std::string& message_encoding,
                                      const std::vector<std::pair<std::string, std::string>>& metadata) {
  State& s = *state_;
  CANOPY_CHECK(!s.closed, "McapWriter::add_channel after close()");
  CANOPY_CHECK(schema_id <= s.schemas.size(), "McapWriter::add_channel: no schema " << schema_id);
  CANOPY_CHECK(s.channels.size() < 65535, "an MCAP file holds at most 65535 channels");
  ChannelEntry c;
  c.id = static_cast<std::uint16_t>(s.channels.size() + 1);
  c.schema_id = schema_id;
  c.topic = topic;
  c.message_encoding = message_encoding;
  c.metadata = metadata;
  c.type_name = schema_id == 0 ? "" : s.schemas[schema_id - 1].name;
  s.emit(channel_record(c), path_);
  s.channels.push_back(std::move(c));
  return s.channels.back().id;
}

std::uint16_t McapWriter::add_ros2_channel(const std::string& topic, const std::string& type_name) {
  const std::uint16_t schema = add_schema(type_name, kRos2MsgSchemaEncoding, ros2msg_schema(type_name));
  return add_channel(schema, topic, kCdrMessageEncoding);
}

void McapWriter::check_channel_type(std::uint16_t channel_id, const char* type_name) const {
  const State& s = *state_;
  CANOPY_CHECK(channel_id >= 1 && channel_id <= s.channels.size(), "McapWriter: no channel " << channel_id);
  CANOPY_CHECK(s.channels[channel_id - 1].type_name == type_name,
               "McapWriter: a " << type_name << " written on channel " << s.channels[channel_id - 1].topic
                                << " of type " << s.channels[channel_id - 1].type_name);
}

void McapWriter::write(std::uint16_t channel_id, std::uint64_t log_time_ns, std::uint64_t publish_time_ns,
                       std::string_view data) {
  State& s = *state_;
  CANOPY_CHECK(!s.closed, "McapWriter::write after close()");
  CANOPY_CHECK(!s.failed, "McapWriter::write after a failed write");
  CANOPY_CHECK(channel_id >= 1 && channel_id <= s.channels.size(), "McapWriter::write: no channel " << channel_id);
  ChannelEntry& c = s.channels[channel_id - 1];
  if (mcap::kRecordPrefixSize + mcap::kMessageFixedSize + data.size() > kMaxChunkUncompressedBytes)
    throw InputError("a message of " + std::to_string(data.size()) + " bytes on " + c.topic +
                     " is larger than an MCAP chunk canopy reads (1 GiB)");
  // A message that would take the chunk past canopy's reading limit starts a new one.
  if (s.chunk.size() + mcap::kRecordPrefixSize + mcap::kMessageFixedSize + data.size() > kMaxChunkUncompressedBytes)
    s.flush_chunk(path_, stats_);

  const std::uint64_t offset = s.chunk.size();
  mcap::put<std::uint8_t>(s.chunk, mcap::kMessage);
  mcap::put<std::uint64_t>(s.chunk, mcap::kMessageFixedSize + data.size());
  mcap::put<std::uint16_t>(s.chunk, channel_id);
  mcap::put<std::uint32_t>(s.chunk, c.next_sequence++);
  mcap::put<std::uint64_t>(s.chunk, log_time_ns);
  mcap::put<std::uint64_t>(s.chunk, publish_time_ns);
  s.chunk.append(data);
  s.chunk_index[channel_id].emplace_back(log_time_ns, offset);

  const bool first_in_chunk = offset == 0;
  s.chunk_start_time = first_in_chunk ? log_time_ns : std::min(s.chunk_start_time, log_time_ns);
  s.chunk_end_time = first_in_chunk ? log_time_ns : std::max(s.chunk_end_time, log_time_ns);
  s.start_time = stats_.messages == 0 ? log_time_ns : std::min(s.start_time, log_time_ns);
  s.end_time = stats_.messages == 0 ? log_time_ns : std::max(s.end_time, log_time_ns);
  ++c.messages;
  ++stats_.messages;
  stats_.message_bytes += data.size();

  if (s.chunk.size() >= s.options.chunk_size_bytes) s.flush_chunk(path_, stats_);
  stats_.file_bytes = s.position;
}

void McapWriter::close() {
  State& s = *state_;
  CANOPY_CHECK(!s.closed, "McapWriter::close twice");
  CANOPY_CHECK(!s.failed, "McapWriter::close after a failed write");
  s.flush_chunk(path_, stats_);

  // Data End carries the CRC of everything before it, from the leading magic on.
  std::string data_end;
  mcap::put<std::uint8_t>(data_end, mcap::kDataEnd);
  mcap::put<std::uint64_t>(data_end, 4);
  mcap::put<std::uint32_t>(data_end, s.data_crc);
  s.emit(data_end, path_);

  std::uint64_t summary_start = 0, summary_offset_start = 0;
  if (s.options.write_summary) {
    s.in_summary = true;
    summary_start = s.position;
    std::vector<std::tuple<std::uint8_t, std::uint64_t, std::uint64_t>> groups;  // opcode, start, length
    const auto group = [&](std::uint8_t op, const std::string& records) {
      if (records.empty()) return;
      groups.emplace_back(op, s.position, records.size());
      s.emit(records, path_);
    };
    std::string records;
    for (const SchemaEntry& e : s.schemas) records += schema_record(e);
    group(mcap::kSchema, records);
    records.clear();
    for (const ChannelEntry& c : s.channels) records += channel_record(c);
    group(mcap::kChannel, records);

    records.clear();
    const auto at = mcap::begin_record(records, mcap::kStatistics);
    mcap::put<std::uint64_t>(records, stats_.messages);
    mcap::put<std::uint16_t>(records, static_cast<std::uint16_t>(s.schemas.size()));
    mcap::put<std::uint32_t>(records, static_cast<std::uint32_t>(s.channels.size()));
    mcap::put<std::uint32_t>(records, 0);  // attachments
    mcap::put<std::uint32_t>(records, 0);  // metadata
    mcap::put<std::uint32_t>(records, static_cast<std::uint32_t>(s.chunk_indexes.size()));
    mcap::put<std::uint64_t>(records, s.start_time);
    mcap::put<std::uint64_t>(records, s.end_time);
    mcap::put<std::uint32_t>(records, static_cast<std::uint32_t>(s.channels.size() * 10));
    for (const ChannelEntry& c : s.channels) {
      mcap::put<std::uint16_t>(records, c.id);
      mcap::put<std::uint64_t>(records, c.messages);
    }
    mcap::end_record(records, at);
    group(mcap::kStatistics, records);

    records.clear();
    for (const ChunkIndexEntry& e : s.chunk_indexes) {
      const auto r = mcap::begin_record(records, mcap::kChunkIndex);
      mcap::put<std::uint64_t>(records, e.start_time);
      mcap::put<std::uint64_t>(records, e.end_time);
      mcap::put<std::uint64_t>(records, e.chunk_start);
      mcap::put<std::uint64_t>(records, e.chunk_length);
      mcap::put<std::uint32_t>(records, static_cast<std::uint32_t>(e.message_index_offsets.size() * 10));
      for (const auto& [channel, offset] : e.message_index_offsets) {
        mcap::put<std::uint16_t>(records, channel);
        mcap::put<std::uint64_t>(records, offset);
      }
      mcap::put<std::uint64_t>(records, e.message_index_length);
      mcap::put_string(records, compression_name(s.options.compression));
      mcap::put<std::uint64_t>(records, e.compressed_size);
      mcap::put<std::uint64_t>(records, e.uncompressed_size);
      mcap::end_record(records, r);
    }
    group(mcap::kChunkIndex, records);

    summary_offset_start = s.position;
    records.clear();
    for (const auto& [op, start, length] : groups) {
      const auto r = mcap::begin_record(records, mcap::kSummaryOffset);
      mcap::put<std::uint8_t>(records, op);
      mcap::put<std::uint64_t>(records, start);
      mcap::put<std::uint64_t>(records, length);
      mcap::end_record(records, r);
    }
    s.emit(records, path_);
  }

  // The summary CRC runs from the summary's start through the footer's offsets.
  std::string footer;
  mcap::put<std::uint8_t>(footer, mcap::kFooter);
  mcap::put<std::uint64_t>(footer, mcap::kFooterContentSize);
  mcap::put<std::uint64_t>(footer, summary_start);
  mcap::put<std::uint64_t>(footer, summary_offset_start);
  s.in_summary = true;
  s.emit(footer, path_);
  std::string tail;
  mcap::put<std::uint32_t>(tail, s.options.write_summary ? s.summary_crc : 0);
  tail.append(mcap::kMagic, mcap::kMagicSize);
  s.emit(tail, path_);
  s.flush(path_);
  stats_.file_bytes = s.position;

  const int fd = s.fd;
  s.fd = -1;
  if (::close(fd) != 0 && errno != EINTR) {
    s.failed = true;
    throw IoError("cannot write " + path_ + ": " + std::strerror(errno) + "; no recording written");
  }
  check_replaceable(path_);  // a file that appeared meanwhile is refused like one that was there
  move_temp_into_place(s.partial, path_);
  s.closed = true;
  s.lock.release();
}

}  // namespace canopy::ros2
