// Checks shared by the image-reader harnesses: what a reader returned is a
// well-formed image, and the project's writers store it so that the reader
// gives back the very same pixels (a reader that "succeeds" with garbage
// dimensions or a buffer of the wrong length fails here).
#pragma once

#include <cstring>
#include <string>

#include "tests/fuzz/fuzz_support.hpp"
#include "tristereo/image.hpp"
#include "tristereo/io.hpp"

namespace tristereo::fuzz {

// Round trips are skipped above this many samples only to keep one input fast.
constexpr std::size_t kMaxRoundTripSamples = std::size_t{1} << 20;

template <typename T>
void check_well_formed(const Image<T>& img, int channels_a, int channels_b, const char* what) {
  TRISTEREO_FUZZ_CHECK(img.width >= 1 && img.height >= 1, what);
  TRISTEREO_FUZZ_CHECK(img.width <= kMaxReadSide && img.height <= kMaxReadSide, what);
  TRISTEREO_FUZZ_CHECK(static_cast<std::int64_t>(img.width) * img.height <= kMaxReadPixels, what);
  TRISTEREO_FUZZ_CHECK(img.channels == channels_a || img.channels == channels_b, what);
  TRISTEREO_FUZZ_CHECK(img.pixels.size() ==
                           static_cast<std::size_t>(img.width) * img.height * img.channels,
                       what);
}

template <typename T>
bool same_image(const Image<T>& a, const Image<T>& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels &&
         a.pixels.size() == b.pixels.size() &&
         (a.pixels.empty() ||
          std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(T)) == 0);
}

// write_png_u8 (or the PGM/PPM writer) then read_image_u8 gives img back.
inline void check_u8_round_trip(const ImageU8& img, bool as_pnm) {
  if (img.pixels.size() > kMaxRoundTripSamples) return;
  const std::string path = scratch_dir() + (as_pnm ? "/round_trip.pnm" : "/round_trip.png");
  if (as_pnm) {
    if (img.channels == 1) write_pgm(path, img.view());
    else write_ppm(path, img.view());
  } else {
    write_png_u8(path, img.view());
  }
  TRISTEREO_FUZZ_CHECK(same_image(read_image_u8(path), img), "8-bit round trip");
}

}  // namespace tristereo::fuzz
