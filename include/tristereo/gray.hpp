// Colour to gray conversion (docs/model.md, section 0).
//
// The stereo model runs on 8-bit gray images. Colour input is converted with
// BT.601 luma weights in Q8 with rounding:
//   Y = (77 R + 150 G + 29 B + 128) >> 8
// The weights sum to 256, so equal R = G = B gives back the same value (255
// stays 255) and the result never exceeds 255. The conversion is pure integer
// arithmetic, hence identical on every platform.
#pragma once

#include "tristereo/export.hpp"

#include <cstdint>

#include "tristereo/image.hpp"

namespace tristereo {

// One row: `width` RGB triplets in, `width` gray samples out. No checks (a
// kernel): the caller guarantees both pointers cover `width` pixels.
TRISTEREO_API void rgb_to_gray_row_scalar(const std::uint8_t* rgb, int width, std::uint8_t* gray);
// The same for BGR triplets (OpenCV's channel order): exactly
// rgb_to_gray_row_scalar of each triplet reversed, without reversing them
// first. Used by the Python module for order='bgr'.
TRISTEREO_API void bgr_to_gray_row_scalar(const std::uint8_t* bgr, int width, std::uint8_t* gray);

// Converts a 3-channel view into a 1-channel view of the same size (any
// strides), with the row kernel of the kernel set this machine runs
// (KernelChoice::kAuto, so TRISTEREO_KERNELS can force one; every set gives
// the same bytes). Throws Error: kUnsupportedFormat for wrong channel counts,
// kSizeMismatch for different sizes, kInvalidArgument for null data, a
// stride shorter than a row, or a TRISTEREO_KERNELS this machine cannot run.
// `gray` is untouched when it throws.
TRISTEREO_API void rgb_to_gray_bt601(ImageView<const std::uint8_t> rgb, ImageView<std::uint8_t> gray);
// The same for a BGR view (OpenCV's channel order), with the BGR row kernel:
// the gray of the same picture stored as RGB, byte for byte.
TRISTEREO_API void bgr_to_gray_bt601(ImageView<const std::uint8_t> bgr, ImageView<std::uint8_t> gray);

// 1 channel: a copy; 3 channels: BT.601 as above; anything else throws
// Error(kUnsupportedFormat).
TRISTEREO_API ImageU8 to_gray(const ImageU8& img);
TRISTEREO_API ImageU8 to_gray(ImageView<const std::uint8_t> img);

}  // namespace tristereo
