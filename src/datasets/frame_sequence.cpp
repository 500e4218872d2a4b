#include "canopy/datasets/frame_sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/png_io.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/common/params.h"
#include "canopy/common/yaml_reader.h"

namespace fs = std::filesystem;

namespace canopy::datasets {

namespace {

constexpr double kQuaternionTolerance = 1e-3;
constexpr double kCanopyDepthScalePerM = 1000.0;  // depth.png of `canopy render`: millimetres

std::string format_color(const Rgb8& c) {
  return "(" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) + ")";
}

// Splits a line into whitespace-separated fields; '#' starts a comment.
std::vector<std::string> fields(const std::string& line) {
  std::istringstream ss(line.substr(0, line.find('#')));
  std::vector<std::string> out;
  for (std::string f; ss >> f;) out.push_back(f);
  return out;
}

double parse_field(const std::string& text, const std::string& where) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = c_stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(v)) throw InputError(where + ": '" + text + "' is not a finite number");
  return v;
}

// Calls f(line_number, fields) for every non-empty line of `path`.
template <typename F>
void for_each_line(const std::string& path, F&& f) {
  std::istringstream in(read_file(path));
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    const std::vector<std::string> v = fields(line);
    if (!v.empty()) f(n, v);
  }
}

Pose checked_pose(const Vec3& t, const Quat& q, const std::string& where) {
  if (std::abs(q.norm() - 1.0) > kQuaternionTolerance)
    throw InputError(where + ": quaternion has norm " + std::to_string(q.norm()) + ", must be unit length");
  return make_pose(t, q);
}

Image<float> depth_in_metres(const Image<std::uint16_t>& raw, double scale_per_m) {
  Image<float> depth(raw.width, raw.height, 0.f);
  for (std::size_t k = 0; k < raw.data.size(); ++k)
    depth.data[k] = raw.data[k] == 0 ? 0.f : static_cast<float>(double(raw.data[k]) / scale_per_m);
  return depth;
}

template <typename T>
void check_size(const Image<T>& image, const CameraIntrinsics& K, const std::string& file) {
  if (image.width != K.width_px || image.height != K.height_px)
    throw InputError(file + ": image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " but the camera is " + std::to_string(K.width_px) + "x" + std::to_string(K.height_px));
}

// A recorded camera has no default pinhole: the D405's would silently describe another camera.
void require_pinhole(YamlReader& y) {
  for (const char* key : {"width_px", "height_px", "fx_px", "fy_px", "cx_px", "cy_px"}) y.require<YAML::Node>(key);
}

// frame.json's intrinsics (put_frame_intrinsics' layout): the pinhole keys under "intrinsics",
// read through CameraIntrinsics::visit, and the depth range from "valid_range_m" [min, max].
// depth_noise_k is what the renderer added, not a property of the recorded frames.
CameraIntrinsics read_frame_intrinsics(const nlohmann::json& j, const std::string& json_path) {
  CameraIntrinsics K;
  YamlReader y(YAML::Load(j.at("intrinsics").dump()), json_path, "intrinsics");  // JSON is YAML
  require_pinhole(y);
  read_params(y, K);
  y.finish();
  K.min_range_m = j.at("valid_range_m").at(0).get<double>();
  K.max_range_m = j.at("valid_range_m").at(1).get<double>();
  validate_params(K, json_path);
  return K;
}

}  // namespace

void validate_recorded_intrinsics(const CameraIntrinsics& K, const std::string& where) { validate_params(K, where); }

const char* to_string(FrameLayout layout) { return layout == FrameLayout::kTum ? "tum" : "canopy"; }

RecordedCamera RecordedCamera::load(const std::string& path) {
  YamlReader y = YamlReader::load_file(path);
  require_pinhole(y);
  y.check(!y.has("depth_noise_k"), "depth_noise_k", "is the renderer's simulated noise, not a recorded camera's");
  RecordedCamera c;
  read_params(y, c);
  y.finish();
  return c;
}

ClassColorTable ClassColorTable::from_classes(const SemanticClasses& classes) {
  ClassColorTable t;
  t.classes = classes;
  for (int c = 0; c < classes.size(); ++c) t.colors.push_back(classes.color(c));
  return t;
}

