// canopy.decode_class_colors and canopy.nearest_stamps (datasets.h).

#include "datasets.h"

#include <cmath>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/datasets/frame_sequence.h"

namespace canopy::python {

namespace {

using Bytes = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

py::array_t<std::uint8_t> decode_class_colors(const Bytes& rgb, const Bytes& colors, const std::string& where) {
  if (rgb.ndim() != 3 || rgb.shape(2) != 3)
    throw InputError(where + ": a colour label image must be (H, W, 3) uint8, got " + describe(rgb));
  if (colors.ndim() != 2 || colors.shape(1) != 3 || colors.shape(0) < 1 || colors.shape(0) > 255)
    throw InputError("colors: must be (N, 3) uint8 with 1 <= N <= 255, got " + describe(colors));
  datasets::ClassColorTable table;
  for (py::ssize_t i = 0; i < colors.shape(0); ++i) table.colors.push_back({colors.at(i, 0), colors.at(i, 1), colors.at(i, 2)});
  const int h = static_cast<int>(rgb.shape(0)), w = static_cast<int>(rgb.shape(1));
  Image<Rgb8> image(w, h);
  const std::uint8_t* p = rgb.data();
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i, p += 3) image.at(i, j) = {p[0], p[1], p[2]};
  const Image<std::uint8_t> ids = table.decode(image, where);
  py::array_t<std::uint8_t> out({py::ssize_t{h}, py::ssize_t{w}});
  std::copy(ids.data.begin(), ids.data.end(), out.mutable_data());
  return out;
}

py::array_t<long> nearest_stamps(const py::handle& sorted, const py::handle& t, double max_dt) {
  const Doubles s = finite_doubles(sorted, "sorted"), q = finite_doubles(t, "t");
  if (s.ndim() != 1 || q.ndim() != 1) throw InputError("sorted and t must be 1-D arrays of times");
  if (std::isnan(max_dt) || max_dt < 0.0) throw InputError("max_dt must be >= 0 (inf: any distance), got " + std::to_string(max_dt));
  const std::vector<double> times(s.data(), s.data() + s.shape(0));
  for (std::size_t i = 1; i < times.size(); ++i)
    if (times[i] < times[i - 1]) throw InputError("sorted: times must not decrease (index " + std::to_string(i) + ")");
  py::array_t<long> out(q.shape(0));
  for (py::ssize_t i = 0; i < q.shape(0); ++i) out.mutable_at(i) = datasets::nearest_timestamp(times, q.at(i), max_dt);
  return out;
}

}  // namespace

void bind_datasets(py::module_& m) {
  m.def("decode_class_colors", &decode_class_colors, py::arg("rgb"), py::arg("colors"), py::arg("where") = "labels",
        R"(Class index of each pixel of a colour label image, as `canopy map --frames` decodes one
(datasets::ClassColorTable::decode): rgb (H, W, 3) uint8; colors (N, 3) uint8, class i's colour
in row i (canopy.class_colors). Returns (H, W) uint8. ValueError naming `where`, the colour and
the pixel when a colour is no class's.)");
  m.def("nearest_stamps", &nearest_stamps, py::arg("sorted"), py::arg("t"), py::arg("max_dt") = std::numeric_limits<double>::infinity(),
        R"(For each time of t, the index of the nearest time in `sorted` (non-decreasing) within max_dt,
else -1; of two equally near, the earlier. The pairing rule of recorded frames
(datasets::nearest_timestamp): a TUM sequence's poses, a bag's RGB, label and camera_info messages.)");
}

}  // namespace canopy::python
