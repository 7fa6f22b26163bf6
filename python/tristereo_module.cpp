// Python bindings of tristereo (pybind11 + NumPy): the pipeline, the
// bit-exactness check and the calibration readers. The model's keyword
// arguments are the command line's options, from the same table
// (src/model/model_options.cpp): same names, values, defaults and checks.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "platform/cpu_features.hpp"
#include "src/model/model_options.hpp"
#include "tristereo/calib.hpp"
#include "tristereo/depth.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"
#include "tristereo/verify.hpp"
#include "tristereo/version.hpp"

namespace py = pybind11;
using namespace tristereo;

namespace {

// ---------------------------------------------------------------- parameters

// The run's options (not the model's): which kernels, how many workers, where.
struct RunOptions {
  int threads = 0;
  KernelChoice kernels = KernelChoice::kAuto;
  std::vector<int> cpus;
  bool pin = true;
};

std::string type_name(py::handle v) { return py::str(py::type::of(v).attr("__name__")); }

[[noreturn]] void wrong_type(const std::string& keyword, const char* expected, py::handle v) {
  throw py::type_error(keyword + " must be " + expected + ", got " + type_name(v) + " " +
                       std::string(py::repr(v)));
}

// An integer: Python's int or anything that is one (__index__: NumPy's
// integer scalars, e.g. a size read from an array's header), but not a bool.
bool is_int(py::handle v) {
  return PyIndex_Check(v.ptr()) && !py::isinstance<py::bool_>(v) && !py::isinstance<py::float_>(v);
}

std::string int_text(py::handle v) { return py::str(py::int_(py::reinterpret_borrow<py::object>(v))); }

// A Python value as the text the command line would take for the option, so
// that both go through the same parser (src/model/model_options.cpp) and give
// the same values and messages. Python ints of any size become their digits
// (the parser refuses those beyond int), floats their repr ('nan' is refused
// by name).
std::string option_text(const ModelOption& o, py::handle v) {
  const std::string kw = o.keyword;
  switch (o.kind) {
    case ModelOptionKind::kInt:
      if (!is_int(v)) wrong_type(kw, "an int", v);
      return int_text(v);
    case ModelOptionKind::kDecimal:
      if (!is_int(v) && !py::isinstance<py::float_>(v) && !py::isinstance(v, py::module_::import("numpy").attr("floating")))
        wrong_type(kw, "a number", v);
      return py::repr(py::float_(py::reinterpret_borrow<py::object>(v)));
    case ModelOptionKind::kSize:
      if (is_int(v)) return int_text(v);
      if (py::isinstance<py::str>(v)) return v.cast<std::string>();
      if (py::isinstance<py::tuple>(v) || py::isinstance<py::list>(v)) {
        const py::sequence seq = py::reinterpret_borrow<py::sequence>(v);
        if (seq.size() == 2 && is_int(seq[0]) && is_int(seq[1])) return int_text(seq[0]) + "x" + int_text(seq[1]);
      }
      wrong_type(kw, "an int, a (width, height) pair of ints or a 'WxH' string", v);
    case ModelOptionKind::kChoice: {
      const std::string choices = o.choices;
      const bool numbers = std::isdigit(static_cast<unsigned char>(choices[0])) != 0;
      if (numbers && is_int(v)) return int_text(v);
      if (!numbers && py::isinstance<py::str>(v)) return v.cast<std::string>();
      std::string expected = numbers ? "one of the ints " : "one of the strings ";
      for (char c : choices) expected += c == '|' ? std::string(", ") : std::string(1, c);
      wrong_type(kw, expected.c_str(), v);
    }
    case ModelOptionKind::kFlag:
      if (!py::isinstance<py::bool_>(v)) wrong_type(kw, "True or False", v);
      return "";
  }
  return "";
}

// Whether a flag keyword asks for the command line's flag: dense=True is
// --dense, subpixel=False is --no-subpixel.
bool flag_given(const ModelOption& o, py::handle v) {
  const bool on = v.cast<bool>();
  return std::string(o.name).rfind("no-", 0) == 0 ? !on : on;
}

std::string known_keywords(bool with_run) {
  std::string s;
  for (const ModelOption& o : model_options())
    if (std::string(o.name) != "ndisp") s += std::string(s.empty() ? "" : ", ") + o.keyword;
  if (with_run) s += ", threads, kernels, cpus, pin";
  return s;
}

int threads_from(py::handle v) {
  if (!is_int(v)) wrong_type("threads", "an int", v);
  const py::int_ i(py::reinterpret_borrow<py::object>(v));
  int overflow = 0;
  const long long n = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow != 0 || n < 0 || n > 256)
    throw py::value_error("threads must be 0 (one per CPU) .. 256, got " + int_text(i));
  return static_cast<int>(n);
}