ClassColorTable ClassColorTable::load(const std::string& path) {
  YamlReader y = YamlReader::load_file(path);
  ClassColorTable t;
  t.classes.names = y.require<std::vector<std::string>>("classes");
  t.classes.target = y.get("target", t.classes.target);
  t.classes.validate(path);
  YamlReader colors = y.child("colors");
  for (const std::string& name : t.classes.names) {
    const auto v = colors.require<std::vector<int>>(name);
    colors.check(v.size() == 3 && std::all_of(v.begin(), v.end(), [](int c) { return c >= 0 && c <= 255; }), name,
                 "must be [r, g, b] with values in 0..255");
    const Rgb8 c{std::uint8_t(v[0]), std::uint8_t(v[1]), std::uint8_t(v[2])};
    for (std::size_t k = 0; k < t.colors.size(); ++k)
      if (t.colors[k] == c) colors.fail(name, "repeats the colour of class '" + t.classes.names[k] + "'");
    t.colors.push_back(c);
  }
  colors.finish();
  y.finish();
  return t;
}

Image<std::uint8_t> ClassColorTable::decode(const Image<Rgb8>& image, const std::string& file) const {
  Image<std::uint8_t> out(image.width, image.height, 0);
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < image.width; ++i) {
      const Rgb8& p = image.at(i, j);
      const auto it = std::find(colors.begin(), colors.end(), p);
      if (it == colors.end())
        throw InputError(file + ": colour " + format_color(p) + " at pixel (" + std::to_string(i) + ", " +
                         std::to_string(j) + ") is not in the class-colour table");
      out.at(i, j) = static_cast<std::uint8_t>(it - colors.begin());
    }
  return out;
}

std::vector<TimedFile> read_tum_file_list(const std::string& path) {
  std::vector<TimedFile> out;
  for_each_line(path, [&](int n, const std::vector<std::string>& v) {
    const std::string where = path + ":" + std::to_string(n);
    if (v.size() != 2) throw InputError(where + ": expected 'timestamp file', found " + std::to_string(v.size()) + " fields");
    out.push_back({parse_field(v[0], where), v[1], n});
  });
  return out;
}

std::vector<TimedPose> read_tum_trajectory(const std::string& path) {
  std::vector<TimedPose> out;
  for_each_line(path, [&](int n, const std::vector<std::string>& v) {
    const std::string where = path + ":" + std::to_string(n);
    if (v.size() != 8)
      throw InputError(where + ": expected 'timestamp tx ty tz qx qy qz qw', found " + std::to_string(v.size()) +
                       " fields");
    double x[8];
    for (int k = 0; k < 8; ++k) x[k] = parse_field(v[static_cast<std::size_t>(k)], where);
    out.push_back({x[0], checked_pose(Vec3(x[1], x[2], x[3]), Quat(x[7], x[4], x[5], x[6]), where)});
  });
  std::stable_sort(out.begin(), out.end(), [](const TimedPose& a, const TimedPose& b) { return a.t_s < b.t_s; });
  return out;
}

std::vector<std::pair<std::size_t, std::size_t>> associate_timestamps(const std::vector<double>& a,
                                                                      const std::vector<double>& b,
                                                                      double max_diff_s) {
  // Candidate pairs within the tolerance (a window of the sorted b per a), closest first.
  std::vector<std::size_t> order(b.size());
  for (std::size_t j = 0; j < b.size(); ++j) order[j] = j;
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return b[x] < b[y] || (b[x] == b[y] && x < y); });
  std::vector<double> sorted_b(b.size());
  for (std::size_t j = 0; j < b.size(); ++j) sorted_b[j] = b[order[j]];
  struct Pair {
    double d;
    std::size_t i, j;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < a.size(); ++i) {
    auto it = std::lower_bound(sorted_b.begin(), sorted_b.end(), a[i] - max_diff_s);
    for (; it != sorted_b.end() && *it <= a[i] + max_diff_s; ++it)
      pairs.push_back({std::abs(*it - a[i]), i, order[static_cast<std::size_t>(it - sorted_b.begin())]});
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
    return x.d < y.d || (x.d == y.d && (x.i < y.i || (x.i == y.i && x.j < y.j)));
  });
  std::vector<char> used_a(a.size(), 0), used_b(b.size(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const Pair& p : pairs) {
    if (used_a[p.i] || used_b[p.j]) continue;
    used_a[p.i] = used_b[p.j] = 1;
    out.emplace_back(p.i, p.j);
  }
  std::sort(out.begin(), out.end());
  return out;
}

