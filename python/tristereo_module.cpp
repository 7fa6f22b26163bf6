// Python bindings of tristereo (pybind11 + NumPy): the pipeline, the
// bit-exactness check and the calibration readers. Parameters are keyword
// arguments named like the command line's options (dmin, window, lambda_q4...).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "tristereo/calib.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"
#include "tristereo/verify.hpp"
#include "tristereo/version.hpp"

namespace py = pybind11;
using namespace tristereo;

namespace {

// ---------------------------------------------------------------- parameters

struct RunOptions {
  int threads = 0;
  KernelChoice kernels = KernelChoice::kAuto;
};

const char* kKnownKeys =
    "dmin, dense, psnr, max_area, min_area, window, weights, truncation, asw_gamma_color, "
    "asw_gamma_proximity, lambda_q4, gap, subpixel, threads, kernels";

// The model's parameters from keyword arguments; range checks stay with
// validate_params() (called by Pipeline.configure), so the messages are the
// library's own.
StereoParams params_from_kwargs(int ndisp, const py::kwargs& kw, RunOptions* run) {
  StereoParams p;
  p.num_disp = ndisp;
  for (const auto& item : kw) {
    const std::string key = py::str(item.first);
    const py::handle v = item.second;
    if (key == "dmin") p.d_min = v.cast<int>();
    else if (key == "dense") p.dense = v.cast<bool>();
    else if (key == "psnr") p.tritree.psnr_deci_db = static_cast<int>(std::lround(v.cast<double>() * 10));
    else if (key == "max_area") p.tritree.max_area_px2 = v.cast<int>();
    else if (key == "min_area") p.tritree.min_area_px2 = v.cast<int>();
    else if (key == "window") {
      if (py::isinstance<py::int_>(v)) {
        p.cost.window_w = p.cost.window_h = v.cast<int>();
      } else {
        const auto wh = v.cast<std::pair<int, int>>();
        p.cost.window_w = wh.first;
        p.cost.window_h = wh.second;
      }
    } else if (key == "weights") p.cost.weights = parse_weights(v.cast<std::string>());
    else if (key == "truncation") p.cost.truncation = v.cast<int>();
    else if (key == "asw_gamma_color") p.cost.asw_gamma_color = v.cast<int>();
    else if (key == "asw_gamma_proximity") p.cost.asw_gamma_proximity = v.cast<int>();
    else if (key == "lambda_q4") p.dp.lambda_q4 = v.cast<int>();
    else if (key == "gap") p.dp.gap = parse_gap_policy(v.cast<std::string>());
    else if (key == "subpixel") p.dp.subpixel = v.cast<bool>();
    else if (key == "threads" && run) run->threads = v.cast<int>();
    else if (key == "kernels" && run) run->kernels = parse_kernel_choice(v.cast<std::string>());
    else throw py::type_error("unexpected keyword argument '" + key + "' (known: " + kKnownKeys + ")");
  }
  return p;
}

// ---------------------------------------------------------------- images

// A uint8 array, (H, W) gray or (H, W, 3) RGB, as a view. Rows may lie at any
// distance (padded rows, a crop of a bigger array): no copy as long as each
// row's pixels are packed; any other layout (e.g. every second column) is
// copied once into `copy`.
struct InputImage {
  ImageU8 copy;
  ImageView<const std::uint8_t> view;
};

InputImage as_image(const py::array& a, const char* name) {
  if (!py::isinstance<py::array_t<std::uint8_t>>(a) || a.dtype().kind() != 'u' || a.itemsize() != 1)
    throw py::value_error(std::string(name) + " must be a uint8 array, got dtype " +
                          std::string(py::str(a.dtype())));
  if (a.ndim() != 2 && !(a.ndim() == 3 && a.shape(2) == 3))
    throw py::value_error(std::string(name) + " must have shape (H, W) or (H, W, 3), got ndim " +
                          std::to_string(a.ndim()) + (a.ndim() == 3 ? " with " + std::to_string(a.shape(2)) + " channels" : ""));
  const py::ssize_t h = a.shape(0), w = a.shape(1);
  const int c = a.ndim() == 3 ? 3 : 1;
  if (h > kMaxImageSide || w > kMaxImageSide)
    throw py::value_error(std::string(name) + " is " + std::to_string(w) + "x" + std::to_string(h) +
                          ", above the largest side " + std::to_string(kMaxImageSide));
  InputImage in;
  const bool packed_rows = a.strides(1) == c && (c == 1 || a.strides(2) == 1) && a.strides(0) > 0;
  if (packed_rows) {
    in.view = {static_cast<const std::uint8_t*>(a.data()), static_cast<int>(w), static_cast<int>(h), c,
               static_cast<std::ptrdiff_t>(a.strides(0))};
    return in;
  }
  in.copy = ImageU8(static_cast<int>(w), static_cast<int>(h), c);
  const auto* base = static_cast<const std::uint8_t*>(a.data());
  for (py::ssize_t y = 0; y < h; ++y)
    for (py::ssize_t x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k)
        in.copy.row(static_cast<int>(y))[x * c + k] =
            base[y * a.strides(0) + x * a.strides(1) + (c == 3 ? k * a.strides(2) : 0)];
  in.view = in.copy.view();
  return in;
}

ImageU8 owned_image(const py::array& a, const char* name) {
  const InputImage in = as_image(a, name);
  ImageU8 img(in.view.width, in.view.height, in.view.channels);
  for (int y = 0; y < img.height; ++y)
    std::memcpy(img.row(y), in.view.row(y), static_cast<std::size_t>(img.width) * img.channels);
  return img;
}

// A str or os.PathLike as a path.
std::string path_of(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path));
}