// The model's parameters from keyword arguments, through the command line's
// option table: ndisp and each keyword as the text the command line takes.
// A keyword the chosen model does not use is refused (lambda_q4 with the path
// optimizer would change nothing).
StereoParams params_from_kwargs(py::handle ndisp, const py::kwargs& kw, RunOptions* run) {
  std::vector<GivenOption> given;
  // None: not given, so that the table's "ndisp is required" says what is missing.
  if (!ndisp.is_none()) given.push_back({find_model_option("ndisp"), option_text(*find_model_option("ndisp"), ndisp)});
  for (const auto& item : kw) {
    const std::string key = py::str(item.first);
    const py::handle v = item.second;
    if (const ModelOption* o = find_model_option_keyword(key); o && key != "ndisp") {
      const std::string text = option_text(*o, v);
      if (o->kind != ModelOptionKind::kFlag || flag_given(*o, v)) given.push_back({o, text});
    } else if (run && key == "threads") {
      run->threads = threads_from(v);
    } else if (run && key == "kernels") {
      if (!py::isinstance<py::str>(v)) wrong_type("kernels", "a string", v);
      run->kernels = parse_kernel_choice(v.cast<std::string>());
    } else if (run && key == "cpus") {
      std::string text;
      if (py::isinstance<py::str>(v)) {
        text = v.cast<std::string>();
      } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
        for (py::handle c : py::reinterpret_borrow<py::sequence>(v)) {
          if (!is_int(c)) wrong_type("cpus", "a list of ints or a string such as '0-3'", v);
          text += (text.empty() ? "" : ",") + int_text(c);
        }
      } else {
        wrong_type("cpus", "a list of ints or a string such as '0-3'", v);
      }
      try {
        run->cpus = parse_cpu_list(text);
      } catch (const Error& e) {
        throw py::value_error(std::string("cpus: ") + e.what());
      }
    } else if (run && key == "pin") {
      if (!py::isinstance<py::bool_>(v)) wrong_type("pin", "True or False", v);
      run->pin = v.cast<bool>();
    } else {
      throw py::type_error("unexpected keyword argument '" + key + "' (known: " + known_keywords(run) + ")");
    }
  }
  return model_params(given, OptionSpelling::kPython, /*refuse_without_effect=*/true);
}

// An option's value in `p` as a Python object of the type its keyword takes.
py::object option_value(const ModelOption& o, const StereoParams& p) {
  const std::string t = o.get(p);
  switch (o.kind) {
    case ModelOptionKind::kInt: return py::int_(std::stoi(t));
    case ModelOptionKind::kDecimal: return py::float_(std::stod(t));
    case ModelOptionKind::kSize: {
      const auto x = t.find('x');
      return py::make_tuple(std::stoi(t.substr(0, x)), std::stoi(t.substr(x + 1)));
    }
    case ModelOptionKind::kChoice:
      if (std::isdigit(static_cast<unsigned char>(o.choices[0]))) return py::int_(std::stoi(t));
      return py::str(t);
    case ModelOptionKind::kFlag: {
      const bool flag = t == "1";
      return py::bool_(std::string(o.name).rfind("no-", 0) == 0 ? !flag : flag);
    }
  }
  return py::none();
}

py::dict params_dict(const StereoParams& p) {
  py::dict d;
  for (const ModelOption& o : model_options())
    if (std::string(o.name) != "mode") d[o.keyword] = option_value(o, p);
  return d;
}

// The table itself, for tests and tools: what each keyword takes.
py::list options_list() {
  const StereoParams defaults;
  const char* kinds[] = {"int", "decimal", "size", "choice", "flag"};
  py::list out;
  for (const ModelOption& o : model_options()) {
    py::dict d;
    d["keyword"] = o.keyword;
    d["option"] = std::string("--") + o.name;
    d["kind"] = kinds[static_cast<int>(o.kind)];
    d["default"] = std::string(o.name) == "ndisp" ? py::object(py::none()) : option_value(o, defaults);
    if (std::string(o.name) == "mode") d["default"] = "default";
    const bool ranged = o.kind == ModelOptionKind::kInt || o.kind == ModelOptionKind::kSize ||
                        o.kind == ModelOptionKind::kDecimal;
    const double scale = o.kind == ModelOptionKind::kDecimal ? 10.0 : 1.0;
    d["min"] = ranged ? (scale == 1.0 ? py::object(py::int_(o.lo)) : py::object(py::float_(o.lo / scale)))
                      : py::object(py::none());
    d["max"] = ranged ? (scale == 1.0 ? py::object(py::int_(o.hi)) : py::object(py::float_(o.hi / scale)))
                      : py::object(py::none());
    d["narrowed"] = o.narrowed;
    py::list choices;
    if (o.choices) {
      std::string c = o.choices;
      std::size_t start = 0;
      for (;;) {
        const std::size_t bar = c.find('|', start);
        const std::string one = c.substr(start, bar == std::string::npos ? bar : bar - start);
        if (std::isdigit(static_cast<unsigned char>(one[0]))) choices.append(std::stoi(one));
        else choices.append(one);
        if (bar == std::string::npos) break;
        start = bar + 1;
      }
    }
    d["choices"] = choices;
    // (keyword, values): the values as the command line spells them ("dp",
    // "ad|ad_census", "!-1"); for a flag the bool its keyword must have.
    py::object needs = py::none();
    if (o.needs_option) {
      const ModelOption& need = *find_model_option(o.needs_option);
      if (need.kind == ModelOptionKind::kFlag)
        needs = py::make_tuple(need.keyword, py::bool_((std::string(o.needs_values) == "1") !=
                                                       (std::string(need.name).rfind("no-", 0) == 0)));
      else
        needs = py::make_tuple(need.keyword, o.needs_values);
    }
    d["needs"] = needs;
    d["help"] = o.help;
    out.append(d);
  }
  return out;
}

// ---------------------------------------------------------------- images

// How the caller's 3-channel arrays hold their channels. There is no default:
// OpenCV's arrays are BGR, tristereo.read_image's, PIL's and imageio's RGB, and
// the array does not say which (python/README.md, "Colour arrays").
enum class Order { kUnset, kGray, kRgb, kBgr };

