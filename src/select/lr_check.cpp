#include "src/select/lr_check.hpp"

#include <cstdlib>

#include "tristereo/fixed_point.hpp"

namespace tristereo {

int lr_check(const SampleLayout& samples, ImageView<const std::int16_t> right_mirrored_q4,
             int max_diff_q4, std::int16_t* disp_q4, int y_begin, int y_end) {
  const int w = samples.width;
  const int i_end = samples.row_begin(y_end < 0 ? samples.height : y_end);
  int rejected = 0;
  for (int i = samples.row_begin(y_begin); i < i_end; ++i) {
    const int d = disp_q4[i];
    if (d == kInvalidDispQ4) continue;
    const int xr = samples.x_of(i) - static_cast<int>(floor_div(d + kDispOne / 2, kDispOne));
    bool ok = xr >= 0 && xr < w;
    if (ok) {
      const int r = right_mirrored_q4.row(samples.y_of(i))[w - 1 - xr];
      ok = r != kInvalidDispQ4 && std::abs(d - r) <= max_diff_q4;
    }
    if (!ok) {
      disp_q4[i] = kInvalidDispQ4;
      ++rejected;
    }
  }
  return rejected;
}

void size_mirror(ImageView<const std::uint8_t> src, ImageU8& dst) {
  dst.width = src.width;
  dst.height = src.height;
  dst.pixels.resize(static_cast<std::size_t>(src.width) * src.height);  // within capacity
}

void mirror_gray_rows(ImageView<const std::uint8_t> src, ImageU8& dst, int y_begin, int y_end) {
  for (int y = y_begin; y < y_end; ++y) {
    const std::uint8_t* s = src.row(y);
    std::uint8_t* o = dst.pixels.data() + static_cast<std::size_t>(y) * src.width;
    for (int x = 0; x < src.width; ++x) o[x] = s[src.width - 1 - x];
  }
}

}  // namespace tristereo
