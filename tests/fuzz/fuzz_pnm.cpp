// libFuzzer harness: the PGM/PPM reader (P5/P6 binary, P2/P3 ASCII, maxval 255;
// other Netpbm kinds must be refused cleanly) through read_image_u8, on the
// input bytes as a file. Seeds: tests/fuzz/corpus/pnm.
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/image_roundtrip.hpp"
#include "tristereo/io.hpp"

using namespace tristereo;
using namespace tristereo::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("input.pnm", data, size);
  ImageU8 img;
  if (library_call("read_image_u8", [&] { img = read_image_u8(path); })) {
    check_well_formed(img, 1, 3, "read_image_u8");
    check_u8_round_trip(img, /*as_pnm=*/true);
  }
  return 0;
}
