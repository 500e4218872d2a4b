#include "canopy/mapping/map_io.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/common/zstd_bytes.h"

namespace canopy::mapping {

namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "map files are written little-endian");

constexpr char kMagic[8] = {'C', 'A', 'N', 'O', 'P', 'Y', 'S', 'M'};

std::uint64_t fnv1a(const char* data, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 1099511628211ull;
  }
  return h;
}

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable<T>::value, "POD only");
    out_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put_string(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    out_.append(s);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(const std::string& bytes, std::size_t end, std::string name) : b_(bytes), end_(end), name_(std::move(name)) {}
  template <typename T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string get_string(std::size_t max_len) {
    const auto n = get<std::uint32_t>();
    if (n > max_len) fail("a string of " + std::to_string(n) + " bytes");
    need(n);
    std::string s = b_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(name_ + ": corrupt semantic map file (" + what + " at byte " + std::to_string(pos_) + ")");
  }
  std::size_t remaining() const { return end_ - pos_; }

 private:
  void need(std::size_t n) const {
    if (n > end_ - pos_) fail("unexpected end of data");
  }
  const std::string& b_;
  std::size_t end_;
  std::size_t pos_ = 0;
  std::string name_;
};

void put_state(Writer& w, const SemanticState& s) {
  for (float l : s.logodds) w.put(l);
  w.put(s.others);
  for (std::uint8_t c : s.class_id) w.put(c);
  w.put(s.count);
}

SemanticState get_state(Reader& r, int num_classes, const UpdateRule& rule) {
  SemanticState s;
  for (float& l : s.logodds) l = r.get<float>();
  s.others = r.get<float>();
  for (std::uint8_t& c : s.class_id) c = r.get<std::uint8_t>();
  s.count = r.get<std::uint8_t>();
  if (s.count > SemanticState::kSlots) r.fail("a voxel with " + std::to_string(s.count) + " classes");
  if (!std::isfinite(s.others)) r.fail("a non-finite log-odds");
  for (int i = 0; i < SemanticState::kSlots; ++i) {
    if (!std::isfinite(s.logodds[i])) r.fail("a non-finite log-odds");
    const bool used = i < s.count;
    if (used && s.class_id[i] >= num_classes) r.fail("class index " + std::to_string(s.class_id[i]) + " out of range");
    if (!used && s.class_id[i] != SemanticState::kNoClass) r.fail("a stray class index");
    if (!used && s.logodds[i] != 0.f) r.fail("a log-odds in an empty slot");
  }
  // The invariants the update rules keep: log-odds within the clamps, stored classes
  // distinct and sorted strongest first.
  auto in_clamps = [&](float l) { return l >= rule.min && l <= rule.max; };
  if (!in_clamps(s.others)) r.fail("a log-odds outside the clamps");
  for (int i = 0; i < s.count; ++i) {
    if (!in_clamps(s.logodds[i])) r.fail("a log-odds outside the clamps");
    for (int j = 0; j < i; ++j)
      if (s.class_id[j] == s.class_id[i]) r.fail("a class stored twice in one voxel");
    if (i > 0 && s.logodds[i] > s.logodds[i - 1]) r.fail("a voxel whose classes are not sorted");
  }
  return s;
}

void write_node(Writer& w, const SemanticNode* node) {
  std::uint8_t mask = 0;
  for (unsigned i = 0; i < 8; ++i)
    if (node->child(i)) mask |= static_cast<std::uint8_t>(1u << i);
  w.put(mask);
  if (mask == 0) {
    put_state(w, node->state());
    return;
  }
  for (unsigned i = 0; i < 8; ++i)
    if (node->child(i)) write_node(w, node->child(i));
}

void read_node(Reader& r, SemanticNode* node, unsigned depth, int num_classes, const UpdateRule& rule,
               std::size_t* nodes) {
  const auto mask = r.get<std::uint8_t>();
  if (mask == 0) {
    node->state() = get_state(r, num_classes, rule);
    return;
  }
  if (depth == kOctreeDepth) r.fail("a voxel with children");
  for (unsigned i = 0; i < 8; ++i) {
    if (!(mask & (1u << i))) continue;
    ++*nodes;
    read_node(r, node->make_child(i), depth + 1, num_classes, rule, nodes);
  }
}

}  // namespace

