// canopy.Intrinsics, canopy.Frame (a labelled RGB-D frame; numpy views of its images) and
// canopy.read_frames (recorded sequences, as `canopy map --frames` reads them).

#include <pybind11/stl.h>

#include <cmath>
#include <limits>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/jobs/recorded_map_job.h"
#include "objects.h"

namespace canopy::python {

namespace {

static_assert(sizeof(Rgb8) == 3, "Rgb8 must be three packed bytes to be viewed as (H, W, 3)");

// A read-only numpy view of an image of `frame`, which `owner` (the Python Frame) keeps alive.
template <typename T>
py::object image_view(const Image<T>& image, const py::object& owner, int channels = 1) {
  if (image.empty()) return py::none();
  std::vector<py::ssize_t> shape = {image.height, image.width};
  if (channels > 1) shape.push_back(channels);
  using Elem = std::conditional_t<std::is_same_v<T, Rgb8>, std::uint8_t, T>;
  py::array_t<Elem> a(shape, reinterpret_cast<const Elem*>(image.data.data()), owner);
  a.attr("setflags")(py::arg("write") = false);
  return std::move(a);
}

// An image from a numpy array of the camera's size (copied). Integer images (labels, instances,
// rgb) must hold integers within their type's range: nothing wraps around silently.
template <typename T>
Image<T> image_from(const py::object& obj, const CameraIntrinsics& K, const std::string& what) {
  using Elem = std::conditional_t<std::is_same_v<T, Rgb8>, std::uint8_t, T>;
  Image<T> image;
  if (obj.is_none()) return image;
  const int channels = std::is_same_v<T, Rgb8> ? 3 : 1;
  const auto check_shape = [&](const py::array& a) {
    const bool shaped = a && a.ndim() == (channels == 3 ? 3 : 2) && a.shape(0) == K.height_px &&
                        a.shape(1) == K.width_px && (channels == 1 || a.shape(2) == 3);
    if (!shaped)
      throw InputError(what + ": " + describe(obj) + " is not an image of " + std::to_string(K.height_px) + " x " +
                       std::to_string(K.width_px) + (channels == 3 ? " x 3" : "") + " (the intrinsics' height x width)");
  };
  image = Image<T>(K.width_px, K.height_px);
  Elem* out = reinterpret_cast<Elem*>(image.data.data());
  // An array of the image's own type holds only valid values: copied as it is (no temporary
  // of doubles, which for a 4096 x 4096 RGB image would be 400 MB).
  if (py::array_t<Elem>::check_(obj)) {
    const auto a = py::array_t<Elem, py::array::c_style | py::array::forcecast>::ensure(obj);
    check_shape(a);
    std::copy(a.data(), a.data() + a.size(), out);
    return image;
  }
  using Source = std::conditional_t<std::is_floating_point_v<Elem>, Elem, double>;
  auto a = py::array_t<Source, py::array::c_style | py::array::forcecast>::ensure(obj);
  check_shape(a);
  const Source* in = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if constexpr (!std::is_floating_point_v<Elem>) {
      constexpr double lo = std::numeric_limits<Elem>::min(), hi = std::numeric_limits<Elem>::max();
      if (!(in[i] == std::floor(in[i]) && in[i] >= lo && in[i] <= hi))
        throw InputError(what + ": value " + py::repr(py::float_(in[i])).cast<std::string>() + " is not an integer in [" +
                         std::to_string(static_cast<long long>(lo)) + ", " + std::to_string(static_cast<long long>(hi)) + "]");
    }
    out[i] = static_cast<Elem>(in[i]);
  }
  return image;
}

// A Python record (dicts, lists, str, bool, int, float, None) as YAML, for run.yaml.
YAML::Node yaml_from(const py::handle& obj, const std::string& what) {
  YAML::Node n;
  if (obj.is_none()) return n;
  if (py::isinstance<py::bool_>(obj)) return YAML::Node(obj.cast<bool>());
  if (py::isinstance<py::int_>(obj)) return YAML::Node(obj.cast<long long>());
  if (py::isinstance<py::float_>(obj)) return YAML::Node(obj.cast<double>());
  if (py::isinstance<py::str>(obj)) return YAML::Node(obj.cast<std::string>());
  if (py::isinstance<py::dict>(obj)) {
    for (const auto& kv : obj.cast<py::dict>()) n[py::str(kv.first).cast<std::string>()] = yaml_from(kv.second, what);
    return n;
  }
  if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
    for (const auto& v : obj) n.push_back(yaml_from(v, what));
    return n;
  }
  throw InputError(what + ": " + describe(obj) + " is not a dict, list, str, bool or number");
}

