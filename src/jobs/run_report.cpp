// report.html of a run folder (run_report.h).

#include "canopy/jobs/run_report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/common/frame.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/png_io.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/world_job.h"
#include "canopy/records/view_columns.h"

namespace canopy::jobs {

namespace {

// Debian's libjs-three: three.js itself and its orbit controls (non-module builds).
constexpr const char* kThreeJs = "/usr/share/javascript/three/three.min.js";
constexpr const char* kOrbitJs = "/usr/share/javascript/three/examples/js/controls/OrbitControls.js";

// Numbers rounded for the page: the shortest text of a rounded double is short.
double r4(double x) { return std::isfinite(x) ? std::round(x * 1e4) / 1e4 : 0.0; }
double r3(double x) { return std::isfinite(x) ? std::round(x * 1e3) / 1e3 : 0.0; }

nlohmann::json vec(const Vec3& v) { return {r4(v.x()), r4(v.y()), r4(v.z())}; }

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = unsigned(std::uint8_t(bytes[i])) << 16 | unsigned(std::uint8_t(bytes[i + 1])) << 8 |
                       unsigned(std::uint8_t(bytes[i + 2]));
    out += t[v >> 18 & 63];
    out += t[v >> 12 & 63];
    out += t[v >> 6 & 63];
    out += t[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = unsigned(std::uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= unsigned(std::uint8_t(bytes[i + 1])) << 8;
    out += t[v >> 18 & 63];
    out += t[v >> 12 & 63];
    out += i + 1 < bytes.size() ? t[v >> 6 & 63] : '=';
    out += '=';
  }
  return out;
}

void put_u16(std::string& s, unsigned v) {
  s += char(v & 0xff);
  s += char(v >> 8 & 0xff);
}
void put_u32(std::string& s, std::uint32_t v) {
  put_u16(s, v & 0xffff);
  put_u16(s, v >> 16);
}

// The classes with their drawing colours.
nlohmann::json classes_json(const SemanticClasses& classes) {
  nlohmann::json c = nlohmann::json::array();
  for (int i = 0; i < classes.size(); ++i) {
    const Rgb8 col = classes.color(i);
    c.push_back({{"name", classes.names[std::size_t(i)]}, {"color", {col.r, col.g, col.b}}});
  }
  return c;
}

// The world's target fruits (box and final coverage filled by the caller).
nlohmann::json fruits_json(const world::World& world) {
  nlohmann::json f = nlohmann::json::array();
  for (const world::FruitTruth& t : world.truth.fruits)
    if (t.target) f.push_back({{"id", t.instance_id}, {"plant", t.plant_index}, {"min", vec(t.bbox_min)}, {"max", vec(t.bbox_max)}});
  return f;
}

// Sets each fruit's final coverage from the metrics (same order: target fruits).
void set_fruit_coverage(nlohmann::json& fruits, const std::vector<evaluation::FruitMetrics>& m) {
  for (std::size_t i = 0; i < fruits.size() && i < m.size(); ++i) fruits[i]["cov"] = r3(m[i].coverage);
}

// The final metrics' fruit detection without its matches, and each match's errors on its fruit
// (`detection` as summary.json's final.detection and canopy map's metrics write it).
nlohmann::json detection_summary(const nlohmann::json& detection, nlohmann::json& fruits) {
  if (!detection.is_object()) return nlohmann::json();
  std::map<int, std::size_t> by_id;
  for (std::size_t i = 0; i < fruits.size(); ++i) by_id[fruits[i].value("id", -1)] = i;
  for (const nlohmann::json& m : detection.value("matches", nlohmann::json::array())) {
    const auto it = by_id.find(m.value("instance_id", -1));
    if (it == by_id.end()) continue;
    nlohmann::json& f = fruits[it->second];
    for (const char* key : {"centre_error_m", "voxel_volume_error", "ellipsoid_volume_error", "true_volume_m3"})
      if (m.contains(key) && m[key].is_number()) f[key] = std::round(m[key].get<double>() * 1e6) / 1e6;
  }
  nlohmann::json out = detection;
  out.erase("matches");
  return out;
}

}  // namespace

nlohmann::json robot_shapes_json(const robot::RobotDescription& robot) {
  nlohmann::json out = nlohmann::json::object();
  for (const robot::Link& link : robot.links()) {
    nlohmann::json shapes = nlohmann::json::array();
    for (const robot::Shape& s : link.visuals.empty() ? link.collisions : link.visuals) {
      nlohmann::json j;
      switch (s.type) {
        case robot::ShapeType::kBox: j = {{"type", "box"}, {"size", vec(s.box_size)}}; break;
        case robot::ShapeType::kSphere: j = {{"type", "sphere"}, {"radius", r4(s.radius)}}; break;
        case robot::ShapeType::kCylinder: j = {{"type", "cylinder"}, {"radius", r4(s.radius)}, {"length", r4(s.length)}}; break;
        case robot::ShapeType::kCapsule: j = {{"type", "capsule"}, {"radius", r4(s.radius)}, {"length", r4(s.length)}}; break;
        case robot::ShapeType::kMesh: continue;
      }
      const Quat q(s.T_link_shape.linear());
      const Vec3& t = s.T_link_shape.translation();
      j["pose"] = {r4(t.x()), r4(t.y()), r4(t.z()), r4(q.w()), r4(q.x()), r4(q.y()), r4(q.z())};
      j["rgba"] = {r3(s.rgba[0]), r3(s.rgba[1]), r3(s.rgba[2]), r3(s.rgba[3])};
      shapes.push_back(j);
    }
    if (!shapes.empty()) out[link.name] = shapes;
  }
  return out;
}

nlohmann::json changed_settings(const settings::Settings& settings) {
  std::map<std::string, std::string> defaults;
  for (const ParamDescription& d : settings::Settings::defaults(default_robot_config()).describe()) defaults[d.key] = d.value;
  nlohmann::json out = nlohmann::json::array();
  for (const ParamDescription& d : settings.describe()) {
    const auto it = defaults.find(d.key);
    if (it == defaults.end() || it->second != d.value)
      out.push_back({{"key", d.key}, {"value", d.value}, {"default", it == defaults.end() ? "" : it->second}});
  }
  return out;
}

RunReport mission_report_data(const records::MissionResult& r, const settings::Settings& settings,
                              const world::World& world, const nlohmann::json& summary) {
  RunReport rep;
  nlohmann::json& d = rep.data;
  d["kind"] = "mission";
  d["vocabulary"] = records::vocabulary_json();
  d["resolution_m"] = settings.mapping.map.resolution_m;
  d["complete"] = r.complete;
  d["end_reason"] = r.end_reason;
  d["classes"] = classes_json(world.spec.classes);
  d["target"] = world.spec.classes.target;
  d["views"] = records::views_json(r.views, settings.method.name);
  d["stops"] = summary.value("stops", nlohmann::json::array());
  d["fruits"] = fruits_json(world);
  set_fruit_coverage(d["fruits"], r.final_metrics.fruits);
  const nlohmann::json& fin = summary.value("final", nlohmann::json::object());
  d["summary"] = {{"method", summary.value("method", nlohmann::json::object())},
                  {"seed", summary.value("seed", 0)},
                  {"p_gt", summary.value("p_gt", 0.0)},
                  {"labels", summary.value("labels", "")},
                  {"world", {{"file", summary.contains("world") ? summary["world"].value("file", "") : ""},
                             {"name", world.spec.name}, {"plants", world.plants.size()},
                             {"fruits", world.truth.fruits.size()}}},
                  {"settings_changed", changed_settings(settings)},
                  {"final", {{"fruit_coverage", r4(r.final_metrics.coverage)},
                             {"fruit_entropy", r4(r.final_metrics.total_entropy)},
                             {"fruits_sc50", fin.value("fruits_sc50", nlohmann::json())},
                             {"fruits_sc80", fin.value("fruits_sc80", nlohmann::json())},
                             {"fruit_voxel_precision", fin.value("fruit_voxel_precision", nlohmann::json())},
                             {"detection", detection_summary(fin.value("detection", nlohmann::json()), d["fruits"])}}},
                  {"views_attempted", summary.value("views_attempted", nlohmann::json())},
                  {"views_successful", summary.value("views_successful", nlohmann::json())},
                  {"failures", summary.value("failures", nlohmann::json::object())},
                  {"simulated_time_s", r3(r.sim_time_s)}};
  rep.wall = {{"wall_time_s", r3(r.wall_time_s)}};
  for (const auto& [phase, s] : r.times.totals()) rep.wall["phases_s"][phase] = r3(s);
  return rep;
}

RunReport map_report_data(const nlohmann::json& metrics, const std::vector<Pose>& poses,
                          const settings::Settings& settings, const world::World& world) {
  RunReport rep;
  nlohmann::json& d = rep.data;
  d["kind"] = "map";
  d["vocabulary"] = records::vocabulary_json();
  d["resolution_m"] = settings.mapping.map.resolution_m;
  d["complete"] = metrics.value("complete", false);
  d["end_reason"] = d["complete"].get<bool>() ? "all views mapped" : "interrupted";
  d["classes"] = classes_json(world.spec.classes);
  d["target"] = world.spec.classes.target;
  // Each mapped view as a record of the views' schema: a free-camera view, reached where it was
  // asked, with the map's figures of its history entry.
  const nlohmann::json history = metrics.value("history", nlohmann::json::array());
  std::vector<records::ViewRecord> views;
  for (std::size_t i = 0; i < history.size() && i < poses.size(); ++i) {
    records::ViewRecord v;
    v.attempt = static_cast<int>(i);
    v.phase = records::ViewPhase::kMapView;
    v.source = "free camera";
    v.success = true;
    v.T_goal = v.T_reached = poses[i];
    v.target = poses[i].translation();
    v.successful_views = static_cast<int>(i) + 1;
    records::read_map_history(history[i], &v);
    views.push_back(v);
  }
  d["views"] = records::views_json(views, "map");
  d["stops"] = nlohmann::json::array();
  d["fruits"] = fruits_json(world);
  if (metrics.contains("fruits"))
    for (std::size_t i = 0; i < d["fruits"].size() && i < metrics["fruits"].size(); ++i)
      d["fruits"][i]["cov"] = r3(metrics["fruits"][i].value("coverage", 0.0));
  d["summary"] = {{"method", {{"name", "map (free camera)"}}},
                  {"p_gt", metrics.value("p_gt", 0.0)},
                  {"labels", metrics.value("labels", "")},
                  {"world", {{"name", world.spec.name}, {"plants", world.plants.size()}, {"fruits", world.truth.fruits.size()}}},
                  {"settings_changed", changed_settings(settings)},
                  {"final", {{"fruit_coverage", r4(metrics.value("coverage", 0.0))},
                             {"fruit_entropy", r4(metrics.value("total_entropy", 0.0))},
                             {"fruits_sc50", metrics.value("fruits_sc50", nlohmann::json())},
                             {"fruits_sc80", metrics.value("fruits_sc80", nlohmann::json())},
                             {"fruit_voxel_precision", metrics.value("fruit_voxel_precision", nlohmann::json())},
                             {"detection", detection_summary(metrics.value("detection", nlohmann::json()), d["fruits"])}}},
                  {"views_attempted", views.size()},
                  {"views_successful", views.size()},
                  {"failures", nlohmann::json::object()}};
  rep.wall = {{"ms_per_insertion", r3(metrics.value("ms_per_insertion", 0.0))}};
  return rep;
}

nlohmann::json pack_replay(const records::MapReplay& replay, const mapping::SemanticMapParams& map,
                           const ReportBounds& bounds) {
  const auto& scans = replay.scans();
  const std::size_t n_voxels = replay.voxels().size();
  // Too many voxels: every m-th, in the order they were first drawn (spread over the map).
  const std::size_t vstep = n_voxels > bounds.max_voxels ? (n_voxels + bounds.max_voxels - 1) / bounds.max_voxels : 1;
  std::size_t total = 0, of_drawn = 0;  // changes recorded, and those of the voxels drawn
  for (const auto& s : scans) {
    total += s.size();
    for (const records::VoxelChange& c : s) of_drawn += c.voxel % vstep == 0;
  }
  // Too many changes: a state every `step` views, each the net change over its views.
  std::size_t step = 1;
  if (of_drawn > bounds.max_changes) step = (of_drawn + bounds.max_changes - 1) / bounds.max_changes;
  std::vector<std::vector<records::VoxelChange>> groups;
  std::vector<std::uint16_t> state(n_voxels, 0), before = state;
  for (std::size_t i = 0; i < scans.size(); i += step) {
    const std::size_t end = std::min(scans.size(), i + step);
    std::vector<std::uint32_t> touched;
    for (std::size_t j = i; j < end; ++j)
      for (const records::VoxelChange& c : scans[j]) {
        if (c.voxel % vstep) continue;
        state[c.voxel] = c.state;
        touched.push_back(c.voxel);
      }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    std::vector<records::VoxelChange> g;
    for (std::uint32_t v : touched)
      if (state[v] != before[v]) {
        g.push_back({static_cast<std::uint32_t>(v / vstep), state[v]});
        before[v] = state[v];
      }
    groups.push_back(std::move(g));
  }
  std::string keys, changes;
  std::size_t drawn = 0;
  for (std::size_t v = 0; v < n_voxels; v += vstep, ++drawn) {
    const octomap::OcTreeKey& k = replay.voxels()[v];
    put_u16(keys, k[0]);
    put_u16(keys, k[1]);
    put_u16(keys, k[2]);
  }
  nlohmann::json counts = nlohmann::json::array();
  std::size_t kept = 0;
  for (const auto& g : groups) {
    counts.push_back(g.size());
    kept += g.size();
    for (const records::VoxelChange& c : g) {
      put_u32(changes, c.voxel);
      put_u16(changes, c.state);
    }
  }
  nlohmann::json fruit_cov = nlohmann::json::array();
  for (std::size_t i = 0; i < replay.fruit_coverage().size(); i += step) {
    const std::size_t last = std::min(replay.fruit_coverage().size(), i + step) - 1;
    nlohmann::json row = nlohmann::json::array();
    for (double c : replay.fruit_coverage()[last]) row.push_back(r3(c));
    fruit_cov.push_back(row);
  }
  nlohmann::json j = {{"resolution_m", map.resolution_m}, {"key_origin", 32768}, {"voxels", drawn},
                      {"voxels_recorded", n_voxels}, {"voxel_step", vstep}, {"scans", scans.size()}, {"step", step},
                      {"changes_recorded", total}, {"changes_kept", kept}, {"counts", counts},
                      {"keys_b64", base64(keys)}, {"changes_b64", base64(changes)}, {"fruit_coverage", fruit_cov}};
  std::string note;
  if (vstep > 1)
    note = "every " + std::to_string(vstep) + "th voxel drawn (" + std::to_string(n_voxels) + " recorded, at most " +
           std::to_string(bounds.max_voxels) + " drawn)";
  if (step > 1)
    note += std::string(note.empty() ? "" : "; ") + "map states every " + std::to_string(step) + " views (" +
            std::to_string(of_drawn) + " voxel changes, at most " + std::to_string(bounds.max_changes) + " kept)";
  if (!note.empty()) j["note"] = note;
  return j;
}

void set_fruit_views(nlohmann::json& fruits, const records::MapReplay& replay) {
  const auto& cov = replay.fruit_coverage();
  const auto& seen = replay.instances_seen();
  for (std::size_t i = 0; i < fruits.size(); ++i) {
    if (!seen.empty()) {
      const int id = fruits[i].value("id", kNoInstance);
      fruits[i]["views_seen"] = std::count_if(seen.begin(), seen.end(), [id](const std::vector<int>& ids) {
        return std::binary_search(ids.begin(), ids.end(), id);
      });
    }
    int raised = 0;
    double before = 0.0;
    for (const std::vector<double>& c : cov) {
      if (i >= c.size()) continue;
      if (c[i] > before + 1e-3) ++raised;
      before = c[i];
    }
    if (!cov.empty() && !cov.front().empty()) fruits[i]["views_raised"] = raised;
  }
}

bool report_libraries_present() {
  return std::filesystem::exists(kThreeJs) && std::filesystem::exists(kOrbitJs);
}

std::string report_scripts(const std::string& page_script, bool three_js) {
  std::string s;
  for (const std::string& path : {std::string(kThreeJs), std::string(kOrbitJs)}) {
    if (!three_js) break;
    if (!std::filesystem::exists(path))
      throw IoError("report.html needs three.js from Debian's libjs-three (" + path + " is missing; run tools/deps.sh)");
    s += "<script>" + read_file(path) + "</script>\n";
  }
  for (const std::string& script : {std::string("web/report_axes.js"), page_script})
    s += "<script>" + read_file(find_data_file(script)) + "</script>\n";
  return s;
}

std::string report_page(const std::string& title, const std::string& scripts, const nlohmann::json& data,
                        const nlohmann::json& wall, const std::string& css) {
  // Inside a script element "</script" ends it and "<!--" starts the HTML parser's
  // script-data-escaped state, in which a later "<script" swallows the rest of the page. JSON
  // has '<' only inside strings, where "\u003c" means the same character: no '<' reaches the page.
  auto escaped = [](const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
      if (c == '<') out += "\\u003c";
      else out += c;
    }
    return out;
  };
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>";
  for (char c : title) html += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  html += "</title>\n<style>" + css + "</style>\n</head><body>\n<div id=\"app\"><p id=\"loading\">Loading the report "
          "(it needs JavaScript and WebGL)...</p></div>\n";
  html += "<script id=\"canopy-data\" type=\"application/json\">" + escaped(data.dump()) + "</script>\n";
  html += "<script id=\"canopy-wall\" type=\"application/json\">" + escaped(wall.dump()) + "</script>\n";
  html += scripts;
  html += "</body></html>\n";
  return html;
}

