// McapWriter: the file's frame (magic, Header naming canopy, footer), every message back
// byte for byte with every compression, chunking, and the file appearing whole or not at all,
// never over a file canopy did not write.
#include "canopy/ros2/mcap_writer.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>

#include "canopy/ros2/mcap_reader.h"
#include "expect_input_error.h"
#include "mcap_test_files.h"

namespace canopy::ros2 {
namespace {

using namespace test;
namespace fs = std::filesystem;

std::vector<Written> read_all(const McapReader& in, McapOrder order = McapOrder::kLogTime) {
  std::vector<Written> out;
  McapReadOptions options;
  options.order = order;
  in.for_each_message(
      [&](const McapMessage& m) {
        out.push_back({m.channel->topic, m.schema->name, m.log_time_ns, std::string(m.data)});
        return true;
      },
      options);
  return out;
}

TEST(McapWriter, FileBeginsWithMagicAndHeaderAndEndsWithFooterAndMagic) {
  const std::string path = temp_path("frame.mcap");
  write_sample_recording(path, {});
  const std::string b = read_bytes(path);
  ASSERT_GT(b.size(), 100u);
  const std::string magic("\x89MCAP0\r\n", 8);
  EXPECT_EQ(b.substr(0, 8), magic);
  EXPECT_EQ(b.substr(b.size() - 8), magic);
  EXPECT_EQ(b[8], '\x01');  // Header
  const std::string library = mcap_library_name();
  EXPECT_EQ(library.rfind("canopy ", 0), 0u);
  EXPECT_NE(b.find(std::string("\x04\0\0\0ros2", 8) + std::string(1, char(library.size())) + std::string(3, '\0') + library),
            std::string::npos);
  EXPECT_EQ(b[b.size() - 8 - 29], '\x02');  // Footer
  const std::uint64_t summary_start = get_u64(b, b.size() - 8 - 20);
  EXPECT_GT(summary_start, 8u);
  EXPECT_EQ(b[summary_start - 13], '\x0F');  // Data End just before the summary
  EXPECT_TRUE(is_canopy_mcap(path));
}

TEST(McapWriter, EveryMessageReadsBackByteForByteWithEveryCompression) {
  for (Compression c : {Compression::kNone, Compression::kLz4, Compression::kZstd}) {
    SCOPED_TRACE(std::string(compression_name(c)));
    McapWriterOptions options;
    options.compression = c;
    const std::string path = temp_path("every.mcap");
    const std::vector<Written> written = write_sample_recording(path, options);
    McapReader in(path);
    EXPECT_TRUE(in.indexed());
    EXPECT_EQ(in.library(), mcap_library_name());
    EXPECT_EQ(in.profile(), "ros2");
    in.verify();
    EXPECT_EQ(in.message_count(), written.size());
    // File order is write order.
    const std::vector<Written> file_order = read_all(in, McapOrder::kFile);
    ASSERT_EQ(file_order.size(), written.size());
    for (std::size_t i = 0; i < written.size(); ++i) {
      EXPECT_EQ(file_order[i].topic, written[i].topic);
      EXPECT_EQ(file_order[i].type, written[i].type);
      EXPECT_EQ(file_order[i].log_time_ns, written[i].log_time_ns);
      EXPECT_TRUE(file_order[i].data == written[i].data) << i << " " << written[i].topic;
    }
    // Log-time order: the same messages, sorted, ties kept in file order.
    std::vector<Written> sorted = written;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const Written& a, const Written& b) { return a.log_time_ns < b.log_time_ns; });
    const std::vector<Written> log_order = read_all(in);
    ASSERT_EQ(log_order.size(), sorted.size());
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      EXPECT_EQ(log_order[i].topic, sorted[i].topic) << i;
      EXPECT_TRUE(log_order[i].data == sorted[i].data) << i;
    }
  }
}

TEST(McapWriter, TopicsListTypesEncodingsAndCounts) {
  const std::string path = temp_path("topics.mcap");
  write_sample_recording(path, {}, 3);
  McapReader in(path);
  const auto topics = in.topics();
  ASSERT_EQ(topics.size(), 10u);
  const auto find = [&](const std::string& name) {
    for (const McapTopic& t : topics)
      if (t.topic == name) return t;
    ADD_FAILURE() << "no topic " << name;
    return McapTopic{};
  };
  EXPECT_EQ(find("/tf").type, "tf2_msgs/msg/TFMessage");
  EXPECT_EQ(find("/tf").message_count, 3u);
  EXPECT_EQ(find("/camera/color/image_raw").type, "sensor_msgs/msg/Image");
  EXPECT_EQ(find("/camera/color/image_raw").message_encoding, "cdr");
  EXPECT_EQ(find("/tf_static").message_count, 1u);
  EXPECT_EQ(find("/canopy/views").type, "visualization_msgs/msg/MarkerArray");
  // One schema per type (7 types on 10 topics), ros2msg.
  EXPECT_EQ(in.schemas().size(), 7u);
  for (const auto& [id, s] : in.schemas()) EXPECT_EQ(s.encoding, "ros2msg") << s.name;
}

