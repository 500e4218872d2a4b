#include "convert.h"

#include <cmath>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/robot/robot_config.h"

namespace canopy::python {

std::string describe(const py::handle& obj) {
  std::string s = py::repr(obj).cast<std::string>();
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s.size() > 120 ? s.substr(0, 117) + "..." : s;
}

Doubles finite_doubles(const py::handle& obj, const std::string& what) {
  const auto not_numbers = [&] { return InputError(what + ": " + describe(obj) + " is not an array of numbers"); };
  if (py::isinstance<py::str>(obj) || obj.is_none()) throw not_numbers();
  Doubles a = Doubles::ensure(obj);  // null when not numeric
  if (!a) throw not_numbers();
  const double* d = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i)
    if (!std::isfinite(d[i])) throw InputError(what + ": " + describe(obj) + " holds a value that is not finite");
  return a;
}

namespace {

Pose pose_at(const double* m, const py::handle& obj, const std::string& what) {
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = m[r * 4 + c];
  const Mat3 R = M.topLeftCorner<3, 3>();
  const bool rigid = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-6 && R.determinant() > 0.0 &&
                     M(3, 0) == 0.0 && M(3, 1) == 0.0 && M(3, 2) == 0.0 && M(3, 3) == 1.0;
  if (!rigid)
    throw InputError(what + ": " + describe(obj) +
                     " is not a rigid transform (a rotation with orthonormal columns, last row 0 0 0 1)");
  Pose T = Pose::Identity();
  T.linear() = R;
  T.translation() = M.topRightCorner<3, 1>();
  return T;
}

}  // namespace

Pose pose_from(const py::handle& obj, const std::string& what) {
  const auto a = finite_doubles(obj, what);
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw InputError(what + ": " + describe(obj) + " is not a 4x4 matrix");
  return pose_at(a.data(), obj, what);
}

std::vector<Pose> poses_from(const py::handle& obj, const std::string& what) {
  const auto a = finite_doubles(obj, what);
  if (a.ndim() == 2) return {pose_from(obj, what)};
  if (a.ndim() != 3 || a.shape(1) != 4 || a.shape(2) != 4)
    throw InputError(what + ": " + describe(obj) + " is not a 4x4 matrix or an (N, 4, 4) array of them");
  std::vector<Pose> out;
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    out.push_back(pose_at(a.data() + 16 * i, obj, what + "[" + std::to_string(i) + "]"));
  return out;
}

py::array_t<double> pose_array(const Pose& T) {
  py::array_t<double> a({4, 4});
  auto m = a.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = T.matrix()(r, c);
  return a;
}

py::array_t<double> poses_array(const std::vector<Pose>& poses) {
  py::array_t<double> a({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}, py::ssize_t{4}});
  auto m = a.mutable_unchecked<3>();
  for (std::size_t i = 0; i < poses.size(); ++i)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(static_cast<py::ssize_t>(i), r, c) = poses[i].matrix()(r, c);
  return a;
}

Vec3 vec3_from(const py::handle& obj, const std::string& what) {
  const auto a = finite_doubles(obj, what);
  if (a.ndim() != 1 || a.shape(0) != 3) throw InputError(what + ": " + describe(obj) + " is not 3 numbers");
  return Vec3(a.data()[0], a.data()[1], a.data()[2]);
}

std::vector<Vec3> points_from(const py::handle& obj, const std::string& what) {
  const auto a = finite_doubles(obj, what);
  if (a.ndim() == 1 && a.shape(0) == 3) return {Vec3(a.data()[0], a.data()[1], a.data()[2])};
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InputError(what + ": " + describe(obj) + " is not a point (3,) or points (N, 3)");
  std::vector<Vec3> out(static_cast<std::size_t>(a.shape(0)));
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec3(a.data()[3 * i], a.data()[3 * i + 1], a.data()[3 * i + 2]);
  return out;
}

py::array_t<double> vec3_array(const Vec3& v) {
  py::array_t<double> a(3);
  for (int i = 0; i < 3; ++i) a.mutable_data()[i] = v[i];
  return a;
}

