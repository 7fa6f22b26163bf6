// libFuzzer harness: 16-bit disparity PNGs read as Q4 (value = 16 d) and as
// KITTI (value = 256 d) through read_disparity, whose conversion must never
// overflow int16 silently; each input as it is and with its chunk CRCs
// repaired (png_crc.hpp). Seeds: tests/fuzz/corpus/disp_png (Q4 and KITTI maps
// written by write_disparity).
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/image_roundtrip.hpp"
#include "tests/fuzz/png_crc.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"

using namespace tristereo;
using namespace tristereo::fuzz;

namespace {

void check_scale(const std::string& path, bool png, DispPngScale scale, const char* what) {
  ImageS16 disp;
  if (!library_call(what, [&] { disp = read_disparity(path, scale); })) return;
  check_well_formed(disp, 1, 1, what);
  // read_disparity picks the format from the magic bytes: a mutated input may
  // be a valid PFM, which the pfm harness checks.
  if (!png) return;
  // Every stored value is 0 (invalid) or the rounded conversion of a valid d;
  // checked against the raw 16-bit samples.
  Image<std::uint16_t> raw;
  TRISTEREO_FUZZ_CHECK(library_call("read_png_u16", [&] { raw = read_png_u16(path); }),
                       "read_disparity accepted a PNG that read_png_u16 refuses");
  TRISTEREO_FUZZ_CHECK(raw.width == disp.width && raw.height == disp.height, what);
  const long s = static_cast<long>(scale);
  for (std::size_t i = 0; i < raw.pixels.size(); ++i) {
    const long v = raw.pixels[i];
    const long want = v == 0 ? kInvalidDispQ4 : (v * 16 + s / 2) / s;
    TRISTEREO_FUZZ_CHECK(disp.pixels[i] == want, std::string(what) + ": pixel " + std::to_string(i) +
                                                     " raw " + std::to_string(v) + " read as " +
                                                     std::to_string(disp.pixels[i]));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  for (int pass = 0; pass < 2; ++pass) {
    const std::string path = write_scratch("input_disp.png", bytes);
    const bool png = has_png_signature(data, size);
    check_scale(path, png, DispPngScale::kQ4, "read_disparity(png, Q4)");
    check_scale(path, png, DispPngScale::kKitti, "read_disparity(png, KITTI)");
    if (!png) break;
    bytes = with_png_crcs_fixed(data, size);  // second pass: CRCs repaired
  }
  return 0;
}