// The frames map_frames hands to the job, one at a time, from a list or any iterable (a
// generator over a bag: memory then holds one frame, not the recording). The next frame is
// made (by Python, GIL held) when the job asks whether to go on, before each frame: a
// KeyboardInterrupt raised while Python makes it stops the job as Ctrl-C does.
class FrameFeed {
 public:
  FrameFeed(const py::object& frames, std::size_t count) : it_(py::iter(frames)), count_(count) {}
  ~FrameFeed() {
    py::gil_scoped_acquire gil;
    next_ = py::object();
    it_ = py::iterator();
  }

  // GIL held. Makes the next frame unless it is made or all are taken; Python's exceptions
  // propagate (py::error_already_set).
  void fetch() {
    if (next_ || taken_ == count_) return;
    PyObject* item = PyIter_Next(it_.ptr());
    if (!item) {
      if (PyErr_Occurred()) throw py::error_already_set();
      throw InputError("frames: the iterable ended after " + std::to_string(taken_) + " of " + std::to_string(count_) +
                       " frames (count)");
    }
    next_ = py::reinterpret_steal<py::object>(item);
    if (!py::isinstance<PyFrame>(next_))
      throw InputError("frames: item " + std::to_string(taken_) + ", " + describe(next_) + ", is not a canopy.Frame");
  }

  // GIL held. The next frame (moved out when nothing else holds it, copied otherwise).
  void take(LabelledFrame* f) {
    fetch();
    const auto frame = next_.cast<std::shared_ptr<PyFrame>>();
    names_.push_back(frame->name.empty() ? "frame " + std::to_string(taken_) : frame->name);
    if (next_.ref_count() == 1 && frame.use_count() <= 2) *f = std::move(frame->frame);
    else *f = frame->frame;
    next_ = py::object();
    ++taken_;
  }

  const std::string& name(std::size_t i) const { return names_.at(i); }

 private:
  py::iterator it_;
  std::size_t count_;
  std::size_t taken_ = 0;
  py::object next_;
  std::vector<std::string> names_;
};

// canopy.Intrinsics(...): the camera model, checked as a recorded camera's.
CameraIntrinsics make_intrinsics(int width_px, int height_px, double fx_px, double fy_px, double cx_px, double cy_px,
                                 double min_range_m, double max_range_m) {
  CameraIntrinsics K;
  K.width_px = width_px;
  K.height_px = height_px;
  K.fx_px = fx_px;
  K.fy_px = fy_px;
  K.cx_px = cx_px;
  K.cy_px = cy_px;
  K.min_range_m = min_range_m;
  K.max_range_m = max_range_m;
  datasets::validate_recorded_intrinsics(K, "Intrinsics");
  return K;
}

// Metres per depth unit: 1 for float depth; an integer depth image (a sensor's uint16
// millimetres) taken as metres would put every point 1000 times too far, so its unit must be given.
double depth_scale_of(const py::object& depth, const py::object& depth_scale) {
  double scale = 1.0;
  if (!depth_scale.is_none()) {
    scale = py::cast<double>(depth_scale);
    if (!(std::isfinite(scale) && scale > 0.0 && scale <= 1e3))
      throw InputError("depth_scale: value " + py::repr(depth_scale).cast<std::string>() +
                       " must be metres per depth unit in (0, 1000] (0.001 for millimetres)");
  }
  const py::array as_array = py::array::ensure(depth);
  const char kind = as_array ? as_array.dtype().kind() : 'f';
  if ((kind == 'i' || kind == 'u' || kind == 'b') && depth_scale.is_none())
    throw InputError("depth: an integer depth image (dtype " + py::str(as_array.dtype()).cast<std::string>() +
                     ") needs depth_scale, its unit in metres (0.001 for millimetres); canopy does not guess it");
  return scale;
}

