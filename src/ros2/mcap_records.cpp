#include "mcap_records.h"

#include <zlib.h>

#include <cstdio>
#include <utility>

#include "canopy/ros2/mcap_reader.h"

namespace canopy::ros2::mcap {

std::string opcode_name(std::uint8_t op) {
  static const char* names[] = {"",           "Header",           "Footer",          "Schema",
                                "Channel",    "Message",          "Chunk",           "Message Index",
                                "Chunk Index", "Attachment",      "Attachment Index", "Statistics",
                                "Metadata",   "Metadata Index",   "Summary Offset",  "Data End"};
  if (op >= 1 && op <= 0x0F) return names[op];
  char buf[32];
  std::snprintf(buf, sizeof(buf), "opcode 0x%02X", op);
  return buf;
}

std::uint32_t crc32_update(std::uint32_t crc, std::string_view bytes) {
  return static_cast<std::uint32_t>(
      crc32_z(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<z_size_t>(bytes.size())));
}

McapSchema parse_schema(std::string_view content) {
  Cursor c(content, "Schema");
  McapSchema s;
  s.id = c.u16();
  s.name = c.string();
  s.encoding = c.string();
  s.data = std::string(c.bytes(c.u32(), "the schema data"));
  return s;
}

McapChannel parse_channel(std::string_view content) {
  Cursor c(content, "Channel");
  McapChannel ch;
  ch.id = c.u16();
  ch.schema_id = c.u16();
  ch.topic = c.string();
  ch.message_encoding = c.string();
  Cursor m(c.bytes(c.u32(), "the metadata map"), "Channel");
  while (m.remaining() > 0) {
    std::string key = m.string();
    ch.metadata.emplace_back(std::move(key), m.string());
  }
  return ch;
}

ChunkHeader parse_chunk_header(Cursor& c) {
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

}  // namespace canopy::ros2::mcap
