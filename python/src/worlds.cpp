// canopy.World: a generated world, its ground truth, and frames rendered from it.

#include <pybind11/stl.h>

#include "canopy/common/error.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/jobs/world_job.h"
#include "objects.h"

namespace canopy::python {

PyWorld::PyWorld(const std::string& path, const py::object& seed, const py::object& settings) : file_(path) {
  // The checks every command that builds a world runs (the robot fits the aisle, the colour
  // segmentation of the settings' labels sees the target fruit): one job of the library.
  jobs::WorldJobParams job;
  job.world_file = path;
  if (!seed.is_none()) job.seed = seed_from(seed, "seed");
  job.extractor = settings_from(settings).mapping.extractor;
  py::gil_scoped_release release;
  world_ = std::make_shared<const world::World>(jobs::load_world(job));
}

sim::Renderer& PyWorld::renderer() {
  if (!renderer_) {
    sim_ = std::make_unique<sim::Simulator>(*world_, default_robot_config());
    renderer_ = std::make_unique<sim::Renderer>(*sim_, world_->spec.camera);
  }
  return *renderer_;
}

LabelledFrame PyWorld::render(const Pose& T_world_camera) {
  std::lock_guard<std::mutex> lock(mutex_);
  return renderer().render_free_camera(T_world_camera);
}

LabelledFrame PyWorld::render_robot(const BasePose& base, const ArmConfig& q) {
  std::lock_guard<std::mutex> lock(mutex_);
  sim::Renderer& r = renderer();
  sim_->set_robot_state(base, q);
  return r.render_wrist_camera();
}

namespace {

py::dict fruits_dict(const world::GroundTruth& truth) {
  std::vector<int> ids, plants;
  std::vector<std::string> colors, shapes;
  std::vector<bool> targets;
  std::vector<Vec3> centers, lo, hi;
  std::vector<double> areas;
  std::vector<std::int64_t> points;
  for (const world::FruitTruth& f : truth.fruits) {
    ids.push_back(f.instance_id);
    plants.push_back(f.plant_index);
    colors.push_back(f.color);
    shapes.push_back(f.shape);
    targets.push_back(f.target);
    centers.push_back(f.center);
    lo.push_back(f.bbox_min);
    hi.push_back(f.bbox_max);
    areas.push_back(f.surface_area_m2);
    points.push_back(static_cast<std::int64_t>(f.surface_points.size()));
  }
  py::array_t<bool> target_array(static_cast<py::ssize_t>(targets.size()));
  std::copy(targets.begin(), targets.end(), target_array.mutable_data());
  return py::dict(py::arg("instance_id") = array_of(ids), py::arg("plant") = array_of(plants),
                  py::arg("color") = strings_array(colors), py::arg("shape") = strings_array(shapes),
                  py::arg("target") = target_array, py::arg("center") = points_array(centers),
                  py::arg("bbox_min") = points_array(lo), py::arg("bbox_max") = points_array(hi),
                  py::arg("surface_area_m2") = array_of(areas), py::arg("surface_points") = array_of(points));
}

using WorldClass = py::class_<PyWorld, std::shared_ptr<PyWorld>>;

// The world's description and its ground truth.
void bind_world_contents(WorldClass& c) {
  c.def(py::init([](const py::object& path, const py::object& seed, const py::object& settings) {
             return std::make_shared<PyWorld>(path_from(path, "path"), seed, settings);
           }),
           py::arg("path") = "worlds/default.yaml",
           py::arg("seed") = py::none(), py::kw_only(), py::arg("settings") = py::none(),
           R"(Generates the world of a world file, with the checks of the command line's world loading.

path: a world file, found like the command line's --world (the current folder, then canopy's
data folder: worlds/small.yaml works anywhere); seed: replaces the file's seed (same seed,
same world, bit for bit); settings: the canopy.Settings (or bundle file) whose labels the
world will be mapped with (default: configs/canopy.yaml). ValueError names a bad file, key or
value, a robot base wider than the aisle, or (labels color) an imported plant whose ripe-fruit
material colour segmentation would not see, with the message `canopy world --seg color` gives.)")
      .def_property_readonly("name", [](const PyWorld& w) { return w.world().spec.name; })
      .def_property_readonly("file", &PyWorld::file, "The world file as given.")
      .def_property_readonly("seed", [](const PyWorld& w) { return w.world().spec.seed; })
      .def_property_readonly("classes", [](const PyWorld& w) { return w.world().spec.classes.names; },
                             "Semantic class names; index 0 is the background.")
      .def_property_readonly("target", [](const PyWorld& w) { return w.world().spec.classes.target; },
                             "The target class (what the metrics and the planners count).")
      .def_property_readonly("camera", [](const PyWorld& w) { return w.world().spec.camera; },
                             "The wrist camera's canopy.Intrinsics.")
      .def_property_readonly("robot_start", [](const PyWorld& w) {
        const BasePose& b = w.world().spec.robot_start;
        return array_of(std::vector<double>{b.x_m, b.y_m, b.yaw_rad});
      }, "Base pose (x, y, yaw) at the start of the aisle.")
      .def_property_readonly("spec", [](const PyWorld& w) { return json_to_py(w.world().spec.to_json()); },
                             "Every resolved parameter of the world file (a dict; its keys are a world file's).")
      .def_property_readonly("triangles", [](const PyWorld& w) { return w.world().triangle_count(); })
      .def_property_readonly("plants", [](const PyWorld& w) {
        py::list out;
        for (std::size_t i = 0; i < w.world().plants.size(); ++i) {
          const std::shared_ptr<const world::Plant> plant = w.world().plant(i);  // generated again when not held
          const world::Plant& p = *plant;
          int fruits = 0;
          for (const auto& part : p.parts) fruits += part.instance_id != kNoInstance;
          out.append(py::dict(py::arg("index") = p.index, py::arg("base_position") = vec3_array(p.base_position),
                              py::arg("height_m") = p.height_m, py::arg("parts") = p.parts.size(),
                              py::arg("fruits") = fruits, py::arg("import_dir") = p.import_dir));
        }
        return out;
      }, "One dict per plant: index, base_position, height_m, parts, fruits, import_dir.")
      .def_property_readonly("fruits", [](const PyWorld& w) { return fruits_dict(w.world().truth); },
                             R"(The fruit ground truth as a dict of arrays, one entry per fruit: instance_id
(as in rendered instance images), plant, color, shape, target (ripe: counted by the metrics),
center, bbox_min, bbox_max (N, 3) [m], surface_area_m2, surface_points (sample counts).)")
      .def("fruit_points", [](const PyWorld& w) {
        std::vector<Vec3> points;
        std::vector<int> ids;
        for (const world::FruitTruth& f : w.world().truth.fruits)
          for (const Vec3& p : f.surface_points) {
            points.push_back(p);
            ids.push_back(f.instance_id);
          }
        return py::dict(py::arg("points") = points_array(points), py::arg("instance_id") = array_of(ids));
      }, "Every fruit's surface samples (what coverage is scored on): {'points': (M, 3), 'instance_id': (M,)}.");
}