std::string serialize_map(const SemanticOcTree& map) {
  Writer w;
  w.bytes().append(kMagic, sizeof(kMagic));
  w.put(kMapFormatVersion);
  const SemanticMapParams& p = map.params();
  w.put(p.resolution_m);
  w.put(p.hit_logodds);
  w.put(p.pass_logodds);
  w.put(p.clamp_min_logodds);
  w.put(p.clamp_max_logodds);
  w.put(p.max_range_m);
  w.put(p.ray_range_m);
  w.put(p.unseen_logodds);
  w.put(static_cast<std::uint8_t>(p.prune));
  w.put(static_cast<std::uint8_t>(p.entropy_categories == EntropyCategories::kPrototype));
  w.put(static_cast<std::int32_t>(p.threads));
  const SemanticClasses& c = map.classes();
  w.put(static_cast<std::uint32_t>(c.names.size()));
  for (const std::string& n : c.names) w.put_string(n);
  w.put_string(c.target);
  w.put(map.revision());
  w.put(static_cast<std::uint64_t>(map.size()));
  const SemanticNode* root = map.getRoot();
  w.put(static_cast<std::uint8_t>(root != nullptr));
  if (root) write_node(w, root);
  w.put(fnv1a(w.bytes().data(), w.bytes().size()));
  return std::move(w.bytes());
}

SemanticOcTree deserialize_map(const std::string& bytes, const std::string& name) {
  const std::size_t min_size = sizeof(kMagic) + sizeof(std::uint32_t) + sizeof(std::uint64_t);
  if (bytes.size() < min_size || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
    throw InputError(name + ": not a canopy semantic map file (bad magic or too short)");
  std::uint32_t version;
  std::memcpy(&version, bytes.data() + sizeof(kMagic), sizeof(version));
  if (version != kMapFormatVersion)
    throw InputError(name + ": semantic map format version " + std::to_string(version) + " is not supported (expected " +
                     std::to_string(kMapFormatVersion) + ")");
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + body, sizeof(stored));
  if (stored != fnv1a(bytes.data(), body))
    throw InputError(name + ": semantic map file is truncated or corrupt (checksum mismatch)");

  Reader r(bytes, body, name);
  for (std::size_t i = 0; i < sizeof(kMagic) + sizeof(std::uint32_t); ++i) r.get<char>();
  SemanticMapParams p;
  p.resolution_m = r.get<double>();
  p.hit_logodds = r.get<float>();
  p.pass_logodds = r.get<float>();
  p.clamp_min_logodds = r.get<float>();
  p.clamp_max_logodds = r.get<float>();
  p.max_range_m = r.get<double>();
  p.ray_range_m = r.get<double>();
  p.unseen_logodds = r.get<float>();
  const auto prune = r.get<std::uint8_t>();
  if (prune > 1) r.fail("a bad prune flag");
  p.prune = prune != 0;
  const auto categories = r.get<std::uint8_t>();
  if (categories > 1) r.fail("a bad entropy categories flag");
  p.entropy_categories = categories ? EntropyCategories::kPrototype : EntropyCategories::kPaper;
  p.threads = r.get<std::int32_t>();
  p.validate(name);
  SemanticClasses c;
  const auto n_classes = r.get<std::uint32_t>();
  if (n_classes == 0 || n_classes > 255) r.fail(std::to_string(n_classes) + " classes");
  c.names.clear();
  for (std::uint32_t i = 0; i < n_classes; ++i) c.names.push_back(r.get_string(1024));
  c.target = r.get_string(1024);
  c.validate(name);
  SemanticOcTree map(p, c);
  const auto revision = r.get<std::uint64_t>();
  const auto size = r.get<std::uint64_t>();
  const auto has_root = r.get<std::uint8_t>();
  if (has_root > 1) r.fail("a bad root flag");
  std::size_t nodes = 0;
  if (has_root) {
    nodes = 1;
    read_node(r, map.create_root(), 0, c.size(), map.rule(), &nodes);
    if (!map.getRoot()->has_children()) r.fail("a root without children");
  }
  if (nodes != size) r.fail("node count " + std::to_string(nodes) + " but header says " + std::to_string(size));
  if (r.remaining() != 0) r.fail("trailing bytes");
  map.set_loaded_state(nodes, revision);
  return map;
}