// canopy.Frame(...): a frame from arrays (copied).
PyFrame make_frame(const py::object& depth, const py::object& pose, const py::object& intrinsics,
                   const py::object& labels, const py::object& rgb, const py::object& instances,
                   const py::object& depth_scale, const std::string& name) {
  PyFrame f;
  f.name = name;
  f.frame.intrinsics = intrinsics_from(intrinsics, CameraIntrinsics{});
  f.frame.T_world_camera = pose_from(pose, "pose");
  const double scale = depth_scale_of(depth, depth_scale);
  f.frame.depth_m = image_from<float>(depth, f.frame.intrinsics, "depth");
  if (scale != 1.0)
    for (float& d : f.frame.depth_m.data) d = static_cast<float>(d * scale);
  f.frame.class_id = image_from<std::uint8_t>(labels, f.frame.intrinsics, "labels");
  f.frame.rgb = image_from<Rgb8>(rgb, f.frame.intrinsics, "rgb");
  f.frame.instance = image_from<std::int32_t>(instances, f.frame.intrinsics, "instances");
  if (f.frame.depth_m.empty()) throw InputError("depth: a frame needs a depth image");
  return f;
}

// canopy.read_frames: a recorded sequence read as `canopy map --frames` reads it.
py::dict read_frames(const py::object& folder_arg, bool labels, const py::object& intrinsics_file,
                     const py::object& label_colors, double max_dt_s) {
  const std::string folder = path_from(folder_arg, "folder");
  if (!(std::isfinite(max_dt_s) && max_dt_s > 0.0))
    throw InputError("max_dt: " + std::to_string(max_dt_s) + " is not a positive number of seconds");
  datasets::FrameReaderOptions options;
  options.label_images = labels;
  if (!intrinsics_file.is_none()) options.intrinsics_file = path_from(intrinsics_file, "intrinsics");
  if (!label_colors.is_none()) options.label_colors_file = path_from(label_colors, "label_colors");
  options.max_time_diff_s = max_dt_s;
  std::vector<PyFrame> frames;
  std::vector<datasets::SkippedFrame> skipped;
  SemanticClasses classes;
  {
    py::gil_scoped_release release;
    const datasets::FrameSequence seq = datasets::FrameSequence::open(find_data_file(folder), options);
    classes = seq.classes();
    skipped = seq.skipped();
    for (std::size_t i = 0; i < seq.size(); ++i) {
      PyFrame f;
      f.name = seq.name(i);
      std::string why;
      if (seq.read(i, &f.frame, &why)) frames.push_back(std::move(f));
      else skipped.push_back({seq.name(i), why});
    }
  }
  py::list out;
  for (PyFrame& f : frames) out.append(frame_object(std::move(f)));
  py::list skipped_out;
  for (const auto& s : skipped) skipped_out.append(py::dict(py::arg("frame") = s.name, py::arg("reason") = s.reason));
  return py::dict(py::arg("frames") = out, py::arg("skipped") = skipped_out, py::arg("classes") = classes.names);
}

// Class names from Python (None: canopy's).
SemanticClasses classes_from(const py::object& classes) {
  SemanticClasses c;
  if (classes.is_none()) return c;
  try {
    c.names = classes.cast<std::vector<std::string>>();
  } catch (const py::cast_error&) {
    throw InputError("classes: " + describe(classes) + " is not a list of class names");
  }
  return c;
}

