// libFuzzer harness: the PFM reader (read_pfm, either endianness, 1 or 3
// channels) and the disparity reader on PFM input (read_disparity: non-finite
// -> invalid, else 16 d rounded, which must fit int16). Seeds:
// tests/fuzz/corpus/pfm.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/image_roundtrip.hpp"
#include "tristereo/io.hpp"

using namespace tristereo;
using namespace tristereo::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("input.pfm", data, size);
  ImageF32 img;
  if (library_call("read_pfm", [&] { img = read_pfm(path); })) {
    check_well_formed(img, 1, 3, "read_pfm");
    if (img.pixels.size() <= kMaxRoundTripSamples) {
      // Bitwise (NaN payloads included): write_pfm stores the floats as they are.
      const std::string out = scratch_dir() + "/round_trip.pfm";
      write_pfm(out, img.view());
      TRISTEREO_FUZZ_CHECK(same_image(read_pfm(out), img), "PFM round trip");
    }
  }
  ImageS16 disp;
  if (library_call("read_disparity(pfm)", [&] { disp = read_disparity(path); })) {
    check_well_formed(disp, 1, 1, "read_disparity");
    // A Q4 map written as PFM reads back as the same Q4 map.
    if (disp.pixels.size() <= kMaxRoundTripSamples) {
      const std::string out = scratch_dir() + "/round_trip_disp.pfm";
      write_disparity(out, disp.view());
      TRISTEREO_FUZZ_CHECK(same_image(read_disparity(out), disp), "Q4 disparity PFM round trip");
    }
  }
  return 0;
}