// ---------------------------------------------------------------- outputs

struct Output {
  py::array_t<float> disparity;
  py::array_t<std::int16_t> disp_q4;
  py::array_t<std::int32_t> vertices;
  py::array_t<std::int32_t> triangles;
  py::array_t<std::int16_t> vertex_disp_q4;
  py::dict timings_ms;
  std::int64_t forced_splits = 0;
  std::int64_t criterion_splits = 0;
  std::string digest;
};

Output make_output(const StereoOutput& o, const FrameTimings& t) {
  Output r;
  const int w = o.disp_q4.width, h = o.disp_q4.height;
  r.disp_q4 = py::array_t<std::int16_t>({h, w});
  r.disparity = py::array_t<float>({h, w});
  auto q = r.disp_q4.mutable_unchecked<2>();
  auto f = r.disparity.mutable_unchecked<2>();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::int16_t v = o.disp_q4.at(x, y);
      q(y, x) = v;
      f(y, x) = v == kInvalidDispQ4 ? std::numeric_limits<float>::quiet_NaN() : v / 16.0f;
    }
  const auto nv = static_cast<py::ssize_t>(o.mesh.vertices.size());
  const auto nt = static_cast<py::ssize_t>(o.mesh.triangles.size());
  r.vertices = py::array_t<std::int32_t>({nv, py::ssize_t{2}});
  r.triangles = py::array_t<std::int32_t>({nt, py::ssize_t{3}});
  r.vertex_disp_q4 = py::array_t<std::int16_t>(nv);
  auto vv = r.vertices.mutable_unchecked<2>();
  auto tt = r.triangles.mutable_unchecked<2>();
  auto vd = r.vertex_disp_q4.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < nv; ++i) {
    vv(i, 0) = o.mesh.vertices[i].x;
    vv(i, 1) = o.mesh.vertices[i].y;
    vd(i) = o.vertex_disp_q4[i];
  }
  for (py::ssize_t i = 0; i < nt; ++i)
    for (int k = 0; k < 3; ++k) tt(i, k) = o.mesh.triangles[i][k];
  r.timings_ms["tritree"] = t.tritree_ns / 1e6;
  r.timings_ms["cost_aggregation"] = t.cost_aggregation_ns / 1e6;
  r.timings_ms["dp"] = t.dp_ns / 1e6;
  r.timings_ms["fill"] = t.fill_ns / 1e6;
  r.timings_ms["interpolation"] = t.interpolation_ns / 1e6;
  r.timings_ms["total"] = t.total_ns / 1e6;
  r.forced_splits = o.mesh.forced_splits;
  r.criterion_splits = o.mesh.criterion_splits;
  r.digest = digest_hex(o);
  return r;
}

