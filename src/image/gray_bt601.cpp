#include "tristereo/gray.hpp"

#include <cstring>
#include <string>

#include "src/kernels/dispatch.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {
// BT.601 in Q8 with rounding. Max is (256 * 255 + 128) >> 8 = 255: no clamp needed.
inline std::uint8_t luma_bt601(unsigned r, unsigned g, unsigned b) {
  return static_cast<std::uint8_t>((77u * r + 150u * g + 29u * b + 128u) >> 8);
}
}  // namespace

void rgb_to_gray_row_scalar(const std::uint8_t* rgb, int width, std::uint8_t* gray) {
  for (int x = 0; x < width; ++x) gray[x] = luma_bt601(rgb[3 * x], rgb[3 * x + 1], rgb[3 * x + 2]);
}

void bgr_to_gray_row_scalar(const std::uint8_t* bgr, int width, std::uint8_t* gray) {
  for (int x = 0; x < width; ++x) gray[x] = luma_bt601(bgr[3 * x + 2], bgr[3 * x + 1], bgr[3 * x]);
}

namespace {

template <typename T>
void check_view(const ImageView<T>& v, const char* what) {
  if (v.data == nullptr) throw Error(ErrorCode::kInvalidArgument, std::string(what) + ": null data");
  if (v.width < 1 || v.height < 1) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + ": size " +
                std::to_string(v.width) + " x " + std::to_string(v.height) +
                " is empty (need at least 1 x 1)");
  }
  const std::ptrdiff_t row_bytes = static_cast<std::ptrdiff_t>(v.width) * v.channels;
  if (v.stride_bytes < row_bytes) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + ": stride_bytes " +
                std::to_string(v.stride_bytes) + " is shorter than a row (" +
                std::to_string(row_bytes) + " bytes)");
  }
}

}  // namespace

void rgb_to_gray_bt601(ImageView<const std::uint8_t> rgb, ImageView<std::uint8_t> gray) {
  if (rgb.channels != 3) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "rgb_to_gray_bt601: input has " + std::to_string(rgb.channels) +
                    " channels, expected 3");
  }
  if (gray.channels != 1) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "rgb_to_gray_bt601: output has " + std::to_string(gray.channels) +
                    " channels, expected 1");
  }
  check_view(rgb, "rgb_to_gray_bt601 input");
  check_view(gray, "rgb_to_gray_bt601 output");
  if (rgb.width != gray.width || rgb.height != gray.height) {
    throw Error(ErrorCode::kSizeMismatch,
                "rgb_to_gray_bt601: input is " + std::to_string(rgb.width) + " x " +
                    std::to_string(rgb.height) + ", output is " + std::to_string(gray.width) +
                    " x " + std::to_string(gray.height));
  }
  // The row kernel of the set this machine runs (TRISTEREO_KERNELS can force
  // one); every set gives the scalar twin's bytes (tests/simd_kernels_test.cpp).
  const auto row = kernel_set_for(KernelChoice::kAuto).rgb_to_gray_row_u8;
  for (int y = 0; y < rgb.height; ++y) row(rgb.row(y), rgb.width, gray.row(y));
}

ImageU8 to_gray(ImageView<const std::uint8_t> img) {
  if (img.channels != 1 && img.channels != 3) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "to_gray: " + std::to_string(img.channels) +
                    " channels; only 1 (gray) or 3 (RGB) are supported");
  }
  check_view(img, "to_gray input");
  ImageU8 out(img.width, img.height, 1);
  if (img.channels == 1) {
    for (int y = 0; y < img.height; ++y)
      std::memcpy(out.row(y), img.row(y), static_cast<std::size_t>(img.width));
  } else {
    rgb_to_gray_bt601(img, out.view());
  }
  return out;
}

ImageU8 to_gray(const ImageU8& img) {
  if (img.channels != 1 && img.channels != 3) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "to_gray: " + std::to_string(img.channels) +
                    " channels; only 1 (gray) or 3 (RGB) are supported");
  }
  if (img.pixels.size() !=
      static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) * img.channels) {
    throw Error(ErrorCode::kInvalidArgument,
                "to_gray: pixel buffer holds " + std::to_string(img.pixels.size()) +
                    " samples, expected width * height * channels");
  }
  return to_gray(img.view());
}

}  // namespace tristereo