// canopy.class_colors: each class's drawing colour.
py::array_t<std::uint8_t> class_colors(const py::object& classes) {
  SemanticClasses c = classes_from(classes);
  if (c.index_of(c.target) < 0 && !c.names.empty()) c.target = c.names.back();  // colours need no target
  c.validate("classes");
  py::array_t<std::uint8_t> a({static_cast<py::ssize_t>(c.size()), py::ssize_t{3}});
  for (int i = 0; i < c.size(); ++i) {
    const Rgb8 rgb = c.color(i);
    a.mutable_at(i, 0) = rgb.r;
    a.mutable_at(i, 1) = rgb.g;
    a.mutable_at(i, 2) = rgb.b;
  }
  return a;
}

// How many frames map_frames takes: a list is checked whole before any work; an iterable (a
// generator) says how many frames it yields (count=), and each is checked when it comes.
std::size_t frame_count(const py::object& frames, const py::object& count_arg) {
  const std::uint64_t given = count_arg.is_none() ? 0 : seed_from(count_arg, "count");
  if (py::hasattr(frames, "__len__")) {
    const std::size_t count = py::len(frames);
    if (!count_arg.is_none() && given != count)
      throw InputError("count: " + describe(count_arg) + " is not the number of frames (" + std::to_string(count) + ")");
    std::size_t i = 0;
    for (const py::handle& f : frames) {
      if (!py::isinstance<PyFrame>(f))
        throw InputError("frames: item " + std::to_string(i) + ", " + describe(f) + ", is not a canopy.Frame");
      ++i;
    }
    return count;
  }
  if (!py::hasattr(frames, "__iter__"))
    throw InputError("frames: " + describe(frames) + " is not a list or an iterable of canopy.Frame");
  if (count_arg.is_none())
    throw InputError("count: an iterable of frames (a generator) needs count=, the number of frames it yields");
  return static_cast<std::size_t>(given);
}

// The sequence map_frames hands to the job: the frames from `feed`, their classes, and what
// frames.json and run.yaml record.
jobs::RecordedSequence frame_sequence(FrameFeed& feed, std::size_t count, const py::object& classes,
                                      const py::object& run, const py::object& skipped, const py::object& notes) {
  jobs::RecordedSequence seq;
  seq.source = "frames";
  if (!classes.is_none()) seq.classes.names = classes_from(classes).names;
  seq.classes.validate("classes");
  seq.size = count;
  seq.name = [&feed](std::size_t i) { return feed.name(i); };
  seq.read = [&feed](std::size_t, LabelledFrame* f, std::string*) {
    py::gil_scoped_acquire gil;
    feed.take(f);
    return true;
  };
  if (!skipped.is_none())
    for (const py::handle& s : skipped) {
      const py::dict d = py::reinterpret_borrow<py::object>(s).cast<py::dict>();
      seq.skipped.push_back({py::str(d["frame"]).cast<std::string>(), py::str(d["reason"]).cast<std::string>()});
    }
  if (!notes.is_none()) seq.notes = notes.cast<std::vector<std::string>>();
  seq.run = yaml_from(run, "run");
  return seq;
}

// Ctrl-C during map_frames: Python's handler only sets a flag while the job runs without the
// GIL; it is polled before each frame, and noted when the progress callback or the making of
// the next frame raised KeyboardInterrupt (the frames so far are published, marked incomplete,
// and KeyboardInterrupt raised).
struct InterruptNote {
  bool interrupted = false;
  template <class F>
  void run(F&& f) {
    try {
      f();
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_KeyboardInterrupt)) throw;
      interrupted = true;
    }
  }
};

