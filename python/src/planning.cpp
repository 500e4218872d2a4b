// Planning from a map: fruit clusters, candidate views, gains by name, the next views for a
// base pose (jobs::next_views, as `canopy nbv`), and the robot's kinematics (canopy.Robot: IK).

#include <pybind11/stl.h>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/jobs/next_views_job.h"
#include "canopy/motion/view_reach.h"
#include "canopy/nbv/candidates.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/view_evaluator.h"
#include "objects.h"
#include "python_planner.h"

namespace canopy::python {

py::dict clusters_dict(const std::vector<nbv::Cluster>& clusters) {
  std::vector<Vec3> centroid, lo, hi;
  std::vector<std::int64_t> voxels;
  for (const nbv::Cluster& c : clusters) {
    centroid.push_back(c.centroid);
    lo.push_back(c.min);
    hi.push_back(c.max);
    voxels.push_back(static_cast<std::int64_t>(c.voxels));
  }
  return py::dict(py::arg("centroid") = points_array(centroid), py::arg("min") = points_array(lo),
                  py::arg("max") = points_array(hi), py::arg("voxels") = array_of(voxels));
}

namespace {
// The default robot, shared by canopy.Robot objects; immutable (every binding takes it const).
const std::shared_ptr<motion::RobotModel>& shared_robot_model() {
  static const auto model = std::make_shared<motion::RobotModel>(motion::RobotModel::load(default_robot_config()));
  return model;
}
}  // namespace

const motion::RobotModel& robot_model() { return *shared_robot_model(); }

py::dict candidates_dict(const py::object& centroid, int cluster, const nbv::CandidateParams& params) {
  std::vector<Pose> poses;
  std::vector<Vec3> targets;
  std::vector<double> polar, azimuth;
  for (const nbv::Candidate& c : nbv::sample_candidates(vec3_from(centroid, "centroid"), cluster, params)) {
    poses.push_back(c.T_world_camera);
    targets.push_back(c.target);
    polar.push_back(c.polar_deg);
    azimuth.push_back(c.azimuth_deg);
  }
  return py::dict(py::arg("pose") = poses_array(poses), py::arg("target") = points_array(targets),
                  py::arg("polar_deg") = array_of(polar), py::arg("azimuth_deg") = array_of(azimuth));
}

py::dict score_views(const nbv::VoxelIndex& index, const CameraIntrinsics& intrinsics, const nbv::NbvParams& params,
                     const std::string& gain_name, const std::string& rays_name, const py::object& poses,
                     const py::object& targets, std::uint64_t seed) {
  const std::vector<Pose> T = poses_from(poses, "poses");
  const std::vector<Vec3> t = points_from(targets, "targets");
  if (t.size() != T.size())
    throw InputError("targets: " + std::to_string(t.size()) + " targets for " + std::to_string(T.size()) + " poses");
  const std::unique_ptr<nbv::GainFunction> gain = nbv::make_gain(gain_name, params.gain, "gain");
  const nbv::RaySetEntry& rays = nbv::ray_set(rays_name, "rays");
  std::vector<double> gains(T.size());
  std::vector<std::string> status(T.size());
  std::vector<std::int64_t> ray_count(T.size()), voxel_count(T.size());
  {
    py::gil_scoped_release release;
    nbv::ViewEvaluator evaluator(index, intrinsics, params.rays);
    for (std::size_t i = 0; i < T.size(); ++i) {
      const nbv::ViewScore s = evaluator.evaluate(T[i], t[i], *gain, rays, mix_seed(seed, i));
      gains[i] = s.gain;
      status[i] = nbv::to_string(s.status);
      ray_count[i] = static_cast<std::int64_t>(s.rays);
      voxel_count[i] = static_cast<std::int64_t>(s.voxels);
    }
  }
  return py::dict(py::arg("gain") = array_of(gains), py::arg("status") = strings_array(status),
                  py::arg("rays") = array_of(ray_count), py::arg("voxels") = array_of(voxel_count));
}

py::dict planned_views_dict(const std::vector<nbv::PlannedView>& ordered,
                            const std::vector<nbv::PlannedView>& unreachable) {
  std::vector<Pose> poses;
  std::vector<Vec3> targets;
  std::vector<int> clusters, tour;
  std::vector<double> gains, shifts, joints;
  std::vector<std::string> sources;
  std::vector<bool> has_joints;
  const auto add = [&](const nbv::PlannedView& v, int tour_index) {
    poses.push_back(v.T_world_camera);
    targets.push_back(v.target);
    clusters.push_back(v.cluster);
    gains.push_back(v.gain);
    shifts.push_back(v.shift_m);
    sources.push_back(v.source);
    tour.push_back(tour_index);
    has_joints.push_back(v.has_q);
    for (double q : v.q) joints.push_back(v.has_q ? q : std::nan(""));
  };
  int order = 0;
  for (const nbv::PlannedView& v : ordered) add(v, order++);
  for (const nbv::PlannedView& v : unreachable) add(v, -1);
  py::array_t<double> joint_array({static_cast<py::ssize_t>(poses.size()), static_cast<py::ssize_t>(kArmDof)});
  std::copy(joints.begin(), joints.end(), joint_array.mutable_data());
  return py::dict(py::arg("pose") = poses_array(poses), py::arg("target") = points_array(targets),
                  py::arg("cluster") = array_of(clusters), py::arg("gain") = array_of(gains),
                  py::arg("shift_m") = array_of(shifts), py::arg("source") = strings_array(sources),
                  py::arg("tour_index") = array_of(tour), py::arg("has_joints") = array_of(has_joints),
                  py::arg("joints") = joint_array);
}

namespace {

Vec3 arm_base(const BasePose& base) {
  return motion::RobotModel::T_world_base(base) * robot_model().T_base_arm().translation();
}

// canopy.next_views: jobs::next_views with the method chosen by name or a Python planner.
py::dict next_views(const PyMap& map, const py::object& base, const py::object& joints, const py::object& settings,
                    const py::object& method, const py::object& planner, const py::object& seed,
                    const py::object& intrinsics) {
  settings::Settings s = settings_from(settings);
  // The default is canopy nbv's (jobs::kNextViewsMethod), not the bundle's method.name (the
  // paper's ours, which run_mission keeps).
  choose_method(s, method.is_none() && planner.is_none() ? py::str(jobs::kNextViewsMethod) : method, planner);
  jobs::NextViewsJob job;
  job.base = base_from(base, "base");
  if (!joints.is_none()) job.joints = joints_from(joints, "joints");
  job.seed = seed_from(seed, "seed");
  job.intrinsics = intrinsics_from(intrinsics, CameraIntrinsics{});
  jobs::NextViewsJobResult r;
  take_interrupt();
  {
    const PendingPlanner pending(planner, s.mapping);
    py::gil_scoped_release release;
    r = map.read([&](const mapping::SemanticOcTree& tree) { return jobs::next_views(tree, s, robot_model(), job); });
  }
  if (take_interrupt()) {  // Ctrl-C in the planner
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  return py::dict(py::arg("views") = planned_views_dict(r.next.ordered, r.next.unreachable),
                  py::arg("method") = r.method.name, py::arg("region") = box_array(r.region),
                  py::arg("clusters") = r.next.batch.clusters, py::arg("candidates") = r.next.batch.candidates,
                  py::arg("filtered") = r.next.batch.filtered, py::arg("robot_voxels_cleared") = r.next.cleared_voxels,
                  py::arg("finished") = r.next.batch.finished, py::arg("reason") = r.next.batch.reason);
}

// canopy.Robot: the default robot's kinematics.
void bind_robot(py::module_& m) {
  py::class_<motion::RobotModel, std::shared_ptr<motion::RobotModel>>(m, "Robot",
      "The mobile manipulator (models/robot: the URDF and robot.yaml): kinematics, IK and limits.")
      .def(py::init([] { return shared_robot_model(); }),
           "The default robot (loaded once, shared).")
      .def_property_readonly("home", [](const motion::RobotModel& r) { return joints_array(r.config().home); },
                             "Home joints [rad].")
      .def_property_readonly("lower", [](const motion::RobotModel& r) { return joints_array(r.limits().lower); })
      .def_property_readonly("upper", [](const motion::RobotModel& r) { return joints_array(r.limits().upper); })
      .def("camera_pose", [](const motion::RobotModel& r, const py::object& base, const py::object& joints) {
        return pose_array(r.camera_pose(base_from(base, "base"), joints_from(joints, "joints")));
      }, py::arg("base"), py::arg("joints"), "4x4 T_world_camera of the wrist camera for base (x, y, yaw) and joints.")
      .def("ik", [](const motion::RobotModel& r, const py::object& base, const py::object& pose, const py::object& seed) {
        const motion::IkResult ik =
            r.camera_ik(base_from(base, "base"), pose_from(pose, "pose"), seed.is_none() ? r.config().home : joints_from(seed, "seed"));
        py::array_t<double> out({static_cast<py::ssize_t>(ik.count), static_cast<py::ssize_t>(kArmDof)});
        for (int i = 0; i < ik.count; ++i)
          std::copy(ik.q[static_cast<std::size_t>(i)].begin(), ik.q[static_cast<std::size_t>(i)].end(),
                    out.mutable_data() + i * kArmDof);
        return out;
      }, py::arg("base"), py::arg("pose"), py::arg("seed") = py::none(),
      R"(Every IK solution placing the camera at pose (4x4 T_world_camera) with the base at (x, y, yaw),
within the joint limits, nearest to seed (default: home) first: (K, 6), K = 0 when unreachable.)")
      .def("within_limits", [](const motion::RobotModel& r, const py::object& joints) {
        return r.within_limits(joints_from(joints, "joints"));
      }, py::arg("joints"))
      .def("arm_base", [](const motion::RobotModel&, const py::object& base) {
        return vec3_array(arm_base(base_from(base, "base")));
      }, py::arg("base"), "The arm base's position in the world for base (x, y, yaw).")
      .def("stop_region", [](const motion::RobotModel&, const py::object& base, const py::object& settings) {
        return box_array(jobs::stop_region_at(settings_from(settings), robot_model(), base_from(base, "base")));
      }, py::arg("base"), py::arg("settings") = py::none(),
      "The box [[min], [max]] a planner looks for targets in at this base (the settings' mission.loop).");
}

}  // namespace

void bind_planning(py::module_& m) {
  m.def("planner_names", &nbv::view_planner_names,
        "View planners of the registry (ours, frontier, predefined, then registered ones; 'python' is the planner= "
        "of run_mission / next_views).");
  m.def("gain_names", &nbv::gain_names, "Information gains: osamcep, ae, uvc, uvpc, oae, mi, rs.");
  m.def("ray_set_names", &nbv::ray_set_names, "Ray sets: ours, dense, sparse.");

  m.def("find_clusters", [](const PyMap& map, const py::object& settings, const py::object& region) {
        const nbv::ClusterParams params = settings_from(settings).nbv.cluster;
        Eigen::AlignedBox3d box;
        if (!region.is_none()) box = box_from(region, "region");
        std::vector<nbv::Cluster> clusters;
        {
          py::gil_scoped_release release;
          clusters = map.read([&](const mapping::SemanticOcTree& tree) {
            return nbv::find_clusters(tree, params, region.is_none() ? nullptr : &box);
          });
        }
        return clusters_dict(clusters);
      }, py::arg("map"), py::arg("settings") = py::none(), py::arg("region") = py::none(),
      R"(Fruit clusters of a map (DBSCAN over target voxels, the settings' nbv.cluster), largest first:
{'centroid', 'min', 'max': (N, 3), 'voxels': (N,)}. region: [[min], [max]] (only voxels inside).)");

  m.def("sample_candidates", [](const py::object& centroid, const py::object& settings, int cluster) {
        return candidates_dict(centroid, cluster, settings_from(settings).nbv.candidates);
      }, py::arg("centroid"), py::arg("settings") = py::none(), py::arg("cluster") = -1,
      R"(Candidate views on the sphere around a centroid (the settings' nbv.candidates), each looking at
it with zero roll: {'pose': (N, 4, 4), 'target': (N, 3), 'polar_deg', 'azimuth_deg': (N,)}.)");

  m.def("gains", [](const PyMap& map, const py::object& poses, const py::object& targets, const std::string& gain,
                    const std::string& rays, const py::object& settings, const py::object& intrinsics, const py::object& seed) {
        const settings::Settings s = settings_from(settings);
        const CameraIntrinsics K = intrinsics_from(intrinsics, CameraIntrinsics{});
        return map.read([&](const mapping::SemanticOcTree& tree) {
          nbv::VoxelIndex index;
          {
            py::gil_scoped_release release;
            index.rebuild(tree);
          }
          return score_views(index, K, s.nbv, gain, rays, poses, targets, seed_from(seed, "seed"));
        });
      }, py::arg("map"), py::arg("poses"), py::arg("targets"), py::arg("gain") = "osamcep", py::arg("rays") = "ours",
      py::arg("settings") = py::none(), py::arg("intrinsics") = py::none(), py::arg("seed") = 1,
      R"(Scores views by a gain chosen by name (gain_names(); rays: ray_set_names()): poses (N, 4, 4)
looking at targets (N, 3). Returns {'gain', 'status' ('ok' or why the view scores 0: 'no rays
in the window', 'target not in front of the camera', 'camera inside an occupied voxel',
'camera outside the map'), 'rays', 'voxels'}: arrays of N. seed feeds the rs gain
(view i gets a seed mixed from seed and i). Builds the map's voxel index for the call; a
planner in the loop scores against the mission's index with request.gains.)");

  m.def("next_views", &next_views, py::arg("map"), py::arg("base"), py::arg("joints") = py::none(), py::arg("settings") = py::none(),
      py::arg("method") = py::none(), py::arg("planner") = py::none(), py::arg("seed") = 1,
      py::arg("intrinsics") = py::none(),
      R"(The next views from a map for the robot at base (x, y, yaw), as `canopy nbv`: the planner's batch
for the stop's region (the settings' mission.loop box around the arm base), the workspace
filter and IK against the map's occupied voxels, then the tour from joints (default: home).

method: a planner name (default: learned, as `canopy nbv`: the planner a lab deploys,
docs/real_robot.md; the settings' method.name is run_mission's); planner: a Python planner
(docs/python.md), instead of method. Returns {'views': dict of arrays (pose, target, cluster,
gain, shift_m, source, tour_index (-1: no IK), has_joints, joints (NaN without IK)), 'method',
'region', 'clusters', 'candidates', 'filtered', 'robot_voxels_cleared', 'finished', 'reason'}.)");


  bind_robot(m);
}

}  // namespace canopy::python