bool compressed_map_path(const std::string& path) {
  return path.size() >= 4 && path.compare(path.size() - 4, 4, ".zst") == 0;
}

std::string compress_map_bytes(const std::string& csm, int level) { return zstd_compress(csm, level); }

std::string map_bytes(const std::string& bytes, const std::string& name) {
  return is_zstd_frame(bytes) ? zstd_decompress(bytes, name) : bytes;
}

void save_map(const SemanticOcTree& map, const std::string& path) {
  const std::string csm = serialize_map(map);
  write_file_atomic(path, compressed_map_path(path) ? compress_map_bytes(csm) : csm);
}

SemanticOcTree load_map(const std::string& path) { return deserialize_map(map_bytes(read_file(path), path), path); }

std::size_t export_ply(const SemanticOcTree& map, const std::string& path) {
  std::string body;
  std::size_t count = 0;
  auto add = [&](const Vec3& c, const SemanticState& s) {
    const float xyz[3] = {float(c.x()), float(c.y()), float(c.z())};
    body.append(reinterpret_cast<const char*>(xyz), sizeof(xyz));
    const int cls = s.most_likely_class();
    const Rgb8 col = cls >= 0 ? map.classes().color(cls) : Rgb8{128, 128, 128};
    const std::uint8_t rgbc[4] = {col.r, col.g, col.b, static_cast<std::uint8_t>(cls >= 0 ? cls : 255)};
    body.append(reinterpret_cast<const char*>(rgbc), sizeof(rgbc));
    const float occ = float(s.occupancy());
    body.append(reinterpret_cast<const char*>(&occ), sizeof(occ));
    ++count;
  };
  map.for_each_voxel_if([](const SemanticState& s) { return s.occupancy_logodds() > 0.f; },
                         [&](const octomap::OcTreeKey& key, const SemanticState& s) { add(map.center_of(key), s); });
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment canopy semantic map, voxel centres, resolution "
         << map.getResolution() << " m\n";
  header << "comment classes:";
  for (int i = 0; i < map.classes().size(); ++i) header << ' ' << i << '=' << map.classes().names[static_cast<std::size_t>(i)];
  header << "\nelement vertex " << count
         << "\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n"
            "property uchar class\nproperty float occupancy\nend_header\n";
  write_file_atomic(path, header.str() + body);
  return count;
}

namespace {
// OctoMap's binary node encoding (OccupancyOcTreeBase::writeBinaryNode): two bits per child,
// 00 unknown, 01 occupied leaf, 10 free leaf, 11 inner; then the inner children, in order.
// Written here rather than through octomap::OcTree, whose writer prints to stderr.
void write_bt_node(std::string& out, const SemanticNode* node) {
  std::uint8_t bits[2] = {0, 0};
  for (unsigned i = 0; i < 8; ++i) {
    const SemanticNode* c = node->child(i);
    if (!c) continue;
    unsigned code;
    if (c->has_children()) code = 3;
    else code = c->state().occupancy_logodds() > 0.f ? 2 : 1;  // bit pair (b0, b1): 01 -> 2, 10 -> 1
    bits[i / 4] = static_cast<std::uint8_t>(bits[i / 4] | (code << (2 * (i % 4))));
  }
  out.push_back(static_cast<char>(bits[0]));
  out.push_back(static_cast<char>(bits[1]));
  for (unsigned i = 0; i < 8; ++i) {
    const SemanticNode* c = node->child(i);
    if (c && c->has_children()) write_bt_node(out, c);
  }
}
}  // namespace

void export_bt(const SemanticOcTree& map, const std::string& path) {
  std::ostringstream header;
  header.precision(17);
  header << "# Octomap OcTree binary file\n# written by canopy: occupancy of a semantic map "
            "(p_occ > 0.5 occupied)\n#\nid OcTree\nsize "
         << map.size() << "\nres " << map.getResolution() << "\ndata\n";
  std::string body;
  if (map.getRoot()) write_bt_node(body, map.getRoot());
  write_file_atomic(path, header.str() + body);
}

}  // namespace canopy::mapping