py::array_t<double> points_array(const std::vector<Vec3>& points) {
  py::array_t<double> a({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  double* d = a.mutable_data();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) d[3 * i + static_cast<std::size_t>(k)] = points[i][k];
  return a;
}

BasePose base_from(const py::handle& obj, const std::string& what) {
  const auto a = finite_doubles(obj, what);
  if (a.ndim() != 1 || a.shape(0) != 3) throw InputError(what + ": " + describe(obj) + " is not (x, y, yaw)");
  return BasePose{a.data()[0], a.data()[1], a.data()[2]};
}

ArmConfig joints_from(const py::handle& obj, const std::string& what) {
  const auto a = finite_doubles(obj, what);
  if (a.ndim() != 1 || a.shape(0) != kArmDof) throw InputError(what + ": " + describe(obj) + " is not 6 joint angles");
  ArmConfig q{};
  std::copy(a.data(), a.data() + kArmDof, q.begin());
  return q;
}

py::array_t<double> joints_array(const ArmConfig& q) {
  py::array_t<double> a(kArmDof);
  std::copy(q.begin(), q.end(), a.mutable_data());
  return a;
}

Eigen::AlignedBox3d box_from(const py::handle& obj, const std::string& what) {
  const auto a = finite_doubles(obj, what);
  if (a.ndim() != 2 || a.shape(0) != 2 || a.shape(1) != 3)
    throw InputError(what + ": " + describe(obj) + " is not a box [[min x, y, z], [max x, y, z]]");
  const Vec3 lo(a.data()[0], a.data()[1], a.data()[2]), hi(a.data()[3], a.data()[4], a.data()[5]);
  if (!(lo.array() <= hi.array()).all()) throw InputError(what + ": " + describe(obj) + " has a min above its max");
  return Eigen::AlignedBox3d(lo, hi);
}

py::array_t<double> box_array(const Eigen::AlignedBox3d& box) {
  py::array_t<double> a({2, 3});
  for (int k = 0; k < 3; ++k) {
    a.mutable_data()[k] = box.min()[k];
    a.mutable_data()[3 + k] = box.max()[k];
  }
  return a;
}

py::array strings_array(const std::vector<std::string>& v) {
  return py::module_::import("numpy").attr("array")(py::cast(v), py::arg("dtype") = "U");
}

py::object yaml_to_py(const YAML::Node& node) {
  if (node.IsMap()) {
    py::dict d;
    for (const auto& kv : node) d[py::str(kv.first.Scalar())] = yaml_to_py(kv.second);
    return std::move(d);
  }
  if (node.IsSequence()) {
    py::list l;
    for (const auto& item : node) l.append(yaml_to_py(item));
    return std::move(l);
  }
  if (!node.IsScalar()) return py::none();
  const std::string& text = node.Scalar();
  if (text == "true" || text == "false") return py::bool_(text == "true");
  long long i = 0;
  double x = 0.0;
  if (node.Tag() != "!" && YAML::convert<long long>::decode(node, i)) return py::int_(i);
  if (node.Tag() != "!" && YAML::convert<double>::decode(node, x)) return py::float_(x);
  return py::str(text);
}

py::object json_to_py(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

std::string path_from(const py::object& path, const std::string& what) {
  if (py::isinstance<py::str>(path)) return path.cast<std::string>();
  if (py::hasattr(path, "__fspath__")) {
    const py::object p = path.attr("__fspath__")();
    if (py::isinstance<py::str>(p)) return p.cast<std::string>();
  }
  throw InputError(what + ": " + describe(path) + " is not a file name (str or path)");
}

std::uint64_t seed_from(const py::object& seed, const std::string& what) {
  const bool integer = py::isinstance<py::int_>(seed) && !py::isinstance<py::bool_>(seed);
  if (integer && seed.cast<py::int_>() >= py::int_(0)) {
    try {
      return seed.cast<std::uint64_t>();
    } catch (const py::cast_error&) {
    }
  }
  throw InputError(what + ": " + describe(seed) + " is not an integer in [0, 2^64)");
}

settings::Settings settings_from(const py::object& settings) {
  if (settings.is_none())
    return settings::Settings::load(find_data_file(settings::default_settings_path()), default_robot_config());
  if (py::isinstance<settings::Settings>(settings)) return settings.cast<settings::Settings>();
  if (py::isinstance<py::str>(settings) || py::hasattr(settings, "__fspath__"))
    return settings::Settings::load(find_data_file(path_from(settings, "settings")), default_robot_config());
  throw InputError("settings: " + describe(settings) + " is not a canopy.Settings, a bundle file or None");
}

CameraIntrinsics intrinsics_from(const py::object& intrinsics, const CameraIntrinsics& fallback) {
  if (intrinsics.is_none()) return fallback;
  if (!py::isinstance<CameraIntrinsics>(intrinsics))
    throw InputError("intrinsics: " + describe(intrinsics) + " is not a canopy.Intrinsics");
  const CameraIntrinsics K = intrinsics.cast<CameraIntrinsics>();
  datasets::validate_recorded_intrinsics(K, "intrinsics");
  return K;
}

std::string yaml_value(const py::handle& value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)) return py::repr(value).cast<std::string>();
  try {
    return py::module_::import("json").attr("dumps")(value).cast<std::string>();
  } catch (const py::error_already_set&) {
    throw InputError("value " + describe(value) + " is not a string, number, bool, list or dict");
  }
}

}  // namespace canopy::python