Order parse_order(const py::object& o) {
  if (o.is_none()) return Order::kUnset;
  if (!py::isinstance<py::str>(o)) wrong_type("order", "'bgr', 'rgb', 'gray' or None", o);
  const std::string s = o.cast<std::string>();
  if (s == "gray") return Order::kGray;
  if (s == "rgb") return Order::kRgb;
  if (s == "bgr") return Order::kBgr;
  throw py::value_error("order must be 'bgr' (OpenCV's arrays), 'rgb' or 'gray', not '" + s + "'");
}

// A uint8 array, (H, W) or (H, W, 1) gray or (H, W, 3) colour, as a view.
// Rows may lie at any distance (padded rows, a crop of a bigger array): no
// copy as long as each row's pixels are packed; any other layout (e.g. every
// second column) is copied once into `copy`.
struct InputImage {
  ImageU8 copy;
  ImageView<const std::uint8_t> view;
};

InputImage as_image(const py::array& a, const char* name, Order order) {
  if (!py::isinstance<py::array_t<std::uint8_t>>(a) || a.dtype().kind() != 'u' || a.itemsize() != 1)
    throw py::value_error(std::string(name) + " must be a uint8 array, got dtype " +
                          std::string(py::str(a.dtype())));
  if (a.ndim() != 2 && !(a.ndim() == 3 && (a.shape(2) == 3 || a.shape(2) == 1)))
    throw py::value_error(std::string(name) + " must have shape (H, W), (H, W, 1) or (H, W, 3), got ndim " +
                          std::to_string(a.ndim()) + (a.ndim() == 3 ? " with " + std::to_string(a.shape(2)) + " channels" : ""));
  const py::ssize_t h = a.shape(0), w = a.shape(1);
  const int c = a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 1;
  if (c == 3 && order == Order::kUnset)
    throw py::value_error(std::string(name) + " has 3 channels: say their order, order='bgr' (OpenCV, cv2.imread) "
                          "or order='rgb' (tristereo.read_image, PIL, imageio)");
  if (c == 3 && order == Order::kGray)
    throw py::value_error(std::string(name) + " has 3 channels but order='gray' (use 'bgr' or 'rgb')");
  if (c == 1 && (order == Order::kRgb || order == Order::kBgr))
    throw py::value_error(std::string(name) + " is a gray array but order='" +
                          (order == Order::kRgb ? "rgb" : "bgr") + "' (use 'gray' or leave order out)");
  if (h > kMaxImageSide || w > kMaxImageSide)
    throw py::value_error(std::string(name) + " is " + std::to_string(w) + "x" + std::to_string(h) +
                          ", above the largest side " + std::to_string(kMaxImageSide));
  InputImage in;
  const bool packed_rows = a.strides(1) == c && (a.ndim() == 2 || a.strides(2) == 1) && a.strides(0) > 0;
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
            base[y * a.strides(0) + x * a.strides(1) + (a.ndim() == 3 ? k * a.strides(2) : 0)];
  in.view = in.copy.view();
  return in;
}

// A BGR view as gray in `gray` (w * h bytes), by the library's BT.601
// conversion of BGR rows (the SIMD set this machine runs): exactly the gray
// of the same picture read as RGB.
ImageView<const std::uint8_t> bgr_to_gray(ImageView<const std::uint8_t> bgr, std::uint8_t* gray) {
  bgr_to_gray_bt601(bgr, {gray, bgr.width, bgr.height, 1, bgr.width});
  return {gray, bgr.width, bgr.height, 1, bgr.width};
}

ImageU8 owned_image(const py::array& a, const char* name, Order order) {
  const InputImage in = as_image(a, name, order);
  if (order == Order::kBgr) {
    ImageU8 gray(in.view.width, in.view.height, 1);
    bgr_to_gray(in.view, gray.pixels.data());
    return gray;
  }
  ImageU8 img(in.view.width, in.view.height, in.view.channels);
  for (int y = 0; y < img.height; ++y)
    std::memcpy(img.row(y), in.view.row(y), static_cast<std::size_t>(img.width) * img.channels);
  return img;
}

// A str, bytes or os.PathLike as the path's bytes (os.fsencode: bytes stay
// as they are, str is encoded as the file system does).
std::string path_of(const py::object& path) {
  return py::module_::import("os").attr("fsencode")(path).cast<std::string>();
}

// ---------------------------------------------------------------- outputs

struct Output {
  py::array_t<float> disparity;
  py::array_t<std::int16_t> disp_q4;
  py::array_t<std::int32_t> vertices;
  py::array_t<std::int32_t> triangles;
  py::array_t<std::int16_t> vertex_disp_q4;
  py::array_t<std::uint8_t> state, confidence;                  // (H, W)
  py::array_t<std::uint8_t> vertex_state, vertex_confidence;    // (N,)
  py::dict timings_ms;
  std::int64_t forced_splits = 0;
  std::int64_t criterion_splits = 0;
  SampleValidity validity;
  int mesh_width = 0, mesh_height = 0;
  std::string digest;  // computed on first use: hashing every pixel costs a millisecond per frame

  // The frame's StereoOutput again, from the arrays (for the digest and the
  // mesh writer, which take the library's types).
  StereoOutput stereo_output() const {
    StereoOutput o;
    o.mesh.width = mesh_width;
    o.mesh.height = mesh_height;
    const auto vv = vertices.unchecked<2>();
    const auto tt = triangles.unchecked<2>();
    for (py::ssize_t i = 0; i < vv.shape(0); ++i) o.mesh.vertices.push_back({vv(i, 0), vv(i, 1)});
    for (py::ssize_t i = 0; i < tt.shape(0); ++i) o.mesh.triangles.push_back({tt(i, 0), tt(i, 1), tt(i, 2)});
    o.vertex_disp_q4.assign(vertex_disp_q4.data(), vertex_disp_q4.data() + vertex_disp_q4.size());
    o.disp_q4 = ImageS16(static_cast<int>(disp_q4.shape(1)), static_cast<int>(disp_q4.shape(0)));
    std::memcpy(o.disp_q4.pixels.data(), disp_q4.data(), o.disp_q4.pixels.size() * sizeof(std::int16_t));
    o.validity = validity;
    return o;
  }

