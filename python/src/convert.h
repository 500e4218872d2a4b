#pragma once
// Conversions between Python values (numpy arrays, sequences, dicts) and canopy's types,
// shared by the binding files. Every conversion of user input checks it and raises
// ValueError (canopy::InputError) naming the argument and its value; every array handed back
// is a fresh copy unless a function says otherwise.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/types.h"
#include "canopy/settings/settings.h"

namespace canopy::python {

namespace py = pybind11;

/// A C-contiguous float64 array.
using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A C-contiguous float64 copy or view of `obj`; InputError naming `what` when it holds
/// anything but finite numbers.
Doubles finite_doubles(const py::handle& obj, const std::string& what);
/// The start of `obj`'s repr, for messages.
std::string describe(const py::handle& obj);

/// A 4x4 rigid transform (rotation orthonormal within 1e-6, last row 0 0 0 1).
Pose pose_from(const py::handle& obj, const std::string& what);
/// (4, 4) or (N, 4, 4) rigid transforms.
std::vector<Pose> poses_from(const py::handle& obj, const std::string& what);
py::array_t<double> pose_array(const Pose& T);
py::array_t<double> poses_array(const std::vector<Pose>& poses);

Vec3 vec3_from(const py::handle& obj, const std::string& what);
/// (3,) or (N, 3) points.
std::vector<Vec3> points_from(const py::handle& obj, const std::string& what);
py::array_t<double> vec3_array(const Vec3& v);
py::array_t<double> points_array(const std::vector<Vec3>& points);

/// (x, y, yaw) [m, m, rad].
BasePose base_from(const py::handle& obj, const std::string& what);
/// Six joint angles [rad].
ArmConfig joints_from(const py::handle& obj, const std::string& what);
py::array_t<double> joints_array(const ArmConfig& q);
/// (2, 3): the corners min and max, min <= max.
Eigen::AlignedBox3d box_from(const py::handle& obj, const std::string& what);
py::array_t<double> box_array(const Eigen::AlignedBox3d& box);

/// A numpy array copied from a vector.
template <typename T>
py::array_t<T> array_of(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}
/// A numpy array of Python strings (dtype object would not compare with ==; unicode does).
py::array strings_array(const std::vector<std::string>& v);

/// YAML as Python objects: mappings as dicts, sequences as lists, scalars as bool (true,
/// false), int, float or str.
py::object yaml_to_py(const YAML::Node& node);

/// JSON as Python objects (dicts, lists, numbers, strings).
py::object json_to_py(const nlohmann::json& j);

/// A file or folder name: a str or an os.PathLike.
std::string path_from(const py::object& path, const std::string& what);

/// A seed: an integer in [0, 2^64).
std::uint64_t seed_from(const py::object& seed, const std::string& what);

/// `settings` as a bundle: a canopy.Settings, a bundle file's path, or None for the default
/// bundle (configs/canopy.yaml, as the command line loads it).
settings::Settings settings_from(const py::object& settings);
/// `intrinsics` (a canopy.Intrinsics) or `fallback` when None; validated.
CameraIntrinsics intrinsics_from(const py::object& intrinsics, const CameraIntrinsics& fallback);

/// A Python value as the YAML text Settings::set reads: str as is, bool as true/false,
/// numbers by repr, lists and dicts as JSON.
std::string yaml_value(const py::handle& value);

}  // namespace canopy::python
