#pragma once
// Reading MCAP recordings of the ros2 profile (rosbag2's, Foxglove's, canopy's), streamed with
// bounded memory: the summary is read when the file has one (else the file is scanned once,
// a chunk at a time), then messages are delivered in log-time order, a chunk decompressed at a
// time (chunks that overlap in time are merged, all of them open at once only while they
// overlap). Every length is checked against the file and its record before anything is
// allocated, chunks against their CRCs, and a chunk's uncompressed size against 1 GiB. A
// truncated, corrupt or non-ros2 file, an unknown compression or a record past the end throws
// InputError: one line naming the file and the problem.
//
//   ros2::McapReader in("lab.mcap");
//   ros2::McapReadOptions only;
//   only.topics = {"/camera/color/camera_info"};
//   in.for_each_message([&](const ros2::McapMessage& m) {
//     info = in.decode<ros2::msg::CameraInfo>(m);
//     return true;  // false stops
//   }, only);

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/ros2/messages.h"

namespace canopy::ros2 {

/// The largest chunk (uncompressed records) canopy reads or writes; a larger declared size is
/// refused before anything is allocated.
constexpr std::uint64_t kMaxChunkUncompressedBytes = std::uint64_t(1) << 30;

/// An MCAP Schema record: how a channel's messages are laid out.
struct McapSchema {
  std::uint16_t id = 0;
  std::string name;      ///< For ros2: the type, "sensor_msgs/msg/Image".
  std::string encoding;  ///< For ros2: "ros2msg".
  std::string data;      ///< For ros2msg: the definition text (message_schemas.h).
};

/// An MCAP Channel record: a topic and its encoding.
struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  ///< 0: no schema.
  std::string topic;
  std::string message_encoding;  ///< For ros2: "cdr".
  std::vector<std::pair<std::string, std::string>> metadata;
};

/// One message as the reader delivers it; `data` and the pointers live until the callback returns.
struct McapMessage {
  const McapChannel* channel = nullptr;
  const McapSchema* schema = nullptr;  ///< nullptr when the channel has no schema.
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::string_view data;
};

/// A topic of the file, for listings.
struct McapTopic {
  std::string topic;
  std::string type;              ///< The schema's name ("" without a schema).
  std::string message_encoding;
  std::uint16_t channel_id = 0;
  std::optional<std::uint64_t> message_count;  ///< When the file's statistics say.
};

/// In which order for_each_message delivers the messages.
enum class McapOrder {
  kLogTime,  ///< Log time, ties in file order (what a player does).
  kFile,     ///< As they lie in the file: one chunk open at a time, whatever the times.
};

/// Which messages for_each_message delivers, and how.
struct McapReadOptions {
  McapOrder order = McapOrder::kLogTime;
  std::vector<std::string> topics;  ///< Only these topics (empty: all); chunks without them are skipped.
};

/// Called for each message; returns false to stop reading.
using McapMessageCallback = std::function<bool(const McapMessage&)>;

/// A ros2-profile MCAP file opened for reading.
class McapReader {
 public:
  /// Opens `path` and reads its header, footer and summary (or scans it when it has none).
  /// Throws InputError when it is missing, not a regular file, not an MCAP of the ros2
  /// profile, truncated or corrupt; IoError when the system refuses a read.
  explicit McapReader(std::string path);
  ~McapReader();
  McapReader(const McapReader&) = delete;
  McapReader& operator=(const McapReader&) = delete;

  const std::string& path() const;
  const std::string& profile() const;
  /// The writer named in the Header ("canopy 0.2.0", "rosbag2", "mcap-ts ...").
  const std::string& library() const;
  /// True when the file's summary indexed its chunks (no scan was needed).
  bool indexed() const;

  const std::map<std::uint16_t, McapSchema>& schemas() const;
  const std::map<std::uint16_t, McapChannel>& channels() const;
  /// The channels, by topic name then id, with their types and message counts.
  std::vector<McapTopic> topics() const;
  /// Messages in the file (from its statistics, or counted by the scan); nullopt when unknown.
  std::optional<std::uint64_t> message_count() const;

  /// Calls `callback` for each message (in `options.order`, on `options.topics`), decompressing
  /// one chunk at a time (more only where chunks overlap in log time, up to 2 GiB at once).
  /// Throws InputError on a corrupt chunk (CRC, lengths, a message on an unknown channel, a
  /// time outside its chunk's range) or an unknown topic in `options.topics`.
  void for_each_message(const McapMessageCallback& callback, const McapReadOptions& options = {}) const;

  /// Checks the CRCs of the whole data section and of the summary (one pass over the file);
  /// throws InputError on a mismatch.
  void verify() const;

  /// The ROS 2 message in `message`, checked to be of M's type and CDR; InputError (naming the
  /// file, the topic and the log time) otherwise or when its bytes are malformed.
  template <class M>
  M decode(const McapMessage& message) const {
    check_type(message, M::kTypeName);
    try {
      return deserialize<M>(message.data);
    } catch (const InputError& e) {
      throw InputError(message_context(message) + ": " + e.what());
    }
  }

 private:
  struct Impl;
  void check_type(const McapMessage& message, const char* type_name) const;
  std::string message_context(const McapMessage& message) const;
  std::unique_ptr<Impl> impl_;
};

/// True when `path` is an MCAP file whose Header names canopy as its writer (library
/// "canopy ..."): the only kind of existing file McapWriter replaces. Never throws.
bool is_canopy_mcap(const std::string& path);

}  // namespace canopy::ros2
