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

namespace {
// Checks both views, then converts row by row with `row` (named `fn` in messages).
void colour_to_gray(ImageView<const std::uint8_t> in, ImageView<std::uint8_t> gray, const char* fn,
                    void (*row)(const std::uint8_t*, int, std::uint8_t*)) {
  if (in.channels != 3) {
    throw Error(ErrorCode::kUnsupportedFormat,
                std::string(fn) + ": input has " + std::to_string(in.channels) + " channels, expected 3");
  }
  if (gray.channels != 1) {
    throw Error(ErrorCode::kUnsupportedFormat,
                std::string(fn) + ": output has " + std::to_string(gray.channels) + " channels, expected 1");
  }
  check_view(in, (std::string(fn) + " input").c_str());
  check_view(gray, (std::string(fn) + " output").c_str());
  if (in.width != gray.width || in.height != gray.height) {
    throw Error(ErrorCode::kSizeMismatch,
                std::string(fn) + ": input is " + std::to_string(in.width) + " x " + std::to_string(in.height) +
                    ", output is " + std::to_string(gray.width) + " x " + std::to_string(gray.height));
  }
  for (int y = 0; y < in.height; ++y) row(in.row(y), in.width, gray.row(y));
}
}  // namespace

// The row kernels of the set this machine runs (TRISTEREO_KERNELS can force
// one); every set gives the scalar twin's bytes (tests/simd_kernels_test.cpp).
void rgb_to_gray_bt601(ImageView<const std::uint8_t> rgb, ImageView<std::uint8_t> gray) {
  colour_to_gray(rgb, gray, "rgb_to_gray_bt601", kernel_set_for(KernelChoice::kAuto).rgb_to_gray_row_u8);
}

void bgr_to_gray_bt601(ImageView<const std::uint8_t> bgr, ImageView<std::uint8_t> gray) {
  colour_to_gray(bgr, gray, "bgr_to_gray_bt601", kernel_set_for(KernelChoice::kAuto).bgr_to_gray_row_u8);
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