  // The digest of the arrays, as digest_hex() gives it for the frame's StereoOutput.
  const std::string& get_digest() {
    if (digest.empty()) digest = digest_hex(stereo_output());
    return digest;
  }
};

// The dense map into the caller's arrays (no GIL needed: plain memory).
void copy_dense(const ImageS16& d, std::int16_t* q, float* f) {
  const std::size_t n = static_cast<std::size_t>(d.width) * d.height;
  std::memcpy(q, d.pixels.data(), n * sizeof(std::int16_t));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < n; ++i) f[i] = q[i] == kInvalidDispQ4 ? nan : q[i] * (1.0f / 16.0f);
}

// The rest of the output (GIL held): the mesh, whose size is known only now.
void copy_mesh(const StereoOutput& o, const FrameTimings& t, Output& r) {
  const auto nv = static_cast<py::ssize_t>(o.mesh.vertices.size());
  const auto nt = static_cast<py::ssize_t>(o.mesh.triangles.size());
  r.vertices = py::array_t<std::int32_t>({nv, py::ssize_t{2}});
  r.triangles = py::array_t<std::int32_t>({nt, py::ssize_t{3}});
  r.vertex_disp_q4 = py::array_t<std::int16_t>(nv);
  r.vertex_state = py::array_t<std::uint8_t>(nv);
  r.vertex_confidence = py::array_t<std::uint8_t>(nv);
  static_assert(sizeof(Vertex) == 2 * sizeof(std::int32_t) && sizeof(Triangle) == 3 * sizeof(std::int32_t),
                "the mesh's arrays are copied as packed int32 rows");
  if (nv > 0) {
    std::memcpy(r.vertices.mutable_data(), o.mesh.vertices.data(), nv * sizeof(Vertex));
    std::memcpy(r.vertex_disp_q4.mutable_data(), o.vertex_disp_q4.data(), nv * sizeof(std::int16_t));
    std::memcpy(r.vertex_state.mutable_data(), o.vertex_state.data(), static_cast<std::size_t>(nv));
    std::memcpy(r.vertex_confidence.mutable_data(), o.vertex_confidence.data(), static_cast<std::size_t>(nv));
  }
  if (nt > 0) std::memcpy(r.triangles.mutable_data(), o.mesh.triangles.data(), nt * sizeof(Triangle));
  r.timings_ms["tritree"] = t.tritree_ns / 1e6;
  r.timings_ms["cost_aggregation"] = t.cost_aggregation_ns / 1e6;
  r.timings_ms["dp"] = t.dp_ns / 1e6;
  r.timings_ms["prior"] = t.prior_ns / 1e6;
  r.timings_ms["right_pass"] = t.right_pass_ns / 1e6;
  r.timings_ms["fill"] = t.fill_ns / 1e6;
  r.timings_ms["interpolation"] = t.interpolation_ns / 1e6;
  r.timings_ms["total"] = t.total_ns / 1e6;
  r.forced_splits = o.mesh.forced_splits;
  r.criterion_splits = o.mesh.criterion_splits;
  r.validity = o.validity;
  r.mesh_width = o.mesh.width;
  r.mesh_height = o.mesh.height;
}

// ---------------------------------------------------------------- depth and files

// A Calibration, or the command line's --camera numbers as a tuple
// (focal_px, baseline_m, cx_px, cy_px[, doffs_px]).
CameraParams camera_of(const py::object& c) {
  if (py::isinstance<StereoCalibration>(c)) return c.cast<const StereoCalibration&>().camera();
  const char* expected = "a Calibration or a (focal_px, baseline_m, cx_px, cy_px[, doffs_px]) tuple";
  if (!py::isinstance<py::tuple>(c) && !py::isinstance<py::list>(c)) wrong_type("camera", expected, c);
  const py::sequence seq = py::reinterpret_borrow<py::sequence>(c);
  if (seq.size() < 4 || seq.size() > 5) wrong_type("camera", expected, c);
  double v[5] = {0, 0, 0, 0, 0};
  for (std::size_t i = 0; i < seq.size(); ++i) {
    if (!is_int(seq[i]) && !py::isinstance<py::float_>(seq[i])) wrong_type("camera", expected, c);
    v[i] = seq[i].cast<double>();
    // The command line's bounds (--camera): far beyond any real camera.
    if (!std::isfinite(v[i]) || std::fabs(v[i]) > 1e6)
      throw py::value_error("camera: " + std::string(py::repr(seq[i])) + " is out of range; each number must be within +-1e6");
  }
  if (!(v[0] > 0) || !(v[1] > 0)) throw py::value_error("camera: focal length and baseline must be > 0");
  return {v[0], v[1], v[2], v[3], v[4]};
}