std::vector<std::string> write_run_report(const std::string& dir, RunReport report, const records::MapReplay& replay,
                                          const ReportBounds& bounds) {
  const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
  const std::string scripts = report_scripts("web/report.js");
  const std::string css = read_file(find_data_file("web/report.css"));
  std::vector<std::string> files;
  // Thumbnails: sheets of thumbs_per_sheet (10 a row), every m-th view beyond max_thumbs.
  const auto& rgb = replay.rgb();
  const std::size_t step = rgb.size() > bounds.max_thumbs ? (rgb.size() + bounds.max_thumbs - 1) / bounds.max_thumbs : 1;
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < rgb.size(); i += step) kept.push_back(i);
  const int per_sheet = std::max(1, bounds.thumbs_per_sheet), cols = 10;
  nlohmann::json thumbs = {{"step", step}, {"per_sheet", per_sheet}, {"cols", cols}, {"rgb", nlohmann::json::array()},
                           {"labels", nlohmann::json::array()}, {"mapped", nlohmann::json::array()}};
  // The labels mapped (after noise) beside the true ones, when every frame has them.
  const bool mapped = !replay.mapped_labels().empty() && replay.mapped_labels().size() == rgb.size();
  struct Kind {
    const std::vector<Image<Rgb8>>* images;
    const char* prefix;
    const char* key;
  };
  std::vector<Kind> kinds = {{&rgb, "report_rgb_", "rgb"}, {&replay.labels(), "report_labels_", "labels"}};
  if (mapped) kinds.push_back({&replay.mapped_labels(), "report_mapped_", "mapped"});
  if (!kept.empty()) {
    const int w = rgb[0].width, h = rgb[0].height;
    thumbs["w"] = w;
    thumbs["h"] = h;
    for (std::size_t s = 0; s * std::size_t(per_sheet) < kept.size(); ++s) {
      const std::size_t first = s * std::size_t(per_sheet), n = std::min(kept.size() - first, std::size_t(per_sheet));
      const int rows = int((n + cols - 1) / cols);
      for (const Kind& kind : kinds) {
        const auto& src = *kind.images;
        Image<Rgb8> sheet(w * std::min<int>(cols, int(n)), h * rows);
        for (std::size_t t = 0; t < n; ++t) {
          const Image<Rgb8>& im = src[kept[first + t]];
          const int x0 = int(t % cols) * w, y0 = int(t / cols) * h;
          for (int y = 0; y < h && y < im.height; ++y)
            for (int x = 0; x < w && x < im.width; ++x) sheet.at(x0 + x, y0 + y) = im.at(x, y);
        }
        const std::string name = kind.prefix + std::to_string(s) + ".png";
        write_png(d + name, sheet);
        thumbs[kind.key].push_back(name);
        files.push_back(name);
      }
    }
  }
  report.data["thumbs"] = thumbs;
  // The robot at each successful view: link names, parents, per view x y z qw qx qy qz of each
  // link in the world, and each link's shapes.
  if (!replay.robot_links().empty() && replay.robot_poses().size() == rgb.size()) {
    nlohmann::json poses = nlohmann::json::array();
    for (const std::vector<Pose>& at : replay.robot_poses()) {
      nlohmann::json row = nlohmann::json::array();
      for (const Pose& T : at) {
        const Quat q(T.linear());
        for (double v : {T.translation().x(), T.translation().y(), T.translation().z(), q.w(), q.x(), q.y(), q.z()})
          row.push_back(r4(v));
      }
      poses.push_back(row);
    }
    report.data["robot"] = {{"links", replay.robot_links()}, {"parents", replay.robot_parents()}, {"poses", poses}};
    // Each recorded link's shapes, in the order of the links (none for a link without).
    if (report.robot_shapes.is_object()) {
      nlohmann::json shapes = nlohmann::json::array();
      for (const std::string& link : replay.robot_links())
        shapes.push_back(report.robot_shapes.contains(link) ? report.robot_shapes[link] : nlohmann::json::array());
      report.data["robot"]["shapes"] = shapes;
    }
  }
  if (report.data.contains("fruits")) set_fruit_views(report.data["fruits"], replay);
  mapping::SemanticMapParams map_params;
  map_params.resolution_m = report.data.value("resolution_m", map_params.resolution_m);
  report.data["map"] = pack_replay(replay, map_params, bounds);
  report.data["format"] = 1;
  const std::string title = "canopy " + report.data.value("kind", std::string("run")) + " report";
  write_file_atomic(d + "report.html", report_page(title, scripts, report.data, report.wall, css));
  files.push_back("report.html");
  return files;
}

}  // namespace canopy::jobs
