#include <gtest/gtest.h>

#include <cstring>

#include <octomap/OcTree.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/mapping/map_io.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/perception/semantic_extractor.h"
#include "synthetic.h"

using namespace canopy;
using namespace canopy::mapping;
namespace fs = std::filesystem;

namespace {
SemanticOcTree sample_map() {
  SemanticOcTree map(SemanticMapParams{}, SemanticClasses{});
  ScanInserter ins(map);
  CameraIntrinsics K;
  K.width_px = K.height_px = 120;
  K.fx_px = K.fy_px = 114.4;
  K.cx_px = K.cy_px = 60;
  const std::vector<synth::Sphere> scene = {{Vec3(0.5, 0, 1), 0.05, 2, 1}, {Vec3(0.6, 0.1, 1), 0.08, 1}};
  for (int v = 0; v < 3; ++v) {
    const LabelledFrame f = synth::render_spheres(
        K, synth::look_at(Vec3(0, -0.3 + 0.3 * v, 1.1), Vec3(0.5, 0, 1)), scene);
    ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
  }
  return map;
}

// Rewrites the trailing FNV-1a checksum of .csm bytes, so that corrupted bytes get past the
// checksum and reach the structural checks.
void resign(std::string& bytes) {
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < body; ++i) h = (h ^ static_cast<unsigned char>(bytes[i])) * 1099511628211ull;
  std::memcpy(&bytes[body], &h, sizeof(h));
}

// Loads `bytes`: a map must write back the very same bytes (nothing half-read, nothing
// silently altered); anything else must be an InputError. Returns true when it loaded.
bool loads_exactly_or_is_rejected(const std::string& bytes, const std::string& what) {
  try {
    const SemanticOcTree m = deserialize_map(bytes, "fuzz");
    EXPECT_EQ(serialize_map(m), bytes) << what;
    return true;
  } catch (const InputError&) {
    return false;
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": not an InputError: " << e.what();
    return false;
  }
}

std::string temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("canopy_map_io_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d.string();
}
}  // namespace

TEST(MapIo, SaveLoadRoundTripIsExact) {
  const SemanticOcTree map = sample_map();
  ASSERT_GT(map.size(), 1000u);
  const std::string path = temp_dir() + "/map.csm";
  save_map(map, path);
  const SemanticOcTree back = load_map(path);
  EXPECT_TRUE(back.identical(map));
  EXPECT_EQ(back.revision(), map.revision());
  EXPECT_EQ(serialize_map(back), serialize_map(map));
  // An empty map round-trips too.
  const SemanticOcTree empty(SemanticMapParams{}, SemanticClasses{});
  EXPECT_TRUE(deserialize_map(serialize_map(empty), "empty").identical(empty));
}

// A compressed map (.csm.zst) reads back as the very same .csm bytes and the same map; the
// `zstd` tool's own frame of the bytes loads too (load_map goes by the bytes, not the name); a
// damaged frame, or one that hides its size, is an InputError naming the file.
TEST(MapIo, CompressedMapsReadBackTheSameBytes) {
  const SemanticOcTree map = sample_map();
  const std::string csm = serialize_map(map);
  const std::string dir = temp_dir();
  save_map(map, dir + "/map.csm.zst");
  const std::string packed = read_file(dir + "/map.csm.zst");
  EXPECT_LT(packed.size() * 4, csm.size());
  EXPECT_EQ(map_bytes(packed, "packed"), csm);
  EXPECT_EQ(map_bytes(csm, "plain"), csm);  // plain bytes pass through
  const SemanticOcTree back = load_map(dir + "/map.csm.zst");
  EXPECT_TRUE(back.identical(map));
  EXPECT_EQ(serialize_map(back), csm);
  // Named .csm, compressed at another level: read by its bytes.
  {
    std::ofstream f(dir + "/other.csm", std::ios::binary);
    const std::string fast = compress_map_bytes(csm, 1);
    f.write(fast.data(), static_cast<std::streamsize>(fast.size()));
  }
  EXPECT_EQ(serialize_map(load_map(dir + "/other.csm")), csm);
  // Damage: a cut frame, flipped bytes in its body, a frame without its size.
  EXPECT_THROW(map_bytes(packed.substr(0, packed.size() / 2), "cut"), InputError);
  int caught = 0;
  for (std::size_t i = 8; i < packed.size(); i += 1 + packed.size() / 37) {
    std::string bad = packed;
    bad[i] = static_cast<char>(bad[i] ^ 0x5a);
    try {  // a flip the frame does not notice is caught by the .csm checksum
      deserialize_map(map_bytes(bad, "flipped.csm.zst"), "flipped.csm.zst");
    } catch (const InputError& e) {
      ++caught;
      EXPECT_NE(std::string(e.what()).find("flipped.csm.zst"), std::string::npos) << e.what();
    }
  }
  EXPECT_GT(caught, 30);
  std::string sizeless = packed;
  sizeless[4] = 0;  // frame header descriptor: no content size, no checksum, no window flag
  EXPECT_THROW(map_bytes(sizeless, "sizeless"), InputError);
  EXPECT_TRUE(compressed_map_path("a/map.csm.zst"));
  EXPECT_FALSE(compressed_map_path("a/map.csm"));
}