// A disparity map the caller passes: int16 (H, W), as Output.disp_q4 is.
ImageView<const std::int16_t> disp_view(const py::array& a, py::array_t<std::int16_t>* keep) {
  if (a.dtype().kind() != 'i' || a.itemsize() != 2 || a.ndim() != 2)
    throw py::value_error("disp_q4 must be an int16 (H, W) array (Output.disp_q4), got " +
                          std::string(py::str(a.dtype())) + " with ndim " + std::to_string(a.ndim()));
  *keep = py::array_t<std::int16_t, py::array::c_style>::ensure(a);  // a copy only if not C-contiguous
  return {keep->data(), static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), 1,
          static_cast<std::ptrdiff_t>(a.shape(1)) * 2};
}

// The left image for colours: gray, or RGB (a BGR array reordered).
ImageU8 colour_image(const py::array& a, Order order) {
  const InputImage in = as_image(a, "left", order);
  ImageU8 img(in.view.width, in.view.height, in.view.channels);
  for (int y = 0; y < img.height; ++y) {
    const std::uint8_t* src = in.view.row(y);
    std::uint8_t* dst = img.row(y);
    if (order != Order::kBgr) {
      std::memcpy(dst, src, static_cast<std::size_t>(img.width) * img.channels);
      continue;
    }
    for (int x = 0; x < img.width; ++x) {
      dst[3 * x] = src[3 * x + 2];
      dst[3 * x + 1] = src[3 * x + 1];
      dst[3 * x + 2] = src[3 * x];
    }
  }
  return img;
}

// The keywords min_disparity, min_depth, max_depth as match's --min-disparity,
// --min-depth, --max-depth (depth.hpp's DepthLimits).
DepthLimits depth_limits_of(double min_disparity, double min_depth, double max_depth) {
  DepthLimits l;
  l.min_disparity_px = min_disparity;
  l.min_depth_m = min_depth;
  l.max_depth_m = max_depth;
  try {
    check_depth_limits(l);
  } catch (const Error& e) {
    throw py::value_error(std::string(e.what()) + " (keywords min_disparity, min_depth, max_depth; 0 = no limit)");
  }
  return l;
}

// A copy of d with the disparities the limits exclude made invalid.
ImageS16 limited_copy(ImageView<const std::int16_t> d, const CameraParams& cam, const DepthLimits& limits) {
  ImageS16 out(d.width, d.height);
  for (int y = 0; y < d.height; ++y)
    std::memcpy(out.pixels.data() + static_cast<std::size_t>(y) * d.width, d.row(y),
                static_cast<std::size_t>(d.width) * sizeof(std::int16_t));
  if (d.width > 0 && d.height > 0) apply_depth_limits(out.view(), cam, limits);
  return out;
}

py::array_t<float> depth_array(const py::array& disp_q4, const py::object& camera, double min_disparity,
                               double min_depth, double max_depth) {
  py::array_t<std::int16_t> keep;
  const ImageView<const std::int16_t> d0 = disp_view(disp_q4, &keep);
  const CameraParams cam = camera_of(camera);
  const ImageS16 limited = limited_copy(d0, cam, depth_limits_of(min_disparity, min_depth, max_depth));
  const Image<float> z = depth_m_from_disp_q4(limited.view(), cam);
  py::array_t<float> out({z.height, z.width});
  float* dst = out.mutable_data();
  // NaN marks invalid pixels, as in Output.disparity (the library's +inf).
  for (std::size_t i = 0; i < z.pixels.size(); ++i)
    dst[i] = std::isinf(z.pixels[i]) ? std::numeric_limits<float>::quiet_NaN() : z.pixels[i];
  return out;
}