long nearest_timestamp(const std::vector<double>& sorted_t, double t, double max_diff_s) {
  const auto it = std::lower_bound(sorted_t.begin(), sorted_t.end(), t);
  long best = -1;
  double best_d = max_diff_s;
  auto consider = [&](std::vector<double>::const_iterator c) {
    const double d = std::abs(*c - t);
    if (d <= best_d && (best < 0 || d < best_d)) {
      best = static_cast<long>(c - sorted_t.begin());
      best_d = d;
    }
  };
  if (it != sorted_t.begin()) consider(it - 1);
  if (it != sorted_t.end()) consider(it);
  return best;
}

FrameSequence FrameSequence::open(const std::string& dir, const FrameReaderOptions& options) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir + ": no such folder (--frames)");
  if (!(options.max_time_diff_s > 0.0) || !std::isfinite(options.max_time_diff_s))
    throw InputError("time tolerance must be > 0 s, got " + std::to_string(options.max_time_diff_s));
  if (fs::exists(fs::path(dir) / "rgb.txt")) return open_tum(dir, options);
  std::vector<std::string> folders;
  if (fs::exists(fs::path(dir) / "frame.json")) {
    folders.push_back(dir);
  } else {
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_directory() && fs::exists(e.path() / "frame.json")) folders.push_back(e.path().string());
    std::sort(folders.begin(), folders.end());
  }
  if (folders.empty())
    throw InputError(dir + ": no frames: neither a TUM sequence (rgb.txt) nor canopy frame folders (frame.json)");
  return open_canopy(dir, folders, options);
}

FrameSequence FrameSequence::open_canopy(const std::string& dir, const std::vector<std::string>& folders,
                                         const FrameReaderOptions& options) {
  FrameSequence s;
  s.layout_ = FrameLayout::kCanopy;
  s.dir_ = dir;
  s.options_ = options;
  SemanticClasses classes;
  bool have_classes = false;
  for (const std::string& folder : folders) {
    const std::string json_path = (fs::path(folder) / "frame.json").string();
    Entry e;
    e.name = fs::path(folder).filename().string();
    std::vector<std::string> names;
    try {
      const nlohmann::json j = nlohmann::json::parse(read_file(json_path));
      e.intrinsics = read_frame_intrinsics(j, json_path);
      const auto& p = j.at("T_world_camera").at("position");
      const auto& q = j.at("T_world_camera").at("quaternion_wxyz");
      e.T_world_camera = checked_pose(
          Vec3(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()),
          Quat(q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>()),
          json_path + ": T_world_camera");
      names = j.at("classes").get<std::vector<std::string>>();
    } catch (const nlohmann::json::exception& ex) {
      throw InputError(json_path + ": " + ex.what());
    }
    if (!have_classes) {
      classes.names = names;
      classes.validate(json_path);
      have_classes = true;
    } else if (names != classes.names) {
      throw InputError(json_path + ": classes differ from the first frame's");
    }
    e.depth_scale_per_m = kCanopyDepthScalePerM;
    e.rgb = (fs::path(folder) / "rgb.png").string();
    e.depth = (fs::path(folder) / "depth.png").string();
    e.labels = (fs::path(folder) / "labels.png").string();
    s.frames_.push_back(e);
  }
  s.table_ = options.label_colors_file.empty() ? ClassColorTable::from_classes(classes)
                                               : ClassColorTable::load(options.label_colors_file);
  if (s.table_.classes.names != classes.names)
    throw InputError(options.label_colors_file + ": classes differ from the frames' (frame.json)");
  return s;
}

