#include "canopy/ros2/mcap_reader.h"

#include <algorithm>
#include <cstring>
#include <queue>
#include <set>
#include <tuple>

#include "canopy/ros2/compression.h"
#include "canopy/ros2/message_schemas.h"
#include "mcap_input.h"
#include "mcap_reader_impl.h"
#include "mcap_records.h"

namespace canopy::ros2 {

using namespace reader_detail;

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
          add_schema(mcap::parse_schema(content), at);
          break;
        case mcap::kChannel:
          add_channel(mcap::parse_channel(content), at);
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
