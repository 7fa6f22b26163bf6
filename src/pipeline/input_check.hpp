// Validation of a stereo pair at the public boundary (shared by Pipeline and
// the reference): throws Error naming the problem; never touches the inputs.
#pragma once

#include <cstdint>

#include <string>

#include "tristereo/image.hpp"
#include "tristereo/status.hpp"

// Header-only so the float reference library (which must not link the integer
// library) shares the same checks.
namespace tristereo {

namespace {
inline std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

inline void check_one(const char* name, ImageView<const std::uint8_t> v, int max_w, int max_h) {
  const std::string n = name;
  if (v.data == nullptr) throw Error(ErrorCode::kInvalidArgument, n + " image has no data (null pointer)");
  if (v.channels != 1 && v.channels != 3)
    throw Error(ErrorCode::kUnsupportedFormat,
                n + " image has " + std::to_string(v.channels) + " channels (expected 1 = gray or 3 = RGB)");
  if (v.width < 2 || v.height < 2)
    throw Error(ErrorCode::kInvalidArgument,
                n + " image is " + size_str(v.width, v.height) + "; at least 2x2 is required");
  if (v.width > max_w || v.height > max_h)
    throw Error(ErrorCode::kInvalidArgument, n + " image is " + size_str(v.width, v.height) +
                                                 ", larger than the configured maximum " +
                                                 size_str(max_w, max_h));
  const std::ptrdiff_t min_stride = static_cast<std::ptrdiff_t>(v.width) * v.channels;
  if (v.stride_bytes < min_stride)
    throw Error(ErrorCode::kInvalidArgument, n + " image stride " + std::to_string(v.stride_bytes) +
                                                 " bytes is smaller than a row (" +
                                                 std::to_string(min_stride) + " bytes)");
}
}  // namespace

inline void check_stereo_inputs(ImageView<const std::uint8_t> left, ImageView<const std::uint8_t> right,
                         int max_width, int max_height) {
  check_one("left", left, max_width, max_height);
  check_one("right", right, max_width, max_height);
  if (left.width != right.width || left.height != right.height)
    throw Error(ErrorCode::kSizeMismatch, "left image is " + size_str(left.width, left.height) +
                                              " but right image is " + size_str(right.width, right.height));
  if (left.channels != right.channels)
    throw Error(ErrorCode::kSizeMismatch, "left and right images have different channel counts");
}

}  // namespace tristereo