// ---------------------------------------------------------------- pipeline

class PyPipeline {
 public:
  PyPipeline(int max_width, int max_height, int ndisp, const py::kwargs& kw) {
    RunOptions run;
    PipelineConfig c;
    c.max_width = max_width;
    c.max_height = max_height;
    c.params = params_from_kwargs(ndisp, kw, &run);
    c.threads = run.threads;
    c.kernels = run.kernels;
    pipeline_.configure(c);
  }

  Output process(const py::array& left, const py::array& right) {
    const InputImage l = as_image(left, "left");
    const InputImage r = as_image(right, "right");
    const StereoOutput* out = nullptr;
    FrameTimings timings;
    {
      // The frame runs without the GIL; one frame at a time per Pipeline.
      py::gil_scoped_release nogil;
      std::lock_guard<std::mutex> lock(mutex_);
      out = &pipeline_.process(l.view, r.view);
      timings = pipeline_.last_timings();
      return_copy_ = *out;  // the next process() may overwrite *out
    }
    return make_output(return_copy_, timings);
  }

  std::string kernels() const { return to_string(pipeline_.active_kernels()); }
  int threads() const { return pipeline_.worker_count(); }
  std::size_t working_memory_bytes() const { return pipeline_.working_memory_bytes(); }

 private:
  Pipeline pipeline_;
  std::mutex mutex_;
  StereoOutput return_copy_;
};

void translate_errors(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const Error& e) {
    switch (e.code()) {
      case ErrorCode::kInvalidArgument:
      case ErrorCode::kSizeMismatch:
      case ErrorCode::kUnsupportedFormat:
      case ErrorCode::kCorruptFile:
        PyErr_SetString(PyExc_ValueError, e.what());
        return;
      case ErrorCode::kIoError:
        PyErr_SetString(PyExc_OSError, e.what());
        return;
      default:
        PyErr_SetString(PyExc_RuntimeError, e.what());
        return;
    }
  }
}

}  // namespace

