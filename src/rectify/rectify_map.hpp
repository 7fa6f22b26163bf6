// The remap of rows of one camera (the stage's unit of work): the row kernel
// for the pixels inside, then the border pixels of those rows.
#pragma once

#include <cstdint>

#include "src/kernels/kernel_set.hpp"
#include "tristereo/rectify.hpp"

namespace tristereo {

// Rows [v0, v1) of `out` (the map's rectified size) from `raw` (the map's raw
// size, gray). No allocation, no checks: the caller checked the sizes.
void remap_rows(const RectifyMap& map, ImageView<const std::uint8_t> raw, ImageView<std::uint8_t> out, int v0, int v1,
                const KernelSet& kernels);

// One border pixel, tap by tap with p = 0 outside the raw image.
std::uint8_t remap_border_pixel(const RectifyMap::Border& b, ImageView<const std::uint8_t> raw);

}  // namespace tristereo
