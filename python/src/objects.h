#pragma once
// The C++ objects behind canopy.World and canopy.Map, and the binding functions of each file.

#include <memory>
#include <mutex>
#include <string>

#include "canopy/common/frame.h"
#include "canopy/mapping/frame_mapping.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/settings/settings.h"
#include "canopy/motion/robot_model.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/nbv/voxel_index.h"
#include "canopy/perception/semantic_extractor.h"
#include "canopy/sim/renderer.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"
#include "convert.h"

namespace canopy::python {

/// canopy.Frame: a labelled frame and its name in a sequence.
struct PyFrame {
  LabelledFrame frame;
  std::string name;
};
/// A new Python Frame.
py::object frame_object(PyFrame frame);

/// canopy.World: a generated world and, made on the first render, a simulator and renderer.
class PyWorld {
 public:
  /// Loads and checks the world of `path` (found like the command line's --world), with `seed`
  /// when given, for the labels of `settings` (None: the default bundle): jobs::load_world.
  PyWorld(const std::string& path, const py::object& seed, const py::object& settings);

  const world::World& world() const { return *world_; }
  std::shared_ptr<const world::World> shared() const { return world_; }
  const std::string& file() const { return file_; }

  /// A free camera's frame (robot hidden). Call without the GIL.
  LabelledFrame render(const Pose& T_world_camera);
  /// The wrist camera's frame with the robot at (base, q), robot visible. Call without the GIL.
  LabelledFrame render_robot(const BasePose& base, const ArmConfig& q);

 private:
  sim::Renderer& renderer();  // with mutex_ held

  std::shared_ptr<const world::World> world_;
  std::string file_;
  std::mutex mutex_;
  std::unique_ptr<sim::Simulator> sim_;
  std::unique_ptr<sim::Renderer> renderer_;  // after sim_: destroyed first
};

/// canopy.Map: a semantic map owned by Python, or the map of a running mission lent to a
/// Python planner for one call (read-only, and unusable after the call).
class PyMap {
 public:
  /// An empty map with the mapping settings (map parameters, extractor, metrics).
  PyMap(const settings::MappingSettings& settings, const SemanticClasses& classes);
  /// Takes `map` over; `settings` gives the extractor and metrics (the map keeps its own parameters).
  PyMap(mapping::SemanticOcTree map, const settings::MappingSettings& settings);
  /// A read-only loan of `map`, valid while *alive is true.
  static std::shared_ptr<PyMap> borrow(const mapping::SemanticOcTree& map, std::shared_ptr<const bool> alive,
                                       const settings::MappingSettings& settings);

  /// Runs f(map) under the map's lock (the GIL may be released around it); throws when a loan
  /// has ended.
  template <typename F>
  auto read(F&& f) const {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    return f(get());
  }
  /// Labels and inserts a frame (mapping::map_frame, the extractor of the settings). Owned maps only.
  mapping::FrameMapStep insert(const LabelledFrame& frame);
  /// Inserts a labelled cloud. Owned maps only.
  mapping::InsertStats insert_cloud(const perception::LabelledCloud& cloud);

  const settings::MappingSettings& settings() const { return settings_; }
  bool borrowed() const { return borrowed_ != nullptr; }
  /// Identical trees, payloads, parameters and classes (both locks taken without deadlock).
  static bool identical(const PyMap& a, const PyMap& b);

 private:
  PyMap() = default;
  const mapping::SemanticOcTree& get() const;
  mapping::SemanticOcTree& owned();
  void make_inserter();  // the first insert's (owned maps only; mutex_ held)

  std::unique_ptr<mapping::SemanticOcTree> owned_;
  const mapping::SemanticOcTree* borrowed_ = nullptr;
  std::shared_ptr<const bool> alive_;
  settings::MappingSettings settings_;
  std::unique_ptr<mapping::ScanInserter> inserter_;  // made by the first insert
  std::unique_ptr<perception::SemanticExtractor> extractor_;
  // Recursive: a Python planner given to next_views(map) may query that same map while
  // next_views reads it, on the same thread.
  mutable std::recursive_mutex mutex_;
};

void bind_settings(py::module_& m);
void bind_frames(py::module_& m);
void bind_worlds(py::module_& m);
void bind_maps(py::module_& m);
void bind_planning(py::module_& m);
void bind_missions(py::module_& m);

/// The default robot's kinematic model (models/robot), loaded once; immutable.
const motion::RobotModel& robot_model();

// Planning results as dicts of arrays (planning.cpp), shared with the planner request.
/// {'centroid', 'min', 'max': (N, 3), 'voxels': (N,)}.
py::dict clusters_dict(const std::vector<nbv::Cluster>& clusters);
/// {'pose': (N, 4, 4), 'target': (N, 3), 'polar_deg', 'azimuth_deg'} of the candidates around `centroid`.
py::dict candidates_dict(const py::object& centroid, int cluster, const nbv::CandidateParams& params);
/// Scores views (poses, targets from Python) by the gain and ray set named, against `index`.
py::dict score_views(const nbv::VoxelIndex& index, const CameraIntrinsics& intrinsics, const nbv::NbvParams& params,
                     const std::string& gain, const std::string& rays, const py::object& poses,
                     const py::object& targets, std::uint64_t seed);
/// Views in execution order, then the unreachable ones (tour_index -1), as arrays.
py::dict planned_views_dict(const std::vector<nbv::PlannedView>& ordered, const std::vector<nbv::PlannedView>& unreachable);

}  // namespace canopy::python
