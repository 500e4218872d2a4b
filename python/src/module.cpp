// The extension module canopy._canopy (imported by canopy/__init__.py): error translation,
// canopy.Settings, and the binding files' parts.

#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/robot/robot_config.h"
#include "objects.h"
#include "python_planner.h"
#include "datasets.h"
#include "records.h"

namespace canopy::python {

void bind_settings(py::module_& m) {
  py::class_<settings::Settings>(m, "Settings", R"(The settings bundle: sections method, mapping, nbv, motion and mission.

Every setting is named by its key path ("mission.loop.views_per_stop"); docs/settings.md
lists them all with their defaults, limits and help (so does describe()).)")
      .def(py::init([](const py::object& path) { return settings_from(path); }), py::arg("path") = py::none(),
           "Loads a bundle file (default: configs/canopy.yaml, found like the command line's --config).")
      .def_static("defaults", [] { return settings::Settings::defaults(default_robot_config()); },
                  "The struct defaults (equal to configs/canopy.yaml).")
      .def_static("from_yaml", [](const std::string& text, const std::string& folder) {
        return settings::Settings::load_string(text, "settings text", folder, default_robot_config());
      }, py::arg("text"), py::arg("folder") = ".", "Parses bundle text; component files are read relative to folder.")
      .def("set", [](settings::Settings& s, const std::string& key, const py::object& value) -> settings::Settings& {
        s.set(key, yaml_value(value), "settings");
        return s;
      }, py::arg("key"), py::arg("value"), py::return_value_policy::reference_internal,
      R"(Sets the setting at key path `key` (str values are YAML text) and validates the bundle;
ValueError names an unknown key or a bad value. Returns the settings (calls chain).)")
      .def("update", [](settings::Settings& s, const py::dict& values) -> settings::Settings& {
        for (const auto& kv : values) s.set(py::str(kv.first), yaml_value(kv.second), "settings");
        return s;
      }, py::arg("values"), py::return_value_policy::reference_internal, "set() for each key: value of a dict, in order.")
      .def("to_yaml", &settings::Settings::to_yaml_text, "Every section inline: what settings.yaml holds.")
      .def("to_dict", [](const settings::Settings& s) { return yaml_to_py(s.to_yaml()); }, "Every section as nested dicts.")
      .def("get", [](const settings::Settings& s, const std::string& key) {
        YAML::Node node = s.to_yaml();
        std::size_t start = 0;
        for (;;) {
          const std::size_t dot = key.find('.', start);
          const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
          const YAML::Node& parent = node;  // const: a lookup must not add the key
          if (part.empty() || !parent.IsMap() || !parent[part])
            throw InputError("settings: unknown setting '" + key + "' (settings are named by key paths such as "
                             "mission.loop.views_per_stop)");
          node.reset(parent[part]);
          if (dot == std::string::npos) break;
          start = dot + 1;
        }
        return yaml_to_py(node);
      }, py::arg("key"), "The value at a key path (a section as a dict).")
      .def("save", [](const settings::Settings& s, const py::object& path) {
        write_file_atomic(path_from(path, "path"), s.to_yaml_text());
      },
           py::arg("path"), "Writes the bundle (a loadable --config) atomically.")
      .def("describe", [](const settings::Settings& s) {
        py::list out;
        for (const ParamDescription& d : s.describe())
          out.append(py::dict(py::arg("key") = d.key, py::arg("value") = d.value, py::arg("limits") = d.limits,
                              py::arg("help") = d.help));
        return out;
      }, "Every setting: key, value (YAML text), limits and help.")
      .def("copy", [](const settings::Settings& s) { return s; })
      .def("__eq__", [](const settings::Settings& a, const settings::Settings& b) { return a == b; }, py::is_operator())
      .def("__repr__", [](const settings::Settings& s) {
        return "<canopy.Settings method=" + s.method.name + " gain=" + s.method.gain + " rays=" + s.method.rays + ">";
      });
}

}  // namespace canopy::python

PYBIND11_MODULE(_canopy, m) {
  using namespace canopy::python;
  m.doc() = "canopy's C++ library (the canopy package re-exports it; help(canopy) for the overview).";
  m.attr("__version__") = CANOPY_VERSION;  // the package's version (CMakeLists.txt project())
  // The library's jobs log their steps at info level for the command line; Python hands
  // progress to callbacks, so only warnings and errors print (the module's own spdlog).
  spdlog::set_level(spdlog::level::warn);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const canopy::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const canopy::IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const canopy::Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    }
  });
  m.def("data_dir", &canopy::data_dir, "canopy's data folder (models/, configs/, worlds/), as every canopy program finds it.");
  // The output-place checks of every canopy command, for the package's Python writers (bags).
  m.def("_check_output", [](const py::object& path, const std::string& option, const std::string& kind) {
    const std::string p = path_from(path, option);
    canopy::check_output_place(p, option);
    if (!kind.empty()) canopy::StagedDir::check_writable(p, kind, option);
  }, py::arg("path"), py::arg("option"), py::arg("kind") = "",
  "ValueError unless an output may be written at path: not inside another canopy output folder (and, with kind, "
  "a folder that is absent, empty or canopy's output of that kind).");
  m.def("_check_disjoint_outputs", &canopy::check_disjoint_outputs, py::arg("outputs"),
        "ValueError when one of [(path, option)] is the same place as another or inside it.");
  bind_settings(m);
  bind_frames(m);
  bind_worlds(m);
  bind_maps(m);
  bind_planning(m);
  bind_python_planner(m);
  bind_missions(m);
  bind_records(m);
  bind_datasets(m);
}
