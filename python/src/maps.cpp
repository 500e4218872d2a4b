// canopy.Map: the semantic octree with its frame step, files, bulk voxel queries and metrics.

#include <pybind11/stl.h>

#include "canopy/common/error.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/jobs/map_job.h"
#include "canopy/mapping/map_io.h"
#include "objects.h"

namespace canopy::python {

PyMap::PyMap(const settings::MappingSettings& settings, const SemanticClasses& classes)
    : owned_(std::make_unique<mapping::SemanticOcTree>(settings.map, classes)), settings_(settings) {}

PyMap::PyMap(mapping::SemanticOcTree map, const settings::MappingSettings& settings)
    : owned_(std::make_unique<mapping::SemanticOcTree>(std::move(map))), settings_(settings) {
  settings_.map = owned_->params();
}

std::shared_ptr<PyMap> PyMap::borrow(const mapping::SemanticOcTree& map, std::shared_ptr<const bool> alive,
                                     const settings::MappingSettings& settings) {
  std::shared_ptr<PyMap> m(new PyMap());
  m->borrowed_ = &map;
  m->alive_ = std::move(alive);
  m->settings_ = settings;
  return m;
}

const mapping::SemanticOcTree& PyMap::get() const {
  if (owned_) return *owned_;
  if (!alive_ || !*alive_)
    throw InputError("map: this is the map a planner was lent for one call; it ends with the call (copy what you need)");
  return *borrowed_;
}

mapping::SemanticOcTree& PyMap::owned() {
  if (!owned_) throw InputError("map: the map a planner is lent is read-only");
  return *owned_;
}

bool PyMap::identical(const PyMap& a, const PyMap& b) {
  if (&a == &b) return true;
  std::scoped_lock lock(a.mutex_, b.mutex_);
  return a.get().identical(b.get());
}

void PyMap::make_inserter() {
  mapping::SemanticOcTree& map = owned();
  if (inserter_) return;
  inserter_ = std::make_unique<mapping::ScanInserter>(map);
  extractor_ = std::make_unique<perception::SemanticExtractor>(settings_.extractor, map.classes());
}

mapping::FrameMapStep PyMap::insert(const LabelledFrame& frame) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  make_inserter();
  return mapping::map_frame(frame, *extractor_, *inserter_);
}

mapping::InsertStats PyMap::insert_cloud(const perception::LabelledCloud& cloud) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  make_inserter();
  return inserter_->insert(cloud);
}

