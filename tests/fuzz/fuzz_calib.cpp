// libFuzzer harness: the calibration readers (Middlebury calib.txt, KITTI,
// OpenCV YAML and XML). The first input byte picks the format (auto or one
// forced reader, so every parser also sees the others' files) and the OpenCV
// unit; the rest is the file. A calibration that is read must hold what
// read_calibration promises: focal length and baseline finite and > 0, the
// principal point and doffs finite, a size >= 0, the format it was read as.
// Seeds: tests/fuzz/corpus/calib.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/fuzz_input.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tristereo/calib.hpp"

using namespace tristereo;
using namespace tristereo::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const std::uint8_t selector = in.byte();
  static const CalibFormat kFormats[4] = {CalibFormat::kAuto, CalibFormat::kMiddlebury,
                                          CalibFormat::kKitti, CalibFormat::kOpenCv};
  const CalibFormat format = kFormats[selector & 3];
  const double unit_m = (selector & 4) ? 0.001 : 1.0;
  const std::string path = write_scratch("calib.txt", in.rest());
  StereoCalibration c;
  if (!library_call("read_calibration", [&] { c = read_calibration(path, format, unit_m); }))
    return 0;
  TRISTEREO_FUZZ_CHECK(c.focal_px >= kMinFocalPx && c.focal_px <= kMaxFocalPx, "focal length within its bounds");
  TRISTEREO_FUZZ_CHECK(c.baseline_m >= kMinBaselineM && c.baseline_m <= kMaxBaselineM, "baseline within its bounds");
  TRISTEREO_FUZZ_CHECK(!check_camera_bounds(c.camera(), c.width, c.height), "every value within its bounds");
  TRISTEREO_FUZZ_CHECK(std::isfinite(c.cx_px) && std::isfinite(c.cy_px) && std::isfinite(c.doffs_px),
                       "principal point and doffs");
  TRISTEREO_FUZZ_CHECK(c.width >= 0 && c.height >= 0, "image size");
  TRISTEREO_FUZZ_CHECK(c.format != CalibFormat::kAuto, "the format read is named");
  TRISTEREO_FUZZ_CHECK(format == CalibFormat::kAuto || c.format == format, "forced format kept");
  TRISTEREO_FUZZ_CHECK(c.path == path, "path kept");
  return 0;
}