TEST(MapIo, TruncatedOrCorruptFilesThrowInputError) {
  const std::string bytes = serialize_map(sample_map());
  // Every truncation length fails cleanly (a sample of them, to stay fast).
  for (std::size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 97)
    EXPECT_THROW(deserialize_map(bytes.substr(0, n), "cut"), InputError) << n;
  for (std::size_t i = 0; i < bytes.size(); i += 1 + bytes.size() / 61) {
    std::string bad = bytes;
    bad[i] = static_cast<char>(bad[i] ^ 0x5a);
    EXPECT_THROW(deserialize_map(bad, "flipped"), InputError) << i;
  }
  EXPECT_THROW(load_map("/nonexistent/map.csm"), InputError);
  // Corruption that keeps a valid checksum (re-signed after the flip) reaches the structural
  // checks: every such file is either rejected with InputError or loads as a map that
  // writes back the very same bytes (nothing half-read, nothing silently altered).
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  std::size_t rejected = 0, accepted = 0;
  for (std::size_t i = 12; i < body; i += 1 + body / 211) {
    for (const unsigned char flip : {0x01, 0x5a, 0x80}) {
      std::string bad = bytes;
      bad[i] = static_cast<char>(bad[i] ^ flip);
      resign(bad);
      if (loads_exactly_or_is_rejected(bad, "byte " + std::to_string(i))) ++accepted;
      else ++rejected;
    }
  }
  EXPECT_GT(rejected, 0u);
  EXPECT_GT(rejected + accepted, 300u);
  try {
    deserialize_map(bytes.substr(0, bytes.size() - 3), "my.csm");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("my.csm"), std::string::npos);
  }
}

TEST(MapIo, FuzzedResignedFilesLoadExactlyOrRaiseInputError) {
  // A seeded loop of truncations and byte mutations, each re-signed so the checksum
  // passes: every case either loads to a map that writes back the same bytes or raises
  // InputError; none crashes (the suite also runs under ASan/UBSan).
  const std::string bytes = serialize_map(sample_map());
  const std::size_t header = 12, trailer = sizeof(std::uint64_t);
  ASSERT_GT(bytes.size(), 1000u);
  std::mt19937_64 rng(20240917);
  auto uniform = [&](std::size_t lo, std::size_t hi) {  // in [lo, hi]
    return std::uniform_int_distribution<std::size_t>(lo, hi)(rng);
  };
  const std::uint32_t extremes[] = {0u, 1u, 0x7fu, 0xffu, 0x7fffffffu, 0x80000000u, 0xffffffffu};
  std::size_t accepted = 0, rejected = 0;
  const int cases = 3000;
  for (int c = 0; c < cases; ++c) {
    std::string bad = bytes;
    std::string what;
    switch (c % 4) {
      case 0: {  // cut anywhere, then re-sign what is left
        bad.resize(uniform(header + trailer, bytes.size() - 1));
        what = "cut to " + std::to_string(bad.size());
        break;
      }
      case 1: {  // a few random bytes anywhere before the checksum
        const std::size_t n = uniform(1, 4);
        for (std::size_t k = 0; k < n; ++k) bad[uniform(0, bad.size() - trailer - 1)] = static_cast<char>(uniform(0, 255));
        what = std::to_string(n) + " random bytes";
        break;
      }
      case 2: {  // one bit
        const std::size_t i = uniform(header, bad.size() - trailer - 1);
        bad[i] = static_cast<char>(bad[i] ^ (1 << uniform(0, 7)));
        what = "bit flip at " + std::to_string(i);
        break;
      }
      default: {  // an extreme 32-bit value over a length, count or mask
        const std::size_t i = uniform(header, bad.size() - trailer - 4);
        const std::uint32_t v = extremes[uniform(0, std::size(extremes) - 1)];
        std::memcpy(&bad[i], &v, sizeof(v));
        what = "value " + std::to_string(v) + " at " + std::to_string(i);
        break;
      }
    }
    resign(bad);
    if (loads_exactly_or_is_rejected(bad, what)) ++accepted;
    else ++rejected;
  }
  EXPECT_EQ(accepted + rejected, std::size_t(cases));
  EXPECT_GT(rejected, std::size_t(cases) / 10);  // the structural checks were reached
  EXPECT_GT(accepted, 0u);                        // and payload changes within bounds load
}

TEST(MapIo, PlyHasOneVertexPerOccupiedVoxel) {
  const SemanticOcTree map = sample_map();
  const std::string path = temp_dir() + "/map.ply";
  const std::size_t n = export_ply(map, path);
  EXPECT_EQ(n, map.counts().occupied);
  const std::string text = read_file(path);
  const std::size_t end = text.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  EXPECT_NE(text.find("element vertex " + std::to_string(n) + "\n"), std::string::npos);
  EXPECT_EQ(text.size() - (end + 11), n * (12 + 4 + 4));
}

TEST(MapIo, BtExportReadsBackInOctoMap) {
  const SemanticOcTree map = sample_map();
  const std::string path = temp_dir() + "/map.bt";
  export_bt(map, path);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(path));
  EXPECT_DOUBLE_EQ(tree.getResolution(), map.getResolution());
  std::size_t agree = 0, total = 0;
  map.for_each_leaf([&](const octomap::OcTreeKey& key, unsigned depth, const SemanticState& s) {
    if (depth != 16) return;
    const octomap::OcTreeNode* n = tree.search(key);
    ASSERT_NE(n, nullptr);
    ++total;
    agree += tree.isNodeOccupied(n) == (s.occupancy_logodds() > 0.f);
  });
  EXPECT_EQ(agree, total);
  EXPECT_GT(total, 1000u);
}