// canopy.map_frames: recorded frames mapped into a run folder (jobs::map_recorded).
py::dict map_frames(const py::object& frames, const py::object& out, const py::object& settings,
                    const py::object& classes, const py::object& run, const py::object& skipped,
                    const py::object& notes, const py::object& progress, const py::object& count_arg) {
  jobs::RecordedMapParams job;
  job.settings = settings_from(settings);
  job.out = path_from(out, "out");
  job.out_option = "out";
  StagedDir::check_writable(job.out, "map", "out");
  const std::size_t count = frame_count(frames, count_arg);
  FrameFeed feed(frames, count);
  const jobs::RecordedSequence seq = frame_sequence(feed, count, classes, run, skipped, notes);
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    throw InputError("progress: " + describe(progress) + " is not callable");
  InterruptNote note;
  if (!progress.is_none())
    job.on_frame = [&progress, &note](const mapping::FrameMapStep& s) {
      py::gil_scoped_acquire gil;
      note.run([&] {
        progress(s.mapped ? "frame " + s.name + ": " + std::to_string(s.extract.points) + " points"
                          : "frame " + s.name + ": skipped (" + s.skip_reason + ")");
      });
    };
  job.stop_requested = [&note, &feed] {
    if (note.interrupted) return true;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      return note.interrupted = true;
    }
    note.run([&] { feed.fetch(); });
    return note.interrupted;
  };
  jobs::RecordedMapResult r;
  {
    py::gil_scoped_release release;
    r = jobs::map_recorded(seq, job);
  }
  return py::dict(py::arg("mapped") = r.mapped, py::arg("skipped") = r.skipped,
                  py::arg("occupied_voxels") = r.occupied_voxels);
}

void bind_intrinsics(py::module_& m) {
  const CameraIntrinsics d;
  py::class_<CameraIntrinsics>(m, "Intrinsics", R"(Pinhole camera intrinsics and valid depth range.

Optical frame: x right, y down, z forward; pixel (i, j) has its centre at (i + 0.5, j + 0.5).
Defaults are the wrist camera of configs (RealSense D405 at 400 x 400).)")
      .def(py::init(&make_intrinsics), py::arg("width_px") = d.width_px, py::arg("height_px") = d.height_px,
           py::arg("fx_px") = d.fx_px, py::arg("fy_px") = d.fy_px, py::arg("cx_px") = d.cx_px,
           py::arg("cy_px") = d.cy_px, py::arg("min_range_m") = d.min_range_m, py::arg("max_range_m") = d.max_range_m,
           "Intrinsics; ValueError names a value out of range.")
      .def_readonly("width_px", &CameraIntrinsics::width_px)
      .def_readonly("height_px", &CameraIntrinsics::height_px)
      .def_readonly("fx_px", &CameraIntrinsics::fx_px)
      .def_readonly("fy_px", &CameraIntrinsics::fy_px)
      .def_readonly("cx_px", &CameraIntrinsics::cx_px)
      .def_readonly("cy_px", &CameraIntrinsics::cy_px)
      .def_readonly("min_range_m", &CameraIntrinsics::min_range_m)
      .def_readonly("max_range_m", &CameraIntrinsics::max_range_m)
      .def("__repr__", [](const CameraIntrinsics& K) {
        return "canopy.Intrinsics(width_px=" + std::to_string(K.width_px) + ", height_px=" +
               std::to_string(K.height_px) + ", fx_px=" + py::repr(py::float_(K.fx_px)).cast<std::string>() + ")";
      });
}

