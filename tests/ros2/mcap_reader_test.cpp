// McapReader: log-time order across chunks that overlap, topic filters, files without a
// summary, and every kind of damage (a cut at any byte, flipped bytes, a foreign profile, an
// unknown compression, lengths past the end) refused with InputError: never a crash, a hang or
// an unbounded allocation.
#include "canopy/ros2/mcap_reader.h"

#include <gtest/gtest.h>

#include <random>

#include "mcap_test_files.h"
#include "expect_input_error.h"

namespace canopy::ros2 {
namespace {

using namespace test;

// Opens, checks and reads every message of `path` (decoding each by its type): what a user of
// the reader does. Returns the number of messages.
std::uint64_t read_everything(const std::string& path) {
  McapReader in(path);
  in.verify();
  std::uint64_t n = 0;
  in.for_each_message([&](const McapMessage& m) {
    const std::string& type = m.schema->name;
    if (type == msg::Image::kTypeName) in.decode<msg::Image>(m);
    if (type == msg::CameraInfo::kTypeName) in.decode<msg::CameraInfo>(m);
    if (type == msg::TFMessage::kTypeName) in.decode<msg::TFMessage>(m);
    if (type == msg::CompressedImage::kTypeName) in.decode<msg::CompressedImage>(m);
    if (type == msg::MarkerArray::kTypeName) in.decode<msg::MarkerArray>(m);
    ++n;
    return true;
  });
  return n;
}

// `bytes` as a file is refused with InputError naming it (or, when `may_pass`, read whole).
void expect_refused(const std::string& bytes, const std::string& what, bool may_pass = false) {
  const std::string path = temp_path("damaged.mcap");
  write_bytes(path, bytes);
  try {
    read_everything(path);
    if (!may_pass) ADD_FAILURE() << what << ": no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << what << ": " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << what << ": " << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": not InputError: " << e.what();
  }
}

TEST(McapReader, DeliversLogTimeOrderAcrossOverlappingChunks) {
  McapWriterOptions options;
  options.chunk_size_bytes = 300;  // a few messages a chunk
  const std::string path = temp_path("order.mcap");
  std::vector<std::pair<std::uint64_t, std::string>> written;
  {
    McapWriter out(path, options);
    const auto a = out.add_channel<msg::String>("/a");
    const auto b = out.add_channel<msg::String>("/b");
    for (int i = 0; i < 60; ++i) {
      // /a goes forward, /b backward, and every fifth /a message repeats a time.
      const std::uint64_t ta = 1000 + 10 * std::uint64_t(i - i % 5 == i ? i : i);
      out.write(a, ta, msg::String{"a" + std::to_string(i)});
      written.emplace_back(ta, "a" + std::to_string(i));
      const std::uint64_t tb = 2000 - 10 * std::uint64_t(i);
      out.write(b, tb, msg::String{"b" + std::to_string(i)});
      written.emplace_back(tb, "b" + std::to_string(i));
    }
    const auto s = out.add_channel<msg::String>("/static");
    out.write(s, 0, msg::String{"first"});  // written last, earliest of all
    written.emplace_back(0, "first");
    out.close();
    EXPECT_GT(out.stats().chunks, 10u);
  }
  std::stable_sort(written.begin(), written.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  McapReader in(path);
  std::vector<std::pair<std::uint64_t, std::string>> read;
  in.for_each_message([&](const McapMessage& m) {
    read.emplace_back(m.log_time_ns, in.decode<msg::String>(m).data);
    return true;
  });
  EXPECT_EQ(read, written);
}

TEST(McapReader, TopicFilterAndEarlyStop) {
  const std::string path = temp_path("filter.mcap");
  McapWriterOptions options;
  options.chunk_size_bytes = 4000;
  write_sample_recording(path, options, 8);
  McapReader in(path);
  McapReadOptions only;
  only.topics = {"/tf", "/tf_static"};
  int tf = 0;
  in.for_each_message(
      [&](const McapMessage& m) {
        EXPECT_TRUE(m.channel->topic == "/tf" || m.channel->topic == "/tf_static") << m.channel->topic;
        in.decode<msg::TFMessage>(m);
        ++tf;
        return true;
      },
      only);
  EXPECT_EQ(tf, 9);
  int seen = 0;
  in.for_each_message([&](const McapMessage&) { return ++seen < 3; });
  EXPECT_EQ(seen, 3);
  only.topics = {"/camera/nope"};
  // Named, with the topics the file has.
  expect_input_error([&] { in.for_each_message([](const McapMessage&) { return true; }, only); },
                     "no topic /camera/nope in the recording (its topics: /camera/aligned_depth");
}

TEST(McapReader, DecodeChecksTheType) {
  const std::string path = temp_path("decode.mcap");
  write_sample_recording(path, {}, 1);
  McapReader in(path);
  McapReadOptions only;
  only.topics = {"/tf"};
  in.for_each_message(
      [&](const McapMessage& m) {
        try {
          in.decode<msg::Image>(m);
          ADD_FAILURE() << "a TFMessage decoded as an Image";
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("/tf at "), std::string::npos) << e.what();
        }
        return true;
      },
      only);
}

TEST(McapReader, ScansAFileWithoutSummary) {
  for (Compression c : {Compression::kNone, Compression::kZstd}) {
    McapWriterOptions options;
    options.write_summary = false;
    options.compression = c;
    options.chunk_size_bytes = 3000;
    const std::string path = temp_path("nosummary.mcap");
    const auto written = write_sample_recording(path, options, 6);
    McapReader in(path);
    EXPECT_FALSE(in.indexed());
    EXPECT_EQ(in.message_count(), written.size());
    EXPECT_EQ(in.topics().size(), 10u);
    std::uint64_t last = 0, n = 0;
    in.for_each_message([&](const McapMessage& m) {
      EXPECT_GE(m.log_time_ns, last);
      last = m.log_time_ns;
      ++n;
      return true;
    });
    EXPECT_EQ(n, written.size());
    EXPECT_EQ(read_everything(path), written.size());
  }
}

TEST(McapReader, RefusesWhatIsNoMcap) {
  EXPECT_THROW(McapReader{temp_path("missing.mcap")}, InputError);
  EXPECT_THROW(McapReader{testing::TempDir()}, InputError);
  EXPECT_THROW(McapReader{"/dev/null"}, InputError);
  const std::string text = temp_path("text.mcap");
  write_bytes(text, "not an mcap file at all, but long enough to have a footer and more bytes than that..........");
  expect_input_error([&] { McapReader in(text); }, "not an MCAP file");
}

TEST(McapReader, RefusesAnotherProfile) {
  const std::string path = temp_path("profile.mcap");
  write_sample_recording(path, {}, 1);
  std::string b = read_bytes(path);
  const auto at = b.find("ros2");
  ASSERT_LT(at, 40u);
  b.replace(at, 4, "ros1");
  write_bytes(path, b);
  expect_input_error([&] { McapReader in(path); }, "profile 'ros1', not ros2");
}

TEST(McapReader, RefusesAnUnknownCompression) {
  McapWriterOptions options;
  options.compression = Compression::kZstd;
  for (bool summary : {true, false}) {
    options.write_summary = summary;
    const std::string path = temp_path("bz2.mcap");
    write_sample_recording(path, options, 1);
    std::string b = without_crcs(read_bytes(path));
    const std::string name("\x04\0\0\0zstd", 8);  // the compression field: length, then the name
    int replaced = 0;
    for (std::size_t at = b.find(name); at != std::string::npos; at = b.find(name, at + 1), ++replaced)
      b.replace(at + 4, 4, "zstx");
    EXPECT_GT(replaced, 0);
    write_bytes(path, b);
    SCOPED_TRACE(summary ? "with a summary" : "without a summary");
    expect_input_error([&] { read_everything(path); }, "compressed with 'zstx'");
  }
}

TEST(McapReader, RefusesLengthsPastTheEndAndHugeChunks) {
  McapWriterOptions options;
  options.write_summary = false;  // the data section's own lengths are all there is
  const std::string path = temp_path("lengths.mcap");
  write_sample_recording(path, options, 2);
  const std::string b = without_crcs(read_bytes(path));
  const auto chunks = data_records(b, 0x06);
  ASSERT_FALSE(chunks.empty());
  {
    std::string bad = b;
    const std::uint64_t huge = std::uint64_t(1) << 62;
    std::memcpy(bad.data() + chunks[0] + 1, &huge, 8);  // the record's length
    expect_refused(bad, "record length past the end");
  }
  {
    std::string bad = b;
    const std::uint64_t size = std::uint64_t(1) << 40;
    std::memcpy(bad.data() + chunks[0] + 9 + 16, &size, 8);  // uncompressed_size: 1 TiB
    const std::string p = temp_path("huge.mcap");
    write_bytes(p, bad);
    expect_input_error([&] { read_everything(p); }, "at most 1 GiB");
  }
  {
    std::string bad = b;
    const std::uint64_t size = std::uint64_t(900) << 20;  // under the cap, not what the frame holds
    std::memcpy(bad.data() + chunks[0] + 9 + 16, &size, 8);
    expect_refused(bad, "a chunk declaring 900 MiB");
  }
}

TEST(McapReader, RefusesEveryCut) {
  for (Compression c : {Compression::kNone, Compression::kLz4}) {
    McapWriterOptions options;
    options.compression = c;
    options.chunk_size_bytes = 1500;
    const std::string path = temp_path("cut_source.mcap");
    write_sample_recording(path, options, 1, 4, 3);
    const std::string b = read_bytes(path);
    for (std::size_t n = 0; n < b.size(); ++n)
      expect_refused(b.substr(0, n), std::string(compression_name(c)) + " cut at " + std::to_string(n));
    // A cut file with its magic put back at the end is still refused.
    for (std::size_t n = 8; n + 8 < b.size(); n += 37)
      expect_refused(b.substr(0, n) + b.substr(b.size() - 8), "cut at " + std::to_string(n) + ", magic restored");
  }
}

TEST(McapReader, EveryFlippedByteIsCaught) {
  // With its CRCs every byte of the file is checked: a flip anywhere is refused.
  McapWriterOptions options;
  options.compression = Compression::kZstd;
  options.chunk_size_bytes = 1500;
  const std::string path = temp_path("flip_source.mcap");
  write_sample_recording(path, options, 1, 4, 3);
  const std::string b = read_bytes(path);
  for (std::size_t i = 0; i < b.size(); ++i) {
    std::string bad = b;
    bad[i] ^= 0x10;
    expect_refused(bad, "flip at byte " + std::to_string(i));
  }
}

TEST(McapReader, FuzzedFilesNeverCrash) {
  // Random flips (fixed seed) of files with and without CRCs, with and without a summary: each
  // is read whole or refused with InputError (expect_refused fails on any other exception; a
  // crash or a hang fails the test run).
  std::mt19937 rng(20261205);
  int refused = 0, passed = 0;
  for (int variant = 0; variant < 6; ++variant) {
    McapWriterOptions options;
    options.compression = variant % 3 == 0 ? Compression::kNone : variant % 3 == 1 ? Compression::kLz4 : Compression::kZstd;
    options.write_summary = variant < 3;
    options.chunk_size_bytes = 1200;
    const std::string path = temp_path("fuzz_source.mcap");
    write_sample_recording(path, options, 2, 4, 3);
    const std::string with_crcs = read_bytes(path);
    const std::string no_crcs = without_crcs(with_crcs);
    for (int round = 0; round < 400; ++round) {
      std::string bad = round % 2 == 0 ? no_crcs : with_crcs;
      const int flips = 1 + int(rng() % 4);
      for (int f = 0; f < flips; ++f) bad[rng() % bad.size()] = static_cast<char>(rng() & 0xFF);
      const std::string p = temp_path("fuzz.mcap");
      write_bytes(p, bad);
      try {
        read_everything(p);
        ++passed;
      } catch (const InputError&) {
        ++refused;
      } catch (const std::exception& e) {
        ADD_FAILURE() << "variant " << variant << " round " << round << ": " << e.what();
      }
    }
  }
  EXPECT_GT(refused, 1000);  // most flips are caught; a flip in message bytes without CRCs reads on
  RecordProperty("refused", refused);
  RecordProperty("passed", passed);
}

}  // namespace
}  // namespace canopy::ros2