TEST(McapWriter, SmallChunksSplitTheRecording) {
  McapWriterOptions options;
  options.chunk_size_bytes = 2000;
  options.compression = Compression::kLz4;
  const std::string path = temp_path("small_chunks.mcap");
  McapWriteStats stats;
  {
    McapWriter out(path, options);
    const auto ch = out.add_channel<msg::Image>("/img");
    for (int i = 0; i < 20; ++i) out.write(ch, 1000 + i, sample_rgb(16, 12, 1000 + i, i));  // 576 bytes of pixels each
    out.close();
    stats = out.stats();
  }
  EXPECT_EQ(stats.messages, 20u);
  EXPECT_GE(stats.chunks, 6u);
  EXPECT_EQ(stats.file_bytes, fs::file_size(path));
  McapReader in(path);
  std::uint64_t n = 0, last = 0;
  in.for_each_message([&](const McapMessage& m) {
    EXPECT_GE(m.log_time_ns, last);
    last = m.log_time_ns;
    EXPECT_EQ(in.decode<msg::Image>(m).data, sample_rgb(16, 12, m.log_time_ns, int(n)).data);
    EXPECT_EQ(m.sequence, n);
    ++n;
    return true;
  });
  EXPECT_EQ(n, 20u);
}

TEST(McapWriter, AnEmptyRecordingIsValid) {
  const std::string path = temp_path("empty.mcap");
  {
    McapWriter out(path);
    out.add_channel<msg::TFMessage>("/tf");
    out.close();
  }
  McapReader in(path);
  EXPECT_EQ(in.message_count(), 0u);
  ASSERT_EQ(in.topics().size(), 1u);
  EXPECT_EQ(in.topics()[0].message_count, 0u);
  in.verify();
  int n = 0;
  in.for_each_message([&](const McapMessage&) { return ++n, true; });
  EXPECT_EQ(n, 0);
}

TEST(McapWriter, NothingAppearsBeforeCloseAndNothingStaysWithoutIt) {
  const std::string path = temp_path("atomic.mcap");
  {
    McapWriter out(path);
    const auto ch = out.add_channel<msg::String>("/s");
    out.write(ch, 1, msg::String{"a"});
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(fs::exists(path + ".partial"));
    // Not closed: an error or an exception ended the writing.
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_FALSE(fs::exists(path + ".lock"));
  {
    McapWriter out(path);
    out.close();
  }
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_FALSE(fs::exists(path + ".lock"));
}

TEST(McapWriter, ReplacesItsOwnRecordingOnly) {
  const std::string path = temp_path("own.mcap");
  write_sample_recording(path, {}, 1);
  write_sample_recording(path, {}, 2);  // canopy's own: replaced
  EXPECT_EQ(McapReader(path).message_count(), 2u * 4 + 6);

  // Another writer's MCAP (the same bytes, the Header naming another library) is never replaced.
  std::string b = read_bytes(path);
  const auto at = b.find("canopy");
  ASSERT_NE(at, std::string::npos);
  b.replace(at, 6, "rosbag");
  const std::string lab = temp_path("lab.mcap");
  write_bytes(lab, b);
  EXPECT_FALSE(is_canopy_mcap(lab));
  EXPECT_THROW(McapWriter{lab}, InputError);
  EXPECT_EQ(read_bytes(lab), b);
  EXPECT_FALSE(fs::exists(lab + ".partial"));
  EXPECT_FALSE(fs::exists(lab + ".lock"));

  const std::string text = temp_path("notes.mcap");
  write_bytes(text, "my notes\n");
  expect_input_error([&] { McapWriter out(text); }, "not an MCAP canopy wrote");
  EXPECT_EQ(read_bytes(text), "my notes\n");
}

TEST(McapWriter, RefusesLinksAndFolders) {
  const std::string target = temp_path("target.mcap");
  write_sample_recording(target, {}, 1);
  const std::string link = temp_path("link.mcap");
  fs::remove(link);
  fs::create_symlink(target, link);
  EXPECT_THROW(McapWriter{link}, InputError);
  const std::string dir = temp_path("folder.mcap");
  fs::create_directories(dir);
  EXPECT_THROW(McapWriter{dir}, InputError);
}

TEST(McapWriter, OneWriterAtATimePerPath) {
  const std::string path = temp_path("busy.mcap");
  McapWriter first(path);
  EXPECT_THROW(McapWriter{path}, InputError);
  first.close();
  McapWriter second(path);
  second.close();
}

TEST(McapWriter, AMissingFolderIsIoError) {
  EXPECT_THROW(McapWriter{temp_path("no/such/folder/x.mcap")}, IoError);
}

TEST(McapWriter, SchemasAreSharedAndTypesChecked) {
  const std::string path = temp_path("types.mcap");
  McapWriter out(path);
  const auto a = out.add_channel<msg::Image>("/a");
  const auto b = out.add_channel<msg::Image>("/b");
  EXPECT_NE(a, b);
  EXPECT_THROW(out.write(a, 1, msg::String{"x"}), InternalError);  // a String on an Image channel
  EXPECT_THROW(out.add_ros2_channel("/imu", "sensor_msgs/msg/Imu"), InputError);
  out.close();
  McapReader in(path);
  EXPECT_EQ(in.schemas().size(), 1u);
  EXPECT_EQ(in.channels().size(), 2u);
}

}  // namespace
}  // namespace canopy::ros2