namespace {

using mapping::SemanticOcTree;
using mapping::SemanticState;

SemanticClasses classes_from(const py::object& classes, const py::object& target) {
  SemanticClasses c;
  if (py::isinstance<PyWorld>(classes)) {
    c = classes.cast<const PyWorld&>().world().spec.classes;
  } else if (!classes.is_none()) {
    try {
      c.names = classes.cast<std::vector<std::string>>();
    } catch (const py::cast_error&) {
      throw InputError("classes: " + describe(classes) + " is not a canopy.World or a list of class names");
    }
  }
  if (!target.is_none()) c.target = py::str(target);
  c.validate("classes");
  return c;
}

// A frame's insertion counts under the keys `canopy map` writes into metrics.json.
py::object insert_dict(const mapping::InsertStats& s, const perception::ExtractStats& e) {
  return json_to_py(jobs::insert_stats_json(s, e));
}

// A per-point query over an (N, 3) array: f(map, point) -> value.
template <typename T, typename F>
py::array_t<T> per_point(const PyMap& m, const py::object& points, F&& f) {
  const std::vector<Vec3> p = points_from(points, "points");
  std::vector<T> out(p.size());
  m.read([&](const SemanticOcTree& map) {
    for (std::size_t i = 0; i < p.size(); ++i) out[i] = f(map, p[i]);
    return 0;
  });
  return array_of(out);
}

// Known finest-level voxels passing `keep`, inside `region` when given.
py::dict voxels_dict(const SemanticOcTree& map, const std::function<bool(const SemanticState&)>& keep,
                     const Eigen::AlignedBox3d* region) {
  std::vector<Vec3> centers;
  std::vector<float> p_occ, entropy;
  std::vector<std::int8_t> cls;
  std::vector<double> probs;
  const int k = map.num_classes();
  std::vector<double> d(static_cast<std::size_t>(k) + 1);
  map.for_each_voxel_if(keep, [&](const octomap::OcTreeKey& key, const SemanticState& s) {
    const Vec3 c = map.center_of(key);
    if (region && !region->contains(c)) return;
    centers.push_back(c);
    p_occ.push_back(static_cast<float>(s.occupancy()));
    entropy.push_back(static_cast<float>(map.entropy_of(s)));
    cls.push_back(static_cast<std::int8_t>(s.most_likely_class()));
    s.distribution(k, d.data());
    probs.insert(probs.end(), d.begin(), d.end());
  });
  py::array_t<double> prob_array({static_cast<py::ssize_t>(centers.size()), static_cast<py::ssize_t>(k + 1)});
  std::copy(probs.begin(), probs.end(), prob_array.mutable_data());
  return py::dict(py::arg("center") = points_array(centers), py::arg("p_occ") = array_of(p_occ),
                  py::arg("most_likely_class") = array_of(cls), py::arg("entropy") = array_of(entropy),
                  py::arg("probabilities") = prob_array);
}

using MapClass = py::class_<PyMap, std::shared_ptr<PyMap>>;

// Map.insert: the frame step with the map's extractor.
py::object insert_frame(PyMap& self, const PyFrame& frame) {
  const bool truth = self.settings().extractor.source == perception::LabelSource::kTruth;
  if (truth && frame.frame.class_id.empty())
    throw InputError("frame: has no labels, and the map's mapping.extractor.source is truth");
  if (!truth && frame.frame.rgb.empty())
    throw InputError("frame: has no rgb image, and the map's mapping.extractor.source is color");
  mapping::FrameMapStep step;
  {
    py::gil_scoped_release release;
    step = self.insert(frame.frame);
  }
  return insert_dict(step.insert, step.extract);
}

// Map.insert_cloud: labelled points, no extractor.
py::object insert_cloud(PyMap& self, const py::object& points, const py::object& labels, const py::object& origin) {
  perception::LabelledCloud cloud;
  cloud.origin_world = vec3_from(origin, "origin");
  for (const Vec3& p : points_from(points, "points")) cloud.points_world.push_back(p.cast<float>());
  const auto l = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(labels);
  if (!l || l.ndim() != 1 || static_cast<std::size_t>(l.shape(0)) != cloud.points_world.size())
    throw InputError("labels: " + describe(labels) + " is not one class index per point");
  for (py::ssize_t i = 0; i < l.shape(0); ++i) {
    const std::int64_t c = l.data()[i];
    cloud.labels.push_back(c >= 0 && c < 255 ? static_cast<std::uint8_t>(c) : std::uint8_t{255});
  }
  cloud.stats.points = cloud.points_world.size();
  mapping::InsertStats s;
  {
    py::gil_scoped_release release;
    s = self.insert_cloud(cloud);
  }
  return insert_dict(s, cloud.stats);
}

// Map.class_probabilities: (N, K + 1) per point.
py::array_t<double> class_probabilities(const PyMap& self, const py::object& points) {
  const std::vector<Vec3> p = points_from(points, "points");
  return self.read([&](const SemanticOcTree& map) {
    const int k = map.num_classes();
    py::array_t<double> out({static_cast<py::ssize_t>(p.size()), static_cast<py::ssize_t>(k + 1)});
    const SemanticState fresh{};
    for (std::size_t i = 0; i < p.size(); ++i) {
      const SemanticState* s = map.find(p[i]);
      (s ? *s : fresh).distribution(k, out.mutable_data() + i * static_cast<std::size_t>(k + 1));
    }
    return out;
  });
}

// Map.voxels: known voxels of a kind, in a region.
py::dict voxels(const PyMap& self, const std::string& which, const py::object& region) {
  std::function<bool(const SemanticState&)> keep;
  if (which == "occupied") keep = [](const SemanticState& s) { return s.occupancy_logodds() > 0.f; };
  else if (which == "free") keep = [](const SemanticState& s) { return !(s.occupancy_logodds() > 0.f); };
  else if (which == "all") keep = [](const SemanticState&) { return true; };
  else throw InputError("which: '" + which + "' is not one of occupied, free, all");
  Eigen::AlignedBox3d box;
  if (!region.is_none()) box = box_from(region, "region");
  return self.read([&](const SemanticOcTree& map) { return voxels_dict(map, keep, region.is_none() ? nullptr : &box); });
}

// Map.metrics: coverage and entropy against a world's truth.
py::object metrics(const PyMap& self, const PyWorld& world) {
  nlohmann::json j;
  {
    py::gil_scoped_release release;
    j = self.read([&](const SemanticOcTree& map) {
      return evaluation::evaluate_map(map, world.world().truth, self.settings().metrics).to_json();
    });
  }
  return json_to_py(j);
}

// Making, inserting into, and reading and writing a map.
void bind_map_making(MapClass& c) {
  c.def(py::init([](const py::object& settings, const py::object& classes, const py::object& target) {
         return std::make_shared<PyMap>(settings_from(settings).mapping, classes_from(classes, target));
       }),
       py::arg("settings") = py::none(), py::arg("classes") = py::none(), py::arg("target") = py::none(),
       R"(An empty map.

settings: canopy.Settings or a bundle file (default: configs/canopy.yaml), whose mapping
section gives the map, extractor and metrics settings; classes: a canopy.World (its classes)
or a list of names starting with "background" (default: background, leaf, fruit); target:
the target class (default: fruit).)")
      .def_static("load", [](const py::object& path_arg, const py::object& settings) {
        const std::string path = path_from(path_arg, "path");
        mapping::SemanticOcTree map = [&] {
          py::gil_scoped_release release;
          return mapping::load_map(path);
        }();
        return std::make_shared<PyMap>(std::move(map), settings_from(settings).mapping);
      }, py::arg("path"), py::arg("settings") = py::none(),
      "Reads a .csm file (as `canopy map` writes); settings gives the extractor and metrics of later inserts.")
      .def_static("from_bytes", [](const py::bytes& data, const py::object& settings) {
        return std::make_shared<PyMap>(mapping::deserialize_map(std::string(data), "bytes"),
                                       settings_from(settings).mapping);
      }, py::arg("data"), py::arg("settings") = py::none(), "A map from .csm bytes.")
      .def("insert", &insert_frame, py::arg("frame"), R"(Labels a canopy.Frame (the settings' extractor) and inserts it: the frame
step every canopy command takes. Returns its counts under the keys of `canopy map`'s
metrics.json history ("insert"): points, skipped_bad_depth, skipped_out_of_range,
carved_missing_depth, skipped_bad_label, skipped_bad_point, masks, masks_flipped, hit_voxels,
free_voxels, saturated_updates, ms_insert, ms_filter, ms_raycast, ms_update.)")
      .def("insert_cloud", &insert_cloud, py::arg("points"), py::arg("labels"), py::arg("origin"),
      R"(Inserts labelled points (N, 3) [m, world] seen from origin (3,), no extractor: labels are
class indices (out-of-range ones are skipped and counted as skipped_bad_label); the counts of insert().)");
}

// Files and bytes.
void bind_map_files(MapClass& c) {
  c.def("save", [](const PyMap& self, const py::object& path_arg) {
        const std::string path = path_from(path_arg, "path");
        py::gil_scoped_release release;
        self.read([&](const mapping::SemanticOcTree& map) {
          mapping::save_map(map, path);
          return 0;
        });
      }, py::arg("path"), "Writes a .csm file atomically (the format `canopy map` and `canopy nbv` read).")
      .def("to_bytes", [](const PyMap& self) {
        const std::string bytes = self.read([](const mapping::SemanticOcTree& map) { return mapping::serialize_map(map); });
        return py::bytes(bytes);
      }, "The .csm bytes.")
      .def("export_ply", [](const PyMap& self, const py::object& path_arg) {
        const std::string path = path_from(path_arg, "path");
        py::gil_scoped_release release;
        return self.read([&](const mapping::SemanticOcTree& map) { return mapping::export_ply(map, path); });
      }, py::arg("path"), "Occupied voxels as a binary PLY (class colours); returns their count.")
      .def("export_bt", [](const PyMap& self, const py::object& path_arg) {
        const std::string path = path_from(path_arg, "path");
        py::gil_scoped_release release;
        self.read([&](const mapping::SemanticOcTree& map) {
          mapping::export_bt(map, path);
          return 0;
        });
      }, py::arg("path"), "The occupancy as an OctoMap .bt file.");
}

// Queries per point and over the voxels.
void bind_map_queries(MapClass& c) {
  c.def("occupancy", [](const PyMap& self, const py::object& points) {
        return per_point<double>(self, points, [](const SemanticOcTree& map, const Vec3& p) { return map.occupancy(p); });
      }, py::arg("points"), "p_occ of the voxels containing points (N, 3); 0.5 where unknown.")
      .def("known", [](const PyMap& self, const py::object& points) {
        return per_point<bool>(self, points, [](const SemanticOcTree& map, const Vec3& p) { return !map.is_unknown(p); });
      }, py::arg("points"), "True where the voxel containing a point was observed.")
      .def("entropy", [](const PyMap& self, const py::object& points) {
        return per_point<double>(self, points, [](const SemanticOcTree& map, const Vec3& p) { return map.entropy(p); });
      }, py::arg("points"), "Entropy [nats] of the voxels containing points (the unseen prior's where unknown).")
      .def("most_likely_class", [](const PyMap& self, const py::object& points) {
        return per_point<std::int8_t>(self, points, [](const SemanticOcTree& map, const Vec3& p) {
          const SemanticState* s = map.find(p);
          return static_cast<std::int8_t>(s ? s->most_likely_class() : -1);
        });
      }, py::arg("points"), "Most likely stored class per point; -1 where unknown or none is stored.")
      .def("class_probabilities", &class_probabilities, py::arg("points"), R"((N, K + 1) probabilities of {free, class 0 .. K-1} per point; an unknown
voxel is a fresh one (p_occ 0.5, the classes equally likely).)")
      .def("voxels", &voxels, py::arg("which") = "occupied", py::arg("region") = py::none(),
      R"(Known finest-level voxels (pruned blocks expanded) as a dict of arrays: center (N, 3),
p_occ, most_likely_class (-1: none stored), entropy [nats], probabilities (N, K + 1) of
{free, classes}. which: occupied (p_occ > 0.5), free or all; region: [[min], [max]] corners.)")
      .def("counts", [](const PyMap& self) {
        const mapping::VoxelCounts c = self.read([](const SemanticOcTree& map) { return map.counts(); });
        return py::dict(py::arg("leaves") = c.leaves, py::arg("voxels") = c.voxels, py::arg("occupied") = c.occupied,
                        py::arg("free") = c.free, py::arg("target") = c.target, py::arg("nodes") = c.nodes,
                        py::arg("memory_bytes") = c.memory_bytes);
      }, "Leaf and voxel counts (target: occupied voxels whose most likely class is the target).")
      .def("metrics", &metrics, py::arg("world"), R"(Coverage and entropy of the target fruits against world's ground truth (the
settings' mapping.metrics; both rules, per fruit), as `canopy map` writes to metrics.json.)");
}

// Copying, comparing and the map's properties.
void bind_map_properties(MapClass& c) {
  c.def("copy", [](const PyMap& self) {
        return std::make_shared<PyMap>(self.read([](const SemanticOcTree& map) { return SemanticOcTree(map); }),
                                       self.settings());
      }, "A deep copy (owned, writable).")
      .def("__eq__", &PyMap::identical, py::is_operator(), "Identical trees, payloads, parameters and classes.")
      .def_property_readonly("resolution", [](const PyMap& self) {
        return self.read([](const SemanticOcTree& map) { return map.getResolution(); });
      }, "Voxel edge [m].")
      .def_property_readonly("classes", [](const PyMap& self) {
        return self.read([](const SemanticOcTree& map) { return map.classes().names; });
      })
      .def_property_readonly("target", [](const PyMap& self) {
        return self.read([](const SemanticOcTree& map) { return map.classes().target; });
      })
      .def_property_readonly("revision", [](const PyMap& self) {
        return self.read([](const SemanticOcTree& map) { return map.revision(); });
      }, "Incremented by every change.")
      .def_property_readonly("read_only", &PyMap::borrowed, "True for the map a planner is lent for one call.");
}

}  // namespace

void bind_maps(py::module_& m) {
  MapClass c(m, "Map", R"(The semantic octree (SSMI rules on OctoMap) with its frame step.

A map owns the extractor of its settings (colour segmentation or true labels, segmentation
noise seeded by mapping.extractor.seed), so inserting the frames `canopy map` inserts, with the
same settings, builds the same map byte for byte. Every query returns new arrays.)");
  bind_map_making(c);
  bind_map_files(c);
  bind_map_queries(c);
  bind_map_properties(c);
}

}  // namespace canopy::python
