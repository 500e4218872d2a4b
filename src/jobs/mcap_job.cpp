#include "canopy/jobs/mcap_job.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/timer.h"
#include "canopy/common/value_text.h"
#include "canopy/jobs/mission_job.h"
#include "canopy/jobs/world_job.h"
#include "canopy/records/run_folder.h"
#include "canopy/ros2/message_schemas.h"
#include "canopy/ros2/messages.h"

namespace canopy::jobs {

namespace msg = ros2::msg;
namespace topics = recording_topics;

namespace {

// The root of the robot's tree in the simulator (sim::RobotLinks) and in every recording.
constexpr const char* kRecordingWorldFrame = "world";

// What rosbag2 records for a latched publisher (durability transient_local, depth 1): a player
// republishes it so, and a late subscriber (Foxglove's 3D panel, RViz) still gets it.
constexpr const char* kLatchedQos =
    "- history: 1\n  depth: 1\n  reliability: 1\n  durability: 1\n  deadline:\n    sec: 2147483647\n    nsec: "
    "4294967295\n  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n  liveliness: 1\n  "
    "liveliness_lease_duration:\n    sec: 2147483647\n    nsec: 4294967295\n  avoid_ros_namespace_conventions: "
    "false\n";
// The frustums drawn for the views (RViz's convention for camera markers: 0.1 m deep).
constexpr double kFrustumDepthM = 0.1;
constexpr double kFrustumLineM = 0.003, kNewestFrustumLineM = 0.008;

// A view's frustum colour: the library's, as the report and the bags draw it.
msg::ColorRGBA phase_colour(records::ViewPhase phase) {
  const Rgb8 c = records::view_colour(phase, true);
  return {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, 1.0f};
}

// A target fruit's colour by its coverage: red (unseen) through yellow to green (covered).
msg::ColorRGBA coverage_colour(double coverage) {
  const float c = static_cast<float>(std::clamp(coverage, 0.0, 1.0));
  return {c < 0.5f ? 1.0f : 2.0f * (1.0f - c), c < 0.5f ? 2.0f * c : 1.0f, 0.1f, 0.6f};
}

msg::Header header(std::uint64_t ns, const std::string& frame) {
  msg::Header h;
  h.stamp = msg::Time::from_ns(ns);
  h.frame_id = frame;
  return h;
}

msg::Transform transform_of(const Pose& T) {
  msg::Transform t;
  const Eigen::Quaterniond q(T.linear());
  t.translation = {T.translation().x(), T.translation().y(), T.translation().z()};
  t.rotation = {q.x(), q.y(), q.z(), q.w()};
  return t;
}

msg::Point point_of(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

template <class Pixel>
msg::Image image_of(std::uint64_t ns, const std::string& frame, const Image<Pixel>& im, const char* encoding,
                    std::size_t bytes_per_pixel) {
  msg::Image m;
  m.header = header(ns, frame);
  m.width = static_cast<std::uint32_t>(im.width);
  m.height = static_cast<std::uint32_t>(im.height);
  m.encoding = encoding;
  m.step = static_cast<std::uint32_t>(im.width * bytes_per_pixel);
  m.data.resize(m.step * m.height);
  static_assert(sizeof(Pixel) > 0);
  std::memcpy(m.data.data(), im.data.data(), m.data.size());
  return m;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read the robot's URDF");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::int64_t wall_clock_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

McapRecordOptions mcap_record_options(const std::string& path, const std::string& compression, const std::string& depth,
                                      const std::string& epoch, const std::string& option, const std::string& prefix) {
  McapRecordOptions o;
  o.path = path;
  o.option = option;
  const std::optional<ros2::Compression> c =
      compression == "none" ? std::optional<ros2::Compression>(ros2::Compression::kNone) : ros2::parse_compression(compression);
  if (!c) throw InputError(prefix + "compression: '" + compression + "' is not none, lz4 or zstd");
  o.compression = *c;
  if (depth == "32FC1") o.depth = DepthEncoding::k32FC1;
  else if (depth == "16UC1") o.depth = DepthEncoding::k16UC1;
  else throw InputError(prefix + "depth: '" + depth + "' is not 32FC1 (metres, NaN for no return) or 16UC1 (mm, 0)");
  if (epoch == "zero") {
    o.epoch_ns = 0;
  } else if (epoch != "run") {
    double s = 0.0;
    try {
      s = parse_numbers(epoch, 1, prefix + "epoch")[0];
    } catch (const InputError&) {
      throw InputError(prefix + "epoch: '" + epoch +
                       "' is not 'run' (the run's start in wall-clock time), 'zero' or seconds since 1970");
    }
    if (!(std::isfinite(s) && s >= 0.0 && s < 2147483647.0 - 1e6))
      throw InputError(prefix + "epoch: " + epoch + " s is not a time ROS 2 stamps hold (0 to 2^31 s since 1970, "
                       "less the run)");
    o.epoch_ns = static_cast<std::int64_t>(std::llround(s * 1e9));
  }
  if (!path.empty() && std::filesystem::path(path).extension() != ".mcap")
    throw InputError(option + ": " + path + ": an MCAP file's name ends in .mcap");
  return o;
}

struct MissionMcap::Impl {
  McapRecordOptions options;
  const world::World& world;
  const settings::Settings& settings;
  ros2::McapWriter out;
  std::uint16_t rgb = 0, depth = 0, labels = 0, labels_color = 0, camera_info = 0, cloud = 0, views = 0, fruits = 0,
                tf = 0, tf_static = 0, description = 0;
  std::int64_t epoch = 0;
  double next_state_s = 0.0;
  bool started = false;
  double cloud_s = 0.0;
  const records::MapReplay* replay = nullptr;
  std::vector<std::uint64_t> view_stamps;  ///< Each successful view's stamp.
  std::size_t fruits_written = 0;          ///< Views whose fruit markers are written.

  // The fruit markers of the views before the newest (the pipeline has settled their scans
  // before the newest began: the same messages in the same order on every run), or of all of
  // them at the end.
  void write_covered_fruits(bool all) {
    if (!replay) return;
    while (fruits_written + (all ? 0 : 1) < view_stamps.size()) {
      const std::optional<std::vector<double>> c = replay->fruit_coverage_after(fruits_written);
      if (!c && !all) return;
      write_fruits(view_stamps[fruits_written], c ? &*c : nullptr);
      ++fruits_written;
    }
  }
  struct DrawnView {
    records::ViewPhase phase;
    Pose T_world_camera;
    CameraIntrinsics intrinsics;
  };
  std::vector<DrawnView> drawn;

  Impl(const McapRecordOptions& o, const world::World& w, const settings::Settings& s)
      : options(o), world(w), settings(s), out(o.path, writer_options(o)) {
    rgb = out.add_channel<msg::Image>(topics::kRgb);
    depth = out.add_channel<msg::Image>(topics::kDepth);
    labels = out.add_channel<msg::Image>(topics::kLabels);
    labels_color = out.add_channel<msg::Image>(topics::kLabelsColor);
    camera_info = out.add_channel<msg::CameraInfo>(topics::kCameraInfo);
    cloud = out.add_channel<msg::PointCloud2>(topics::kMap);
    views = out.add_channel<msg::MarkerArray>(topics::kViews);
    fruits = out.add_channel<msg::MarkerArray>(topics::kFruits);
    tf = out.add_channel<msg::TFMessage>(topics::kTf);
    const auto latched = [this](const std::string& topic, const char* type) {
      const std::uint16_t schema = out.add_schema(type, ros2::kRos2MsgSchemaEncoding, ros2::ros2msg_schema(type));
      return out.add_channel(schema, topic, ros2::kCdrMessageEncoding, {{"offered_qos_profiles", kLatchedQos}});
    };
    tf_static = latched(topics::kTfStatic, msg::TFMessage::kTypeName);
    description = latched(topics::kRobotDescription, msg::String::kTypeName);
  }

  static ros2::McapWriterOptions writer_options(const McapRecordOptions& o) {
    ros2::McapWriterOptions w;
    w.compression = o.compression;
    return w;
  }

  std::uint64_t stamp(double sim_time_s) const {
    return static_cast<std::uint64_t>(epoch + std::llround(sim_time_s * 1e9));
  }

  // The edges of the robot's links whose fixedness is `fixed`, from the world poses now.
  msg::TFMessage edges(const sim::Simulator& sim, bool fixed, std::uint64_t ns) const {
    const sim::RobotLinks now = sim.robot_links();
    std::map<std::string, const Pose*> world_pose;
    for (std::size_t i = 0; i < now.links.size(); ++i) world_pose[now.links[i]] = &now.poses[i];
    msg::TFMessage m;
    for (std::size_t i = 0; i < now.links.size(); ++i) {
      if (now.fixed[i] != fixed) continue;
      const auto parent = world_pose.find(now.parents[i]);
      const Pose T_parent_child = parent == world_pose.end() ? now.poses[i] : Pose(parent->second->inverse() * now.poses[i]);
      msg::TransformStamped t;
      t.header = header(ns, now.parents[i]);
      t.child_frame_id = now.links[i];
      t.transform = transform_of(T_parent_child);
      m.transforms.push_back(std::move(t));
    }
    return m;
  }

  void write_tf(const sim::Simulator& sim) {
    const std::uint64_t ns = stamp(sim.time());
    out.write(tf, ns, edges(sim, false, ns));
  }

  void write_fruits(std::uint64_t ns, const std::vector<double>* coverage) {
    msg::MarkerArray a;
    std::size_t target = 0;
    for (const world::FruitTruth& f : world.truth.fruits) {
      msg::Marker m;
      m.header = header(ns, kRecordingWorldFrame);
      m.ns = f.target ? "target fruits" : "other fruits";
      m.id = f.instance_id;
      m.type = msg::Marker::kCube;
      m.action = msg::Marker::kAdd;
      const Vec3 c = 0.5 * (f.bbox_min + f.bbox_max), size = (f.bbox_max - f.bbox_min).cwiseMax(1e-3);
      m.pose.position = point_of(c);
      m.scale = {size.x(), size.y(), size.z()};
      if (f.target) {
        const double cov = coverage && target < coverage->size() ? (*coverage)[target] : 0.0;
        m.color = coverage_colour(cov);
        m.text = format_number(cov, "%.3f");
        ++target;
      } else {
        m.color = {0.6f, 0.6f, 0.6f, 0.3f};
      }
      a.markers.push_back(std::move(m));
    }
    out.write(fruits, ns, a);
  }

  msg::PointCloud2 map_cloud(std::uint64_t ns, const mapping::SemanticOcTree& map) const {
    msg::PointCloud2 c;
    c.header = header(ns, kRecordingWorldFrame);
    c.height = 1;
    using PF = msg::PointField;
    c.fields = {{"x", 0, PF::kFloat32, 1},  {"y", 4, PF::kFloat32, 1},
                {"z", 8, PF::kFloat32, 1},  {"rgb", 12, PF::kFloat32, 1},  // packed 0x00RRGGBB, as RViz reads it
                {"probability", 16, PF::kFloat32, 1}, {"class", 20, PF::kUint8, 1}};
    c.point_step = 24;
    c.is_dense = true;
    map.for_each_voxel_if([](const mapping::SemanticState& s) { return s.occupancy_logodds() > 0.f; },
                          [&](const octomap::OcTreeKey& key, const mapping::SemanticState& s) {
                            const Vec3 p = map.center_of(key);
                            const int cls = s.most_likely_class();
                            const Rgb8 col = cls >= 0 ? map.classes().color(cls) : Rgb8{128, 128, 128};
                            const float xyz[3] = {float(p.x()), float(p.y()), float(p.z())};
                            const std::uint32_t packed = (std::uint32_t(col.r) << 16) | (std::uint32_t(col.g) << 8) | col.b;
                            const float prob = float(s.occupancy());
                            std::uint8_t point[24] = {};
                            std::memcpy(point, xyz, 12);
                            std::memcpy(point + 12, &packed, 4);
                            std::memcpy(point + 16, &prob, 4);
                            point[20] = static_cast<std::uint8_t>(cls >= 0 ? cls : 255);
                            c.data.insert(c.data.end(), point, point + 24);
                          });
    c.width = static_cast<std::uint32_t>(c.data.size() / c.point_step);
    c.row_step = static_cast<std::uint32_t>(c.data.size());
    return c;
  }

  msg::MarkerArray frustums(std::uint64_t ns) const {
    msg::MarkerArray a;
    for (std::size_t i = 0; i < drawn.size(); ++i) {
      const DrawnView& v = drawn[i];
      msg::Marker m;
      m.header = header(ns, kRecordingWorldFrame);
      m.ns = records::to_string(v.phase);
      m.id = static_cast<std::int32_t>(i);
      m.type = msg::Marker::kLineList;
      m.action = msg::Marker::kAdd;
      m.scale.x = i + 1 < drawn.size() ? kFrustumLineM : kNewestFrustumLineM;  // the newest drawn thicker
      m.color = phase_colour(v.phase);
      const CameraIntrinsics& K = v.intrinsics;
      const Vec3 apex = v.T_world_camera.translation();
      Vec3 corner[4];
      const double uv[4][2] = {{0, 0}, {double(K.width_px), 0}, {double(K.width_px), double(K.height_px)},
                               {0, double(K.height_px)}};
      for (int k = 0; k < 4; ++k) corner[k] = v.T_world_camera * K.unproject(uv[k][0], uv[k][1], kFrustumDepthM);
      for (int k = 0; k < 4; ++k) {
        m.points.push_back(point_of(apex));
        m.points.push_back(point_of(corner[k]));
        m.points.push_back(point_of(corner[k]));
        m.points.push_back(point_of(corner[(k + 1) % 4]));
      }
      a.markers.push_back(std::move(m));
    }
    return a;
  }
};

MissionMcap::MissionMcap(const McapRecordOptions& options, const world::World& world, const settings::Settings& settings)
    : impl_(std::make_unique<Impl>(options, world, settings)) {}

MissionMcap::~MissionMcap() = default;

std::int64_t MissionMcap::epoch_ns() const { return impl_->epoch; }

void MissionMcap::start(const sim::Simulator& sim, std::int64_t epoch_ns) {
  Impl& s = *impl_;
  CANOPY_CHECK(!s.started, "MissionMcap::start twice");
  s.started = true;
  s.epoch = epoch_ns;
  const std::uint64_t ns = s.stamp(sim.time());
  msg::String urdf;
  urdf.data = read_text(sim.robot_config().urdf_path);
  s.out.write(s.description, ns, urdf);
  s.out.write(s.tf_static, ns, s.edges(sim, true, ns));
  s.write_tf(sim);
  s.write_fruits(ns, nullptr);
  s.next_state_s = sim.time() + s.options.state_period_s;
}

void MissionMcap::state(const sim::Simulator& sim) {
  Impl& s = *impl_;
  if (!s.started) return start(sim, s.options.epoch_ns.value_or(wall_clock_now_ns()));
  if (sim.time() < s.next_state_s - 1e-9) return;
  s.write_tf(sim);
  while (s.next_state_s <= sim.time() + 1e-9) s.next_state_s += s.options.state_period_s;
}

void MissionMcap::view(const records::ViewRecord& view, const LabelledFrame& f, const sim::Simulator& sim,
                       const mapping::SemanticOcTree& map) {
  Impl& s = *impl_;
  if (!s.started) start(sim, s.options.epoch_ns.value_or(wall_clock_now_ns()));
  const std::uint64_t ns = s.stamp(sim.time());
  s.write_tf(sim);
  const std::string& camera = sim.robot_config().camera_frame;
  const CameraIntrinsics& K = f.intrinsics;
  msg::CameraInfo info;
  info.header = header(ns, camera);
  info.width = static_cast<std::uint32_t>(K.width_px);
  info.height = static_cast<std::uint32_t>(K.height_px);
  info.distortion_model = "plumb_bob";
  info.d = {0.0, 0.0, 0.0, 0.0, 0.0};
  const double cx = K.cx_px - 0.5, cy = K.cy_px - 0.5;  // ROS: pixel centres at integer coordinates
  info.k = {K.fx_px, 0.0, cx, 0.0, K.fy_px, cy, 0.0, 0.0, 1.0};
  info.r = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.p = {K.fx_px, 0.0, cx, 0.0, 0.0, K.fy_px, cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  s.out.write(s.camera_info, ns, info);
  s.out.write(s.rgb, ns, image_of(ns, camera, f.rgb, "rgb8", 3));
  if (s.options.depth == DepthEncoding::k32FC1) {
    Image<float> d = f.depth_m;
    for (float& z : d.data)
      if (!(z > 0.0f)) z = std::numeric_limits<float>::quiet_NaN();  // REP 118: no return
    s.out.write(s.depth, ns, image_of(ns, camera, d, "32FC1", 4));
  } else {
    Image<std::uint16_t> d(f.depth_m.width, f.depth_m.height);
    for (std::size_t i = 0; i < d.data.size(); ++i) {
      const float z = f.depth_m.data[i];
      d.data[i] = z > 0.0f ? static_cast<std::uint16_t>(std::min(65535.0f, std::round(z * 1000.0f))) : 0;
    }
    s.out.write(s.depth, ns, image_of(ns, camera, d, "16UC1", 2));
  }
  if (!f.class_id.data.empty()) {
    s.out.write(s.labels, ns, image_of(ns, camera, f.class_id, "mono8", 1));
    Image<Rgb8> colours(f.class_id.width, f.class_id.height);
    for (std::size_t i = 0; i < colours.data.size(); ++i) colours.data[i] = map.classes().color(f.class_id.data[i]);
    s.out.write(s.labels_color, ns, image_of(ns, camera, colours, "rgb8", 3));
  }
  const Stopwatch clouding;
  s.out.write(s.cloud, ns, s.map_cloud(ns, map));
  s.cloud_s += clouding.seconds();
  s.drawn.push_back({view.phase, f.T_world_camera, K});
  s.out.write(s.views, ns, s.frustums(ns));
  s.view_stamps.push_back(ns);
  s.write_covered_fruits(false);
}

void MissionMcap::follow_coverage(const records::MapReplay* replay) { impl_->replay = replay; }

ros2::McapWriteStats MissionMcap::close() {
  impl_->write_covered_fruits(true);
  spdlog::debug("{}: map clouds {:.2f} s", impl_->options.path, impl_->cloud_s);
  impl_->out.close();
  return impl_->out.stats();
}

}  // namespace canopy::jobs

namespace canopy::jobs {

ros2::McapWriteStats export_mcap(const ExportMcapParams& params) {
  namespace fs = std::filesystem;
  const std::string& run = params.run_dir;
  for (const char* name : {"summary.json", "settings.yaml", "views.csv"})
    if (!fs::is_regular_file(fs::path(run) / name))
      throw InputError(run + ": not a canopy mission run folder (no " + name + ")");
  const records::RunFolder folder = records::read_run_folder(run);
  const nlohmann::json& summary = folder.summary;
  const auto method = summary.find("method");
  if (method != summary.end() && method->is_object() && method->value("name", "") == "python")
    throw InputError(run + ": the run was planned by a Python planner, which its folder does not hold; record it "
                           "while it runs (canopy.run_mission's on_view, or canopy mission --mcap)");
  if (summary.value("complete", true) == false)
    throw InputError(run + ": the run was interrupted (summary.json \"complete\": false); only a whole run replays");
  const auto world_it = summary.find("world");
  if (world_it == summary.end() || !world_it->is_object() || !world_it->contains("spec") || !summary.contains("seed") ||
      !summary["seed"].is_number_unsigned())
    throw InputError(run + "/summary.json: lacks the world's resolved spec or the seed");
  McapRecordOptions mcap = params.mcap;
  if (!mcap.epoch_ns) {
    const auto started = summary.find("started_unix_ns");
    if (started == summary.end() || !started->is_number_integer())
      throw InputError(run + "/summary.json: has no started_unix_ns (a run of an older canopy): give the stamps' epoch "
                             "(--epoch SECONDS, or zero)");
    mcap.epoch_ns = started->get<std::int64_t>();
  }
  // The world as the run resolved it (a world file is JSON-readable YAML).
  const fs::path spec_file = fs::temp_directory_path() /
                             ("canopy-export-mcap-" + std::to_string(wall_clock_now_ns()) + "-world.json");
  {
    std::ofstream f(spec_file);
    f << (*world_it)["spec"].dump();
    if (!f) throw IoError("cannot write " + spec_file.string());
  }
  world::WorldSpec spec;
  try {
    spec = load_world_spec(spec_file.string());
  } catch (...) {
    fs::remove(spec_file);
    throw;
  }
  fs::remove(spec_file);
  const world::World world = build_world(spec);
  MissionJobParams job;
  job.settings = settings::Settings::load((fs::path(run) / "settings.yaml").string(), default_robot_config());
  job.seed = summary["seed"].get<std::uint64_t>();
  job.world_file = world_it->value("file", "");
  job.report = false;
  // Recorded through the job's hooks (no run folder): published only when the replay is the run.
  MissionMcap recorder(mcap, world, job.settings);
  records::MapReplay replay(world.spec.classes);  // the pipeline's per-view fruit coverage, for the markers
  recorder.follow_coverage(&replay);
  job.on_view = [&recorder](const records::ViewRecord& v, const LabelledFrame& f, const sim::Simulator& sim,
                            const mapping::SemanticOcTree& map) { recorder.view(v, f, sim, map); };
  mission::MissionCallbacks cb;
  cb.progress = params.progress;
  cb.stop_requested = params.stop_requested;
  cb.replay = &replay;
  cb.video_period_s = mcap.state_period_s;
  cb.video_tick = [&recorder](sim::Simulator& sim, const std::string&) { recorder.state(sim); };
  const MissionJobResult r = run_mission_job(world, job, cb);
  if (!r.result.complete) throw Interrupted("interrupted while replaying " + run + "; no MCAP written");
  const std::string replayed = records::views_csv(r.result, job.settings.method.name);
  if (replayed != folder.views_csv) {
    std::size_t line = 1;
    for (std::size_t i = 0; i < std::min(replayed.size(), folder.views_csv.size()) && replayed[i] == folder.views_csv[i]; ++i)
      line += replayed[i] == '\n';
    throw InputError(run + ": replaying the run gave other views than its views.csv (first difference on line " +
                     std::to_string(line) + "); was it made by another canopy? No MCAP written");
  }
  return recorder.close();
}

}  // namespace canopy::jobs
