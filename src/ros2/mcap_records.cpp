#include "mcap_records.h"

#include <zlib.h>

#include <cstdio>

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

}  // namespace canopy::ros2::mcap