void bind_frame(py::module_& m) {
  py::class_<PyFrame, std::shared_ptr<PyFrame>>(m, "Frame", R"(A labelled RGB-D frame: what the renderer (or a camera and a segmenter) hands to mapping.

The image attributes are read-only numpy views of the frame's memory; an array keeps its
frame alive, so it stays valid after the frame object is deleted.)")
      .def(py::init(&make_frame), py::arg("depth"), py::arg("pose"), py::arg("intrinsics") = py::none(),
           py::arg("labels") = py::none(), py::arg("rgb") = py::none(), py::arg("instances") = py::none(),
           py::kw_only(), py::arg("depth_scale") = py::none(), py::arg("name") = "",
           R"(A frame from arrays (copied).

depth: (H, W) planar z-depth [m], 0 where invalid; an integer depth image (a sensor's uint16)
needs depth_scale, metres per unit (0.001 for millimetres), and is refused without it;
pose: 4x4 T_world_camera (optical frame);
intrinsics: canopy.Intrinsics (default: the D405 of configs); labels: (H, W) class indices
(uint8); rgb: (H, W, 3) uint8; instances: (H, W) fruit instance ids (int32, -1 = none).
name: the frame's name in its sequence (frames.json of canopy.map_frames).
Which of labels / rgb a map needs depends on its settings' mapping.extractor.source
(truth: labels, color: rgb).)")
      .def_readonly("name", &PyFrame::name, "The frame's name in its sequence ('' when rendered or built).")
      .def_property_readonly("pose", [](const PyFrame& f) { return pose_array(f.frame.T_world_camera); },
                             "4x4 T_world_camera (a copy).")
      .def_property_readonly("intrinsics", [](const PyFrame& f) { return f.frame.intrinsics; })
      .def_property_readonly("depth", [](const py::object& self) {
        return image_view(self.cast<const PyFrame&>().frame.depth_m, self);
      }, "(H, W) float32 planar depth [m]; 0 = invalid.")
      .def_property_readonly("labels", [](const py::object& self) {
        return image_view(self.cast<const PyFrame&>().frame.class_id, self);
      }, "(H, W) uint8 class indices, or None.")
      .def_property_readonly("rgb", [](const py::object& self) {
        return image_view(self.cast<const PyFrame&>().frame.rgb, self, 3);
      }, "(H, W, 3) uint8, or None.")
      .def_property_readonly("instances", [](const py::object& self) {
        return image_view(self.cast<const PyFrame&>().frame.instance, self);
      }, "(H, W) int32 fruit instance ids (-1 = none), or None.");
}

void bind_frame_functions(py::module_& m) {
  m.def("read_frames", &read_frames, py::arg("folder"), py::arg("labels") = false, py::arg("intrinsics") = py::none(),
        py::arg("label_colors") = py::none(), py::arg("max_dt") = datasets::FrameReaderOptions{}.max_time_diff_s,
        R"(Reads a recorded sequence as `canopy map --frames` does.

folder: canopy frame folders (what `canopy render` writes) or a TUM RGB-D folder; labels: read
the label images too; intrinsics: TUM camera YAML (default folder/camera.yaml); label_colors:
class-colour table YAML; max_dt: TUM pairing tolerance [s].
Returns {"frames": [Frame], "skipped": [{"frame", "reason"}], "classes": [names]}.)");

  m.def("class_colors", &class_colors, py::arg("classes") = py::none(),
        "The drawing colour of each class ((K, 3) uint8: label images, map.ply); classes: names (default: canopy's).");

  m.def("map_frames", &map_frames, py::arg("frames"), py::arg("out"), py::arg("settings") = py::none(), py::kw_only(),
        py::arg("classes") = py::none(), py::arg("run") = py::none(), py::arg("skipped") = py::none(),
        py::arg("notes") = py::none(), py::arg("progress") = py::none(), py::arg("count") = py::none(),
        R"(Maps recorded frames into the run folder `canopy map --frames` writes.

frames: canopy.Frame objects, mapped in order with the settings' frame step (colour
segmentation of their rgb, or their labels with mapping.extractor.source: truth): a list, or
any iterable (a generator making one frame at a time, as canopy.bag.map_bag streams a bag)
with count=, the number of frames it yields; out: the folder (map.csm, map.ply, map.bt,
frames.json, run.yaml, settings.yaml; written and published as every canopy output folder);
classes: the label classes (default: canopy's); run: what run.yaml records (a dict); skipped,
notes: frames dropped before mapping ({'frame', 'reason'}) and the reader's notes, for
frames.json; progress: called with a line per frame. An exception of the iterable ends the
call with nothing written. Ctrl-C publishes the frames mapped so far (frames.json "complete":
false) and raises KeyboardInterrupt. Returns {'mapped', 'skipped', 'occupied_voxels'}.)");
}

}  // namespace

py::object frame_object(PyFrame frame) { return py::cast(std::make_shared<PyFrame>(std::move(frame))); }

void bind_frames(py::module_& m) {
  bind_intrinsics(m);
  bind_frame(m);
  bind_frame_functions(m);
}

}  // namespace canopy::python
