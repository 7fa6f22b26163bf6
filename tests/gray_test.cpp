#include "tristereo/gray.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "tristereo/status.hpp"

namespace tristereo {
namespace {

std::uint8_t gray_of(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  const std::uint8_t rgb[3] = {r, g, b};
  std::uint8_t out = 0;
  rgb_to_gray_row_scalar(rgb, 1, &out);
  return out;
}

TEST(Gray, HandComputedValues) {
  EXPECT_EQ(gray_of(255, 0, 0), 77);   // (77*255 + 128) >> 8 = 19763 >> 8
  EXPECT_EQ(gray_of(0, 255, 0), 149);  // (150*255 + 128) >> 8 = 38378 >> 8
  EXPECT_EQ(gray_of(0, 0, 255), 29);   // (29*255 + 128) >> 8 = 7523 >> 8
  EXPECT_EQ(gray_of(100, 150, 200), 141);  // 36128 >> 8
  EXPECT_EQ(gray_of(0, 0, 0), 0);
  EXPECT_EQ(gray_of(255, 255, 255), 255);
  EXPECT_EQ(gray_of(1, 0, 0), 0);      // 205 >> 8: rounding, not truncation of 77/256
  EXPECT_EQ(gray_of(2, 0, 0), 1);      // 282 >> 8
}

// BGR rows (the Python module's order='bgr') give exactly the RGB conversion
// of the reversed triplets, for every value of each channel.
TEST(Gray, BgrRowIsTheRgbRowOfTheReversedTriplets) {
  constexpr int kWidth = 256 * 3;
  std::vector<std::uint8_t> rgb(3 * kWidth), bgr(3 * kWidth);
  for (int x = 0; x < kWidth; ++x) {
    // Each channel sweeps 0..255 while the others take unrelated values.
    const int c = x / 256, v = x % 256;
    const std::uint8_t px[3] = {static_cast<std::uint8_t>(c == 0 ? v : (v * 37 + 11) & 255),
                                static_cast<std::uint8_t>(c == 1 ? v : (v * 91 + 5) & 255),
                                static_cast<std::uint8_t>(c == 2 ? v : (v * 13 + 200) & 255)};
    for (int k = 0; k < 3; ++k) {
      rgb[3 * x + k] = px[k];
      bgr[3 * x + 2 - k] = px[k];
    }
  }
  std::vector<std::uint8_t> from_rgb(kWidth + 1, 0xEE), from_bgr(kWidth + 1, 0xEE);
  rgb_to_gray_row_scalar(rgb.data(), kWidth, from_rgb.data());
  bgr_to_gray_row_scalar(bgr.data(), kWidth, from_bgr.data());
  EXPECT_EQ(from_bgr, from_rgb);
  EXPECT_EQ(from_bgr[kWidth], 0xEE);  // nothing written past the row
  EXPECT_EQ(from_bgr[0], gray_of(0, 5, 200));
  // The whole-image function, with the row kernel of the set this machine runs.
  std::vector<std::uint8_t> image(kWidth + 1, 0xEE);
  bgr_to_gray_bt601({bgr.data(), kWidth, 1, 3, 3 * kWidth}, {image.data(), kWidth, 1, 1, kWidth});
  EXPECT_EQ(image, from_rgb);
  EXPECT_THROW(bgr_to_gray_bt601({bgr.data(), kWidth, 1, 1, kWidth}, {image.data(), kWidth, 1, 1, kWidth}), Error);
}

// The conversion takes the kernel set that TRISTEREO_KERNELS forces, so a
// value no machine can run is refused before anything is written.
TEST(Gray, KernelOverrideIsHonouredOrRefused) {
  const char* old = std::getenv("TRISTEREO_KERNELS");
  const std::string saved = old ? old : "";
  const std::vector<std::uint8_t> rgb = {10, 200, 30, 255, 255, 255, 0, 0, 0};
  std::vector<std::uint8_t> out(3, 0xEE);
  const ImageView<const std::uint8_t> in{rgb.data(), 3, 1, 3, 9};
  const ImageView<std::uint8_t> dst{out.data(), 3, 1, 1, 3};
  setenv("TRISTEREO_KERNELS", "scalar", 1);
  rgb_to_gray_bt601(in, dst);
  EXPECT_EQ(out, (std::vector<std::uint8_t>{gray_of(10, 200, 30), 255, 0}));
  out.assign(3, 0xEE);
  setenv("TRISTEREO_KERNELS", "sse3", 1);
  try {
    rgb_to_gray_bt601(in, dst);
    ADD_FAILURE() << "an unknown TRISTEREO_KERNELS was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  }
  EXPECT_EQ(out, std::vector<std::uint8_t>(3, 0xEE));
  if (old) setenv("TRISTEREO_KERNELS", saved.c_str(), 1); else unsetenv("TRISTEREO_KERNELS");
}

TEST(Gray, EqualChannelsKeepTheirValue) {
  for (int v = 0; v < 256; ++v) {
    const auto u = static_cast<std::uint8_t>(v);
    EXPECT_EQ(gray_of(u, u, u), u) << v;
  }
}

TEST(Gray, StridedViewsWriteOnlyTheImage) {
  const int w = 5, h = 3, in_stride = 3 * w + 7, out_stride = w + 3;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(in_stride) * h, 0xEE);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) rgb[y * in_stride + 3 * x + c] = static_cast<std::uint8_t>(40 * c + 10 * x + y);
  std::vector<std::uint8_t> gray(static_cast<std::size_t>(out_stride) * h + 4, 0xAB);
  rgb_to_gray_bt601({rgb.data(), w, h, 3, in_stride}, {gray.data(), w, h, 1, out_stride});
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* p = &rgb[y * in_stride + 3 * x];
      EXPECT_EQ(gray[y * out_stride + x], gray_of(p[0], p[1], p[2]));
    }
    for (int x = w; x < out_stride; ++x) EXPECT_EQ(gray[y * out_stride + x], 0xAB);
  }
  for (int i = 0; i < 4; ++i) EXPECT_EQ(gray[out_stride * h + i], 0xAB);
}