py::dict write_depth_file(const py::object& path, const py::array& depth_m) {
  if (depth_m.dtype().kind() != 'f' || depth_m.ndim() != 2)
    throw py::value_error("depth_m must be a float (H, W) array of metres (tristereo.depth())");
  const auto z = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(depth_m);
  Image<float> img(static_cast<int>(z.shape(1)), static_cast<int>(z.shape(0)));
  // NaN (this module's invalid) becomes the library's +inf.
  for (std::size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = std::isnan(z.data()[i]) ? std::numeric_limits<float>::infinity() : z.data()[i];
  const std::string file = path_of(path);
  DepthWriteReport r;
  {
    py::gil_scoped_release nogil;  // the file is written from the copy above
    r = write_depth(file, img.view());
  }
  return py::dict(py::arg("valid") = r.valid, py::arg("invalid") = r.invalid,
                  py::arg("out_of_range") = r.out_of_range);
}

// ---------------------------------------------------------------- pipeline

class PyPipeline {
 public:
  PyPipeline(int max_width, int max_height, const py::object& ndisp, const py::kwargs& kw) {
    RunOptions run;
    PipelineConfig c;
    c.max_width = max_width;
    c.max_height = max_height;
    c.params = params_from_kwargs(ndisp, kw, &run);
    c.threads = run.threads;
    c.kernels = run.kernels;
    c.cpus = run.cpus;
    c.pin_threads = run.pin;
    pipeline_.configure(c);
  }

  // One frame at a time per Pipeline, and each caller gets its own frame's
  // result: the lock is held from the frame until its output has been copied
  // into the caller's arrays. The GIL is released for the frame, so other
  // threads (and other Pipelines) run meanwhile; it is taken back, lock still
  // held, only to create the mesh's arrays (their size is known only then).
  // No deadlock: a thread waiting for the lock never holds the GIL.
  //
  // out=: an earlier Output of the same size whose dense arrays are filled
  // again in place (the mesh's arrays are new: their sizes change), so a
  // loop allocates no megabyte-sized arrays per frame. Fresh arrays can cost
  // the first touch of their pages (measured in the binding: the dense copy
  // took 0.22 ms into reused pages, 0.88 ms on every second call into fresh
  // ones, Teddy's size); python/bench_overhead.py times both ways.
  py::object process(const py::array& left, const py::array& right, const py::object& order_arg,
                     const py::object& out_arg) {
    const Order order = parse_order(order_arg);
    const InputImage l = as_image(left, "left", order);
    const InputImage r = as_image(right, "right", order);
    const int w = l.view.width, h = l.view.height;
    if (!out_arg.is_none() && !py::isinstance<Output>(out_arg)) wrong_type("out", "an Output or None", out_arg);
    py::object result = out_arg.is_none() ? py::cast(Output{}) : out_arg;
    Output& res = result.cast<Output&>();
    const auto fits = [&](const py::array& a) {
      return a.ndim() == 2 && a.shape(0) == h && a.shape(1) == w && a.writeable() &&
             (a.flags() & py::array::c_style) != 0;
    };
    // New arrays, if needed, join `res` only when the frame succeeded: a
    // failed call leaves the caller's output as it was (refilled arrays are
    // written only after the frame, the last step that can fail).
    const bool reuse = fits(res.disp_q4) && fits(res.disparity) && fits(res.state) && fits(res.confidence);
    py::array_t<std::int16_t> q_array = reuse ? res.disp_q4 : py::array_t<std::int16_t>({h, w});
    py::array_t<float> f_array = reuse ? res.disparity : py::array_t<float>({h, w});
    py::array_t<std::uint8_t> s_array = reuse ? res.state : py::array_t<std::uint8_t>({h, w});
    py::array_t<std::uint8_t> c_array = reuse ? res.confidence : py::array_t<std::uint8_t>({h, w});
    std::int16_t* q = q_array.mutable_data();
    float* f = f_array.mutable_data();
    std::uint8_t* st = s_array.mutable_data();
    std::uint8_t* cf = c_array.mutable_data();
    std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
    const StereoOutput* out = nullptr;
    FrameTimings timings;
    {
      py::gil_scoped_release nogil;
      lock.lock();
      ImageView<const std::uint8_t> lv = l.view, rv = r.view;
      if (order == Order::kBgr) {
        const auto& cfg = pipeline_.config();
        if (r.view.width != w || r.view.height != h)
          throw Error(ErrorCode::kSizeMismatch, "left is " + std::to_string(w) + "x" + std::to_string(h) +
                                                    ", right " + std::to_string(r.view.width) + "x" +
                                                    std::to_string(r.view.height));
        if (w > cfg.max_width || h > cfg.max_height)
          throw Error(ErrorCode::kInvalidArgument, "frame " + std::to_string(w) + "x" + std::to_string(h) +
                                                       " is larger than the configured " +
                                                       std::to_string(cfg.max_width) + "x" +
                                                       std::to_string(cfg.max_height));
        reserve_bgr_buffers();
        lv = bgr_to_gray(l.view, gray_left_.data());
        rv = bgr_to_gray(r.view, gray_right_.data());
      }
      out = &pipeline_.process(lv, rv);
      timings = pipeline_.last_timings();
      copy_dense(out->disp_q4, q, f);
      std::memcpy(st, out->pixel_state.pixels.data(), out->pixel_state.pixels.size());
      std::memcpy(cf, out->pixel_confidence.pixels.data(), out->pixel_confidence.pixels.size());
    }
    res.disp_q4 = q_array;
    res.disparity = f_array;
    res.state = s_array;
    res.confidence = c_array;
    res.digest.clear();
    copy_mesh(*out, timings, res);
    return result;
  }

  std::string kernels() const { return to_string(pipeline_.active_kernels()); }
  int threads() const { return pipeline_.worker_count(); }
  std::size_t working_memory_bytes() const { return pipeline_.working_memory_bytes(); }
  py::dict params() const { return params_dict(pipeline_.config().params); }

 private:
  // BGR frames' gray copies, allocated once at the configured maximum on the
  // first BGR frame (gray and RGB frames never need them).
  void reserve_bgr_buffers() {
    const auto& cfg = pipeline_.config();
    const std::size_t n = static_cast<std::size_t>(cfg.max_width) * cfg.max_height;
    if (gray_left_.size() < n) {
      gray_left_.resize(n);
      gray_right_.resize(n);
    }
  }

  Pipeline pipeline_;
  std::mutex mutex_;
  std::vector<std::uint8_t> gray_left_, gray_right_;
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

  py::class_<Output>(m, "Output",
                     "What one frame produced: the caller's own arrays, unchanged by later frames (unless "
                     "passed back as process(..., out=...), which refills them).")
      .def_readonly("disparity", &Output::disparity, "float32 (H, W), pixels, NaN = invalid")
      .def_readonly("disp_q4", &Output::disp_q4, "int16 (H, W), disparity * 16, INVALID_DISP_Q4 = invalid")
      .def_readonly("vertices", &Output::vertices, "int32 (N, 2): x, y of the mesh vertices (the samples)")
      .def_readonly("triangles", &Output::triangles, "int32 (M, 3): vertex indices")
      .def_readonly("vertex_disp_q4", &Output::vertex_disp_q4, "int16 (N,): the samples' disparities * 16")
      .def_readonly("state", &Output::state,
                    "uint8 (H, W): 0 invalid, 1 filled (a neighbour's disparity), 2 measured, as `tristereo "
                    "match --valid` writes it (docs/model.md section 7)")
      .def_readonly("confidence", &Output::confidence,
                    "uint8 (H, W): 0 invalid, 1..127 filled, 128..255 measured, as `tristereo match "
                    "--confidence` writes it")
      .def_readonly("vertex_state", &Output::vertex_state, "uint8 (N,): each sample's state, as `state`")
      .def_readonly("vertex_confidence", &Output::vertex_confidence, "uint8 (N,): each sample's confidence")
      .def_readonly("timings_ms", &Output::timings_ms, "per-stage wall time of this frame, ms")
      .def_readonly("forced_splits", &Output::forced_splits, "tritree splits made only to keep the mesh conforming")
      .def_readonly("criterion_splits", &Output::criterion_splits, "tritree splits the PSNR/area criterion asked for")
      .def_property_readonly(
          "samples", [](const Output& o) { return o.validity.samples; }, "samples matched (vertices, or pixels if dense)")
      .def_property_readonly(
          "uniqueness_rejected", [](const Output& o) { return o.validity.uniqueness_rejected; },
          "samples that failed the uniqueness test")
      .def_property_readonly(
          "lr_rejected", [](const Output& o) { return o.validity.lr_rejected; },
          "samples that failed the left-right check")
      .def_property_readonly(
          "prior_redecided", [](const Output& o) { return o.validity.prior_redecided; },
          "samples the support prior chose again")
      .def_property_readonly(
          "prior_recovered", [](const Output& o) { return o.validity.prior_recovered; },
          "invalid samples the support prior gave a disparity")
      .def_property_readonly(
          "prior_lost", [](const Output& o) { return o.validity.prior_lost; },
          "valid samples the support prior's uniqueness test made invalid")
      .def_property_readonly(
          "filled", [](const Output& o) { return o.validity.filled; },
          "invalid samples given a neighbour's disparity by the fill")
      .def_property_readonly(
          "min_confidence_rejected", [](const Output& o) { return o.validity.min_confidence_rejected; },
          "samples made invalid by min_confidence after the fill")
      .def_property_readonly("digest", &Output::get_digest,
                             "64-bit FNV-1a digest of mesh, samples and dense map (hex), as `tristereo verify` prints");

  py::class_<PyPipeline>(m, "Pipeline",
                         "Pipeline(max_width, max_height, ndisp, **params): configure once (all memory "
                         "allocated, workers started), then process(left, right) per frame. The keywords are "
                         "the command line's model options (tristereo.model_options()) and threads, kernels, "
                         "cpus, pin.")
      .def(py::init<int, int, const py::object&, const py::kwargs&>(), py::arg("max_width"), py::arg("max_height"),
           py::arg("ndisp") = py::none())
      .def("process", &PyPipeline::process, py::arg("left"), py::arg("right"), py::arg("order") = py::none(),
           py::arg("out") = py::none(),
           "left, right: uint8 arrays (H, W) gray, or (H, W, 3) with order='bgr' or 'rgb'; equal sizes. "
           "out: an earlier Output to fill again (its dense arrays are reused when the size matches). "
           "Releases the GIL while it runs; one frame at a time per Pipeline (other threads wait).")
      .def_property_readonly("kernels", &PyPipeline::kernels)
      .def_property_readonly("threads", &PyPipeline::threads)
      .def_property_readonly("params", &PyPipeline::params, "every model option's value in this configuration")
      .def_property_readonly("working_memory_bytes", &PyPipeline::working_memory_bytes,
                             "bytes the configured pipeline allocated (docs/performance.md)");

  m.def("model_options", &options_list,
        "The model options the command line and the Python keywords share: keyword, option, kind, default, "
        "min, max, choices, needs (the option and values it is used with), help.");

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
      [](const py::array& left, const py::array& right, const py::object& ndisp, std::vector<int> thread_counts,
         const py::object& order_arg, const py::kwargs& kw) {
        const Order order = parse_order(order_arg);
        const ImageU8 l = owned_image(left, "left", order), r = owned_image(right, "right", order);
        const StereoParams p = params_from_kwargs(ndisp, kw, nullptr);
        py::gil_scoped_release nogil;
        return verify_bit_exact(l, r, p, thread_counts);
      },
      py::arg("left"), py::arg("right"), py::arg("ndisp") = py::none(), py::arg("thread_counts") = std::vector<int>{},
      py::arg("order") = py::none(),
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
      py::arg("path"), "An 8-bit PNG/PGM/PPM as uint8 (H, W), or (H, W, 3) in RGB order (pass order='rgb').");

  m.def("depth", &depth_array, py::arg("disp_q4"), py::arg("camera"), py::arg("min_disparity") = 2.0,
        py::arg("min_depth") = 0.0, py::arg("max_depth") = 0.0,
        "Depth in metres along the optical axis, float32 (H, W), NaN where the disparity is invalid or "
        "outside the depth limits: Z = focal_px * baseline_m / (d + doffs_px), kept where d + doffs_px >= "
        "min_disparity (default 2 px; 0 keeps every d + doffs > 0) and min_depth <= Z <= max_depth (0 = no "
        "limit), as match --min-disparity/--min-depth/--max-depth. camera: a Calibration or "
        "(focal_px, baseline_m, cx_px, cy_px[, doffs_px]).");
  m.def(
      "write_disparity",
      [](const py::object& path, const py::array& disp_q4, const std::string& png_scale) {
        py::array_t<std::int16_t> keep;
        const auto d = disp_view(disp_q4, &keep);
        if (png_scale != "q4" && png_scale != "kitti")
          throw py::value_error("png_scale must be 'q4' or 'kitti', not '" + png_scale + "'");
        const std::string file = path_of(path);
        py::gil_scoped_release nogil;  // `keep` holds the array while it is written
        write_disparity(file, d, png_scale == "q4" ? DispPngScale::kQ4 : DispPngScale::kKitti);
      },
      py::arg("path"), py::arg("disp_q4"), py::arg("png_scale") = "q4",
      "As match --disp: .pfm float pixels (+inf invalid) or .png uint16 (16 d, or 256 d with "
      "png_scale='kitti'; 0 invalid).");
  m.def(
      "write_disparity_color",
      [](const py::object& path, const py::array& disp_q4, int dmin, int ndisp) {
        py::array_t<std::int16_t> keep;
        const auto d = disp_view(disp_q4, &keep);
        const std::string file = path_of(path);
        py::gil_scoped_release nogil;
        write_disparity_color(file, d, dmin, ndisp);
      },
      py::arg("path"), py::arg("disp_q4"), py::arg("dmin"), py::arg("ndisp"),
      "As match --disp-color: an RGB PNG of disparities dmin .. dmin + ndisp - 1, invalid black.");
  m.def("write_depth", &write_depth_file, py::arg("path"), py::arg("depth_m"),
        "As match --depth: .pfm float metres (+inf invalid) or .png uint16 millimetres (0 invalid). "
        "NaN counts as invalid. Returns the counts written.");
  m.def(
      "write_mesh_ply",
      [](const py::object& path, const Output& out, const py::array& left, const py::object& camera, bool binary,
         const py::object& order_arg, bool include_filled, double min_disparity, double min_depth,
         double max_depth) {
        const ImageU8 colours = colour_image(left, parse_order(order_arg));
        const DepthLimits limits = depth_limits_of(min_disparity, min_depth, max_depth);
        StereoOutput o = out.stereo_output();
        if (!include_filled) {
          const auto state = out.vertex_state.unchecked<1>();
          for (py::ssize_t i = 0; i < state.shape(0); ++i)
            if (state(i) != static_cast<std::uint8_t>(SampleState::kMeasured))
              o.vertex_disp_q4[static_cast<std::size_t>(i)] = kInvalidDispQ4;
        }
        CameraParams cam{};
        if (!camera.is_none()) {
          cam = camera_of(camera);
          const int n = static_cast<int>(o.vertex_disp_q4.size());
          if (n > 0)
            apply_depth_limits({o.vertex_disp_q4.data(), n, 1, 1, static_cast<std::ptrdiff_t>(n) * 2}, cam, limits);
        }
        const std::string file = path_of(path);
        MeshWriteReport r;
        {
          py::gil_scoped_release nogil;  // from the copies above
          r = write_mesh_ply(file, o.mesh, o.vertex_disp_q4, colours.view(), camera.is_none() ? nullptr : &cam,
                             binary);
        }
        return py::dict(py::arg("faces_written") = r.faces_written,
                        py::arg("faces_without_disparity") = r.faces_without_disparity,
                        py::arg("faces_behind_camera") = r.faces_behind_camera);
      },
      py::arg("path"), py::arg("out"), py::arg("left"), py::arg("camera") = py::none(), py::arg("binary") = true,
      py::arg("order") = py::none(), py::arg("include_filled") = false, py::arg("min_disparity") = 2.0,
      py::arg("min_depth") = 0.0, py::arg("max_depth") = 0.0,
      "As match --mesh: the 2.5D mesh as PLY, coloured by the left image; (x, y, d) in pixels without a "
      "camera, metres with one (vertices within the depth limits only, as depth()); faces of measured "
      "vertices only unless include_filled (as --points-include-filled). Returns the face counts.");
  m.def(
      "write_points_ply",
      [](const py::object& path, const py::array& disp_q4, const py::array& left, const py::object& camera,
         bool binary, const py::object& order_arg, const py::object& state_arg, double min_disparity,
         double min_depth, double max_depth) {
        const DepthLimits limits = depth_limits_of(min_disparity, min_depth, max_depth);
        py::array_t<std::int16_t> keep;
        auto d = disp_view(disp_q4, &keep);
        ImageS16 measured;  // state given: the measured pixels' disparities only
        if (!state_arg.is_none()) {
          const auto state = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(state_arg);
          if (!state || state.ndim() != 2 || state.shape(0) != d.height || state.shape(1) != d.width)
            throw py::value_error("state must be a uint8 (H, W) array of disp_q4's size (Output.state)");
          measured = ImageS16(d.width, d.height);
          const std::uint8_t* s = state.data();
          for (int y = 0; y < d.height; ++y)
            for (int x = 0; x < d.width; ++x) {
              const std::size_t i = static_cast<std::size_t>(y) * d.width + x;
              measured.pixels[i] =
                  s[i] == static_cast<std::uint8_t>(SampleState::kMeasured) ? d.row(y)[x] : kInvalidDispQ4;
            }
          d = static_cast<const ImageS16&>(measured).view();
        }
        const ImageU8 colours = colour_image(left, parse_order(order_arg));
        const CameraParams cam = camera_of(camera);
        const ImageS16 limited = limited_copy(d, cam, limits);
        const std::string file = path_of(path);
        py::gil_scoped_release nogil;
        return write_points_ply(file, limited.view(), colours.view(), cam, binary);
      },
      py::arg("path"), py::arg("disp_q4"), py::arg("left"), py::arg("camera"), py::arg("binary") = true,
      py::arg("order") = py::none(), py::arg("state") = py::none(), py::arg("min_disparity") = 2.0,
      py::arg("min_depth") = 0.0, py::arg("max_depth") = 0.0,
      "As match --points: one coloured PLY vertex (metres) per valid pixel within the depth limits (as "
      "depth()); with state (Output.state), per measured pixel, as match --points without "
      "--points-include-filled. Returns the number of points.");

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
