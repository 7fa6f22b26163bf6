// libFuzzer harness: the PNG readers (read_image_u8 for 1/2/4/8-bit gray,
// palette, RGB, with or without alpha; read_png_u16 for 16-bit gray) on the
// input bytes as a file, then on the same bytes with every chunk CRC repaired
// (png_crc.hpp). Seeds: tests/fuzz/corpus/png (made by make_fuzz_seeds with the
// project's PNG writer).
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/image_roundtrip.hpp"
#include "tests/fuzz/png_crc.hpp"
#include "tristereo/io.hpp"

using namespace tristereo;
using namespace tristereo::fuzz;

namespace {

void read_png_file(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("input.png", data, size);
  ImageU8 img;
  if (library_call("read_image_u8", [&] { img = read_image_u8(path); })) {
    check_well_formed(img, 1, 3, "read_image_u8");
    check_u8_round_trip(img, /*as_pnm=*/false);
  }
  Image<std::uint16_t> img16;
  if (library_call("read_png_u16", [&] { img16 = read_png_u16(path); })) {
    check_well_formed(img16, 1, 1, "read_png_u16");
    if (img16.pixels.size() <= kMaxRoundTripSamples) {
      const std::string out = scratch_dir() + "/round_trip16.png";
      write_png_u16(out, img16.view());
      TRISTEREO_FUZZ_CHECK(same_image(read_png_u16(out), img16), "16-bit round trip");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  read_png_file(data, size);
  if (has_png_signature(data, size)) {
    const std::vector<std::uint8_t> fixed = with_png_crcs_fixed(data, size);
    read_png_file(fixed.data(), fixed.size());
  }
  return 0;
}