// Views of the world and renders.
void bind_world_renders(WorldClass& c) {
  c.def("views", [](const PyWorld& w, const std::string& spec) {
        return poses_array(evaluation::views_from_spec(spec, w.world()));
      }, py::arg("spec") = "ring", R"(Camera poses around the plants, as `canopy map --views`: 'ring' (around each plant),
'aisle' (along each row, from the aisle) or a file of 'x y z qw qx qy qz' lines: (N, 4, 4).)")
      .def("render", [](PyWorld& w, const py::object& pose) {
        const Pose T = pose_from(pose, "pose");
        PyFrame f;
        {
          py::gil_scoped_release release;
          f.frame = w.render(T);
        }
        return frame_object(std::move(f));
      }, py::arg("pose"), R"(Renders a free camera at pose (4x4 T_world_camera, optical frame: x right,
y down, z forward), robot hidden: a canopy.Frame with rgb, depth, labels and instances.)")
      .def("render_robot", [](PyWorld& w, const py::object& base, const py::object& joints) {
        const BasePose b = base_from(base, "base");
        const ArmConfig q = joints.is_none() ? robot_model().config().home : joints_from(joints, "joints");
        if (!robot_model().within_limits(q))
          throw InputError("joints: " + describe(joints) + " is outside the joint limits");
        PyFrame f;
        {
          py::gil_scoped_release release;
          f.frame = w.render_robot(b, q);
        }
        return frame_object(std::move(f));
      }, py::arg("base"), py::arg("joints") = py::none(),
      R"(Renders the wrist camera with the robot's base at (x, y, yaw) and the arm at joints (6 angles
[rad], default: home), robot visible.)");
}

}  // namespace

void bind_worlds(py::module_& m) {
  WorldClass c(m, "World", R"(A generated greenhouse world: plants, fruits and their ground truth.

The simulator and renderer are made on the first render and kept (one OSMesa context per
world); renders of one world from several threads take turns.)");
  bind_world_contents(c);
  bind_world_renders(c);
}

}  // namespace canopy::python