PYBIND11_MODULE(_tristereo, m) {
  m.doc() = "tristereo: fixed-point stereo on a tritree mesh";
  py::register_exception_translator(&translate_errors);
  m.attr("__version__") = kVersionString;
  m.attr("INVALID_DISP_Q4") = kInvalidDispQ4;

  py::class_<Output>(m, "Output", "What one frame produced (copies; valid after the next frame).")
      .def_readonly("disparity", &Output::disparity, "float32 (H, W), pixels, NaN = invalid")
      .def_readonly("disp_q4", &Output::disp_q4, "int16 (H, W), disparity * 16, INVALID_DISP_Q4 = invalid")
      .def_readonly("vertices", &Output::vertices, "int32 (N, 2): x, y of the mesh vertices (the samples)")
      .def_readonly("triangles", &Output::triangles, "int32 (M, 3): vertex indices")
      .def_readonly("vertex_disp_q4", &Output::vertex_disp_q4, "int16 (N,): the samples' disparities * 16")
      .def_readonly("timings_ms", &Output::timings_ms, "per-stage wall time of this frame, ms")
      .def_readonly("forced_splits", &Output::forced_splits)
      .def_readonly("criterion_splits", &Output::criterion_splits)
      .def_readonly("digest", &Output::digest, "64-bit FNV-1a digest of mesh, samples and dense map (hex)");

  py::class_<PyPipeline>(m, "Pipeline",
                         "Pipeline(max_width, max_height, ndisp=64, **params): configure once (all memory "
                         "allocated, workers started), then process(left, right) per frame.")
      .def(py::init<int, int, int, const py::kwargs&>(), py::arg("max_width"), py::arg("max_height"),
           py::arg("ndisp") = 64)
      .def("process", &PyPipeline::process, py::arg("left"), py::arg("right"),
           "left, right: uint8 arrays (H, W) or (H, W, 3), equal sizes; releases the GIL while it runs")
      .def_property_readonly("kernels", &PyPipeline::kernels)
      .def_property_readonly("threads", &PyPipeline::threads)
      .def_property_readonly("working_memory_bytes", &PyPipeline::working_memory_bytes,
                             "bytes the configured pipeline allocated (docs/performance.md)");

  py::class_<VerifyReport>(m, "VerifyReport")
      .def_readonly("bit_exact", &VerifyReport::bit_exact)
      .def_readonly("reference_digest", &VerifyReport::reference_digest)
      .def_property_readonly("cases", [](const VerifyReport& r) {
        py::list cases;
        for (const VerifyCase& c : r.cases)
          cases.append(py::dict(py::arg("kernels") = to_string(c.kernels), py::arg("threads") = c.threads,
                                py::arg("identical") = c.identical,
                                py::arg("first_difference") = c.first_difference));
        return cases;
      });
  m.def(
      "verify",
      [](const py::array& left, const py::array& right, int ndisp, std::vector<int> thread_counts,
         const py::kwargs& kw) {
        const ImageU8 l = owned_image(left, "left"), r = owned_image(right, "right");
        const StereoParams p = params_from_kwargs(ndisp, kw, nullptr);
        py::gil_scoped_release nogil;
        return verify_bit_exact(l, r, p, thread_counts);
      },
      py::arg("left"), py::arg("right"), py::arg("ndisp") = 64, py::arg("thread_counts") = std::vector<int>{},
      "The float reference against every kernel set this CPU runs, at several thread counts.");

  m.def(
      "read_image",
      [](const py::object& path) {
        const ImageU8 img = read_image_u8(path_of(path));
        std::vector<py::ssize_t> shape = {img.height, img.width};
        if (img.channels == 3) shape.push_back(3);
        py::array_t<std::uint8_t> a(shape);
        auto* dst = static_cast<std::uint8_t*>(a.mutable_data());
        const std::size_t row = static_cast<std::size_t>(img.width) * img.channels;
        for (int y = 0; y < img.height; ++y) std::memcpy(dst + y * row, img.row(y), row);
        return a;
      },
      py::arg("path"), "An 8-bit PNG/PGM/PPM as uint8 (H, W) or (H, W, 3).");

  py::class_<StereoCalibration>(m, "Calibration")
      .def_readonly("focal_px", &StereoCalibration::focal_px)
      .def_readonly("baseline_m", &StereoCalibration::baseline_m)
      .def_readonly("cx_px", &StereoCalibration::cx_px)
      .def_readonly("cy_px", &StereoCalibration::cy_px)
      .def_readonly("doffs_px", &StereoCalibration::doffs_px)
      .def_readonly("width", &StereoCalibration::width)
      .def_readonly("height", &StereoCalibration::height)
      .def_readonly("path", &StereoCalibration::path)
      .def_property_readonly("format", [](const StereoCalibration& c) { return to_string(c.format); });
  m.def(
      "read_calibration",
      [](const py::object& path, const std::string& format, double unit_m) {
        return read_calibration(path_of(path), parse_calib_format(format), unit_m);
      },
      py::arg("path"), py::arg("format") = "auto", py::arg("unit_m") = 1.0,
      "Middlebury calib.txt, KITTI (P2/P3 or P0/P1) or OpenCV YAML/XML (P1+P2 or Q).");
}
