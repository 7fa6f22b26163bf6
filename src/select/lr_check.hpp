// Left-right consistency (docs/model.md section 6).
#pragma once

#include <cstdint>

#include "src/aggregate/samples.hpp"
#include "tristereo/image.hpp"

namespace tristereo {

// right_mirrored_q4: the dense disparity map of the right view computed as the
// left view of the mirrored pair (mirror(R), mirror(L)), so right pixel xr is
// at column W - 1 - xr. Left sample i at (x, y) with disparity D = disp_q4[i]
// / 16 matches right pixel xr = x - floor((D_q4 + 8) / 16); it stays valid when
// xr is inside the image, the right map is valid there and
// |disp_q4[i] - right(xr, y)| <= max_diff_q4. Others become kInvalidDispQ4.
// Returns the number of samples invalidated here. Only the samples of image
// rows [y_begin, y_end) (default: all): a sample reads and writes only
// itself, so row ranges may be checked at once on different workers.
int lr_check(const SampleLayout& samples, ImageView<const std::int16_t> right_mirrored_q4,
             int max_diff_q4, std::int16_t* disp_q4, int y_begin = 0, int y_end = -1);

// dst(x, y) = src(W - 1 - x, y), in two steps so that rows can go to
// different workers: size dst as src (stride = width) once, then mirror any
// ranges of rows into it.
void size_mirror(ImageView<const std::uint8_t> src, ImageU8& dst);
void mirror_gray_rows(ImageView<const std::uint8_t> src, ImageU8& dst, int y_begin, int y_end);

}  // namespace tristereo
