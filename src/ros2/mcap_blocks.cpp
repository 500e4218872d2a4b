#include "mcap_reader_impl.h"

#include <algorithm>
#include <set>
#include <string>
#include <string_view>

#include "canopy/ros2/compression.h"
#include "mcap_input.h"
#include "mcap_records.h"

namespace canopy::ros2 {

using namespace reader_detail;

template <class OnRecord>
std::string McapReader::Impl::read_chunk(std::uint64_t record_at, std::uint64_t content_size, const Block* indexed_block,
                                         mcap::ChunkHeader& h, std::size_t& records_offset,
                                         OnRecord&& on_record) const {
  if (content_size > max_compressed_size(kMaxChunkUncompressedBytes) + 4096)
    fail_at(record_at, "a Chunk record of " + bytes_text(content_size) + " (canopy reads chunks of at most 1 GiB)");
  std::string content = file.read(record_at + mcap::kRecordPrefixSize, static_cast<std::size_t>(content_size));
  std::string_view records;
  try {
    mcap::Cursor c(content, "Chunk");
    h = mcap::parse_chunk_header(c);
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
    const mcap::ChunkHeader& x = indexed_block->index;
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
            add_schema(mcap::parse_schema(content), pos);
          else
            add_channel(mcap::parse_channel(content), pos);
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
          mcap::ChunkHeader h;
          std::size_t records_offset = 0;
          read_chunk(pos, size, nullptr, h, records_offset, [&](std::uint8_t inner_op, std::string_view inner, std::size_t) {
            if (inner_op == mcap::kSchema) {
              add_schema(mcap::parse_schema(inner), pos);
            } else if (inner_op == mcap::kChannel) {
              add_channel(mcap::parse_channel(inner), pos);
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
      mcap::ChunkHeader h;
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

}  // namespace canopy::ros2