FrameSequence FrameSequence::open_tum(const std::string& dir, const FrameReaderOptions& options) {
  FrameSequence s;
  s.layout_ = FrameLayout::kTum;
  s.dir_ = dir;
  s.options_ = options;
  const fs::path root(dir);
  const RecordedCamera camera =
      RecordedCamera::load(options.intrinsics_file.empty() ? (root / "camera.yaml").string() : options.intrinsics_file);
  s.table_ = options.label_colors_file.empty() ? ClassColorTable::from_classes(SemanticClasses{})
                                               : ClassColorTable::load(options.label_colors_file);
  std::vector<TimedFile> rgb = read_tum_file_list((root / "rgb.txt").string());
  // Frames are mapped in time order; a list out of order is sorted, and said so.
  std::size_t out_of_order = 0;
  for (std::size_t i = 1; i < rgb.size(); ++i) out_of_order += rgb[i].t_s < rgb[i - 1].t_s;
  if (out_of_order > 0) {
    std::stable_sort(rgb.begin(), rgb.end(), [](const TimedFile& a, const TimedFile& b) { return a.t_s < b.t_s; });
    s.notes_.push_back("rgb.txt lists frames out of time order (" + std::to_string(out_of_order) +
                       " steps back in time); they are mapped in time order");
  }
  const std::vector<TimedFile> depth = read_tum_file_list((root / "depth.txt").string());
  const std::vector<TimedPose> poses = read_tum_trajectory((root / "groundtruth.txt").string());
  std::vector<double> t_rgb, t_depth, t_pose;
  for (const TimedFile& f : rgb) t_rgb.push_back(f.t_s);
  for (const TimedFile& f : depth) t_depth.push_back(f.t_s);
  for (const TimedPose& p : poses) t_pose.push_back(p.t_s);
  const auto pairs = associate_timestamps(t_rgb, t_depth, options.max_time_diff_s);
  std::vector<char> paired(rgb.size(), 0);
  for (const auto& [i, j] : pairs) paired[i] = 1;
  char tol[32];
  c_snprintf(tol, sizeof tol, "%g s", options.max_time_diff_s);
  std::size_t next_pair = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const std::string name = fs::path(rgb[i].file).filename().string();
    if (!paired[i]) {
      s.skipped_.push_back({name, std::string("no depth image within ") + tol});
      continue;
    }
    const std::size_t j = pairs[next_pair++].second;
    const long k = nearest_timestamp(t_pose, depth[j].t_s, options.max_time_diff_s);
    if (k < 0) {
      s.skipped_.push_back({name, std::string("no ground-truth pose within ") + tol});
      continue;
    }
    Entry e;
    e.name = name;
    e.rgb = (root / rgb[i].file).string();
    e.depth = (root / depth[j].file).string();
    e.labels = (root / "labels" / name).string();
    e.intrinsics = camera.intrinsics;
    e.depth_scale_per_m = camera.depth_scale_per_m;
    e.T_world_camera = poses[static_cast<std::size_t>(k)].T_world_camera;
    s.frames_.push_back(e);
  }
  if (rgb.empty()) throw InputError((root / "rgb.txt").string() + ": lists no images");
  return s;
}

bool FrameSequence::read(std::size_t i, LabelledFrame* frame, std::string* why) const {
  const Entry& e = frames_.at(i);
  LabelledFrame f;
  f.intrinsics = e.intrinsics;
  f.T_world_camera = e.T_world_camera;
  const Image<std::uint16_t> raw = read_png_gray16(e.depth);
  check_size(raw, e.intrinsics, e.depth);
  f.depth_m = depth_in_metres(raw, e.depth_scale_per_m);
  f.rgb = read_png_rgb(e.rgb);
  check_size(f.rgb, e.intrinsics, e.rgb);
  if (options_.label_images) {
    const Image<Rgb8> labels = read_png_rgb(e.labels);
    check_size(labels, e.intrinsics, e.labels);
    f.class_id = table_.decode(labels, e.labels);
  }
  const auto in_range = [&](float z) { return z >= e.intrinsics.min_range_m && z <= e.intrinsics.max_range_m; };
  if (std::none_of(f.depth_m.data.begin(), f.depth_m.data.end(), in_range)) {
    if (why) *why = "no depth pixel within the valid range";
    return false;
  }
  *frame = std::move(f);
  return true;
}

std::map<std::string, int> count_reasons(const std::vector<SkippedFrame>& skipped) {
  std::map<std::string, int> out;
  for (const SkippedFrame& s : skipped) ++out[s.reason];
  return out;
}

}  // namespace canopy::datasets