TEST(Gray, ToGrayCopiesOneChannelAndConvertsThree) {
  ImageU8 g(3, 2, 1);
  for (std::size_t i = 0; i < g.pixels.size(); ++i) g.pixels[i] = static_cast<std::uint8_t>(i * 40);
  const ImageU8 copy = to_gray(g);
  EXPECT_EQ(copy.channels, 1);
  EXPECT_EQ(copy.pixels, g.pixels);

  ImageU8 rgb(2, 1, 3);
  rgb.pixels = {255, 0, 0, 100, 150, 200};
  const ImageU8 y = to_gray(rgb);
  ASSERT_EQ(y.channels, 1);
  EXPECT_EQ(y.pixels, (std::vector<std::uint8_t>{77, 141}));
}

TEST(Gray, BadInputThrowsAndLeavesOutputAlone) {
  ImageU8 two(4, 4, 2);
  try {
    to_gray(two);
    FAIL() << "2 channels accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnsupportedFormat);
  }
  ImageU8 rgb(4, 4, 3, 200);
  ImageU8 out(3, 4, 1, 7);
  try {
    rgb_to_gray_bt601(static_cast<const ImageU8&>(rgb).view(), out.view());
    FAIL() << "size mismatch accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kSizeMismatch);
  }
  for (auto v : out.pixels) EXPECT_EQ(v, 7);
  ImageU8 out4(4, 4, 1, 7);
  ImageView<const std::uint8_t> bad_stride = static_cast<const ImageU8&>(rgb).view();
  bad_stride.stride_bytes = 4;  // shorter than a 12-byte RGB row
  EXPECT_THROW(rgb_to_gray_bt601(bad_stride, out4.view()), Error);
  ImageView<const std::uint8_t> null_view{nullptr, 4, 4, 3, 12};
  EXPECT_THROW(rgb_to_gray_bt601(null_view, out4.view()), Error);
  for (auto v : out4.pixels) EXPECT_EQ(v, 7);
}

}  // namespace
}  // namespace tristereo
