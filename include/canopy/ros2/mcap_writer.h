#pragma once
// Writing MCAP recordings (mcap.dev specification; profile "ros2": ros2msg schemas, CDR
// messages), which Foxglove, `ros2 bag play` and `mcap` read. Messages go into chunks
// (compressed with lz4 or zstd, or not at all), each followed by its message indexes; close()
// writes the summary (schemas, channels, statistics, chunk indexes) and its offsets, so readers
// can seek, with every CRC the format has.
//
// The file appears whole or not at all: it is written under a temporary name beside `path` and
// renamed into place by close(). An existing file at `path` is replaced only when canopy wrote
// it (its Header's library starts with "canopy"); a lab's recording is never overwritten.
//
//   ros2::McapWriter out("run.mcap");
//   auto rgb = out.add_channel<ros2::msg::Image>("/camera/color/image_raw");
//   out.write(rgb, stamp_ns, image);
//   out.close();

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/ros2/cdr.h"
#include "canopy/ros2/compression.h"

namespace canopy::ros2 {

/// How a McapWriter lays out its file.
struct McapWriterOptions {
  Compression compression = Compression::kZstd;  ///< Chunk compression.
  /// 1: the fastest (zstd 1, lz4's fast mode); on 640x480 camera images zstd 1 wrote about 3x
  /// faster than zstd 3 for 7 % more bytes (docs/ros2.md). 0: the library's default (zstd 3).
  int compression_level = 1;
  /// A chunk is closed once its uncompressed records reach this many bytes (a larger message
  /// gets a chunk of its own). Readers hold about one chunk at a time.
  std::uint64_t chunk_size_bytes = std::uint64_t(4) << 20;
  /// The summary section (what lets readers seek and list topics without a pass over the file).
  /// Off only to test readers on files a streaming recorder writes.
  bool write_summary = true;
};

/// What a McapWriter has written so far.
struct McapWriteStats {
  std::uint64_t messages = 0;
  std::uint64_t chunks = 0;
  std::uint64_t message_bytes = 0;  ///< Message data before compression.
  std::uint64_t file_bytes = 0;     ///< Bytes written to the file (all of it after close()).
};

/// Writes one MCAP file (not thread-safe: one writer per thread).
class McapWriter {
 public:
  /// Starts writing `path` (its temporary file beside it). Throws InputError when `path` exists
  /// and is not an MCAP canopy wrote, is a link, a folder or another kind of file; IoError when
  /// the temporary file cannot be created.
  explicit McapWriter(std::string path, McapWriterOptions options = {});
  /// Without close(), removes the temporary file: nothing appears at `path`.
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// Registers a schema; returns its id (from 1). The same (name, encoding, data) gives the same id.
  std::uint16_t add_schema(const std::string& name, const std::string& encoding, std::string_view data);
  /// Registers a channel on `schema_id` (0: no schema); returns its id (from 1).
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                            const std::vector<std::pair<std::string, std::string>>& metadata = {});
  /// A CDR channel of the ROS 2 type `type_name` ("sensor_msgs/msg/Image"), its ros2msg schema
  /// registered once. Throws InputError for a type message_schemas.h does not know.
  std::uint16_t add_ros2_channel(const std::string& topic, const std::string& type_name);
  /// add_ros2_channel for the message struct M of messages.h.
  template <class M>
  std::uint16_t add_channel(const std::string& topic) {
    return add_ros2_channel(topic, M::kTypeName);
  }

  /// Writes one message: `data` as it goes in the record (CDR bytes for a ros2 channel). Log
  /// times need not increase (readers sort them); the sequence number counts per channel.
  /// Throws IoError when the disk refuses it, InputError for a message over 1 GiB.
  void write(std::uint16_t channel_id, std::uint64_t log_time_ns, std::uint64_t publish_time_ns,
             std::string_view data);
  /// Serialises `message` (CDR) onto a channel of its type; publish time = log time.
  template <class M>
  void write(std::uint16_t channel_id, std::uint64_t log_time_ns, const M& message) {
    check_channel_type(channel_id, M::kTypeName);
    scratch_.reset();
    scratch_(message);
    write(channel_id, log_time_ns, log_time_ns, scratch_.bytes());
  }

  /// Writes the last chunk, the summary and the footer, and renames the file into place
  /// (refusing, as the constructor does, a file that appeared at `path` meanwhile and is not
  /// canopy's). After close() nothing more can be written.
  void close();

  const std::string& path() const { return path_; }
  const McapWriteStats& stats() const { return stats_; }

 private:
  struct State;
  void check_channel_type(std::uint16_t channel_id, const char* type_name) const;

  std::string path_;
  std::unique_ptr<State> state_;
  CdrWriter scratch_;
  McapWriteStats stats_;
};

/// The library string canopy writes in the Header record: "canopy <version>".
std::string mcap_library_name();

}  // namespace canopy::ros2
