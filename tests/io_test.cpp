// Image, disparity and PLY files: round trips, every libpng input variant we
// convert, the Middlebury files, and malformed input of every kind.
#include "tristereo/io.hpp"

#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tristereo/eval.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"
#include "support/data.hpp"

namespace fs = std::filesystem;

namespace tristereo {
namespace {

// ------------------------------------------------------------------ helpers

class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("tristereo_io_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

std::vector<std::uint8_t> read_bytes(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(f), {});
}

void write_bytes(const std::string& p, const std::vector<std::uint8_t>& b) {
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

void write_text(const std::string& p, const std::string& s) {
  write_bytes(p, std::vector<std::uint8_t>(s.begin(), s.end()));
}

ErrorCode code_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.code();
  }
  ADD_FAILURE() << "no tristereo::Error thrown";
  return ErrorCode::kPlatform;  // never expected by these tests
}

template <typename T>
Image<T> pattern(int w, int h, int c, std::uint32_t seed) {
  Image<T> img(w, h, c);
  std::uint32_t s = seed;
  for (auto& v : img.pixels) {
    s = s * 1664525u + 1013904223u;
    v = static_cast<T>(s >> 16);
  }
  return img;
}

template <typename T>
ImageView<const T> cview(const Image<T>& img) {
  return img.view();
}

// Writes an arbitrary PNG variant with libpng directly (the library under test
// only writes 8-bit gray/RGB and 16-bit gray).
// libpng's errors longjmp back into this frame, which changes no local after
// setjmp (a local assigned after it would be indeterminate there: -Wclobbered).
bool write_png_body(png_structp png, png_infop info, std::FILE* f, int w, int h, int bit_depth,
                    int color_type, png_bytep* rows, bool interlace,
                    const std::vector<png_color>& palette, const std::vector<png_byte>& trns) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, bit_depth, color_type,
               interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  if (!palette.empty()) png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
  if (!trns.empty()) png_set_tRNS(png, info, trns.data(), static_cast<int>(trns.size()), nullptr);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

bool write_png_raw(const std::string& p, int w, int h, int bit_depth, int color_type,
                   const std::vector<std::vector<std::uint8_t>>& rows, bool interlace,
                   const std::vector<png_color>& palette, const std::vector<png_byte>& trns) {
  std::FILE* f = std::fopen(p.c_str(), "wb");
  if (!f) return false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> ptrs;
  for (const auto& r : rows) ptrs.push_back(const_cast<png_bytep>(r.data()));
  const bool ok = write_png_body(png, info, f, w, h, bit_depth, color_type, ptrs.data(), interlace,
                                 palette, trns);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
  return ok;
}

// Offsets of the chunk named `type` (its length field) in a PNG byte string.
std::size_t find_chunk(const std::vector<std::uint8_t>& b, const char* type) {
  std::size_t pos = 8;
  while (pos + 12 <= b.size()) {
    const std::uint32_t len = (b[pos] << 24) | (b[pos + 1] << 16) | (b[pos + 2] << 8) | b[pos + 3];
    if (std::memcmp(&b[pos + 4], type, 4) == 0) return pos;
    pos += 12 + len;
  }
  return std::string::npos;
}

void fix_crc(std::vector<std::uint8_t>& b, std::size_t chunk) {
  const std::uint32_t len = (b[chunk] << 24) | (b[chunk + 1] << 16) | (b[chunk + 2] << 8) | b[chunk + 3];
  const uLong crc = crc32(0L, &b[chunk + 4], 4 + len);
  for (int i = 0; i < 4; ++i) b[chunk + 8 + len + i] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
}

// ------------------------------------------------------------------ round trips

TEST_F(IoTest, Png8GrayAndRgbRoundTripThroughStridedViews) {
  for (int c : {1, 3}) {
    const ImageU8 img = pattern<std::uint8_t>(37, 23, c, 5u + c);
    // Same pixels behind a padded stride.
    const int stride = 37 * c + 9;
    std::vector<std::uint8_t> padded(static_cast<std::size_t>(stride) * 23, 0x55);
    for (int y = 0; y < 23; ++y) std::memcpy(&padded[y * stride], img.row(y), 37 * c);
    const std::string p = path("rt" + std::to_string(c) + ".png");
    write_png_u8(p, {padded.data(), 37, 23, c, stride});
    const ImageU8 back = read_image_u8(p);
    EXPECT_EQ(back.width, 37);
    EXPECT_EQ(back.height, 23);
    EXPECT_EQ(back.channels, c);
    EXPECT_EQ(back.pixels, img.pixels);
  }
}

TEST_F(IoTest, Png16RoundTripAndRejectedByTheEightBitReader) {
  const Image<std::uint16_t> img = pattern<std::uint16_t>(19, 11, 1, 77);
  const std::string p = path("u16.png");
  write_png_u16(p, cview(img));
  const Image<std::uint16_t> back = read_png_u16(p);
  EXPECT_EQ(back.width, 19);
  EXPECT_EQ(back.height, 11);
  EXPECT_EQ(back.pixels, img.pixels);
  EXPECT_EQ(code_of([&] { read_image_u8(p); }), ErrorCode::kUnsupportedFormat);
  // And an 8-bit PNG is not a 16-bit one.
  const ImageU8 small = pattern<std::uint8_t>(4, 4, 1, 3);
  write_png_u8(path("u8.png"), cview(small));
  EXPECT_EQ(code_of([&] { read_png_u16(path("u8.png")); }), ErrorCode::kUnsupportedFormat);
}

TEST_F(IoTest, PnmBinaryRoundTripAndAsciiWithComments) {
  const ImageU8 g = pattern<std::uint8_t>(13, 7, 1, 9);
  const ImageU8 rgb = pattern<std::uint8_t>(13, 7, 3, 10);
  write_pgm(path("a.pgm"), cview(g));
  write_ppm(path("a.ppm"), cview(rgb));
  EXPECT_EQ(read_image_u8(path("a.pgm")).pixels, g.pixels);
  const ImageU8 back = read_image_u8(path("a.ppm"));
  EXPECT_EQ(back.channels, 3);
  EXPECT_EQ(back.pixels, rgb.pixels);
  // The header is the standard one.
  const auto bytes = read_bytes(path("a.pgm"));
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 11), "P5\n13 7\n255");

  write_text(path("ascii.pgm"), "P2\n# a comment\n3 2 # trailing\n255\n0 1 2\n253\t254\n255\n");
  const ImageU8 a = read_image_u8(path("ascii.pgm"));
  EXPECT_EQ(a.channels, 1);
  EXPECT_EQ(a.pixels, (std::vector<std::uint8_t>{0, 1, 2, 253, 254, 255}));
  write_text(path("ascii.ppm"), "P3 2 1 255 10 20 30 40 50 60");
  const ImageU8 b = read_image_u8(path("ascii.ppm"));
  EXPECT_EQ(b.channels, 3);
  EXPECT_EQ(b.pixels, (std::vector<std::uint8_t>{10, 20, 30, 40, 50, 60}));
  // Binary P5 with a comment inside the header.
  std::string p5 = "P5 #c\n2 2\n255\n";
  p5 += std::string("\x01\x02\x03\xff", 4);
  write_text(path("c.pgm"), p5);
  EXPECT_EQ(read_image_u8(path("c.pgm")).pixels, (std::vector<std::uint8_t>{1, 2, 3, 255}));
}

TEST_F(IoTest, PfmLayoutIsMiddleburyLittleEndianBottomToTop) {
  Image<float> img(3, 2, 1);
  img.pixels = {1.f, 2.f, 3.f, 4.5f, -5.f, std::numeric_limits<float>::infinity()};
  write_pfm(path("a.pfm"), cview(img));
  const auto b = read_bytes(path("a.pfm"));
  const std::string header = "Pf\n3 2\n-1\n";
  ASSERT_EQ(b.size(), header.size() + 6 * 4);
  EXPECT_EQ(std::string(b.begin(), b.begin() + header.size()), header);
  // The first stored row is the bottom one: 4.5 = 0x40900000 little endian.
  EXPECT_EQ(b[header.size() + 0], 0x00);
  EXPECT_EQ(b[header.size() + 2], 0x90);
  EXPECT_EQ(b[header.size() + 3], 0x40);
  const Image<float> back = read_pfm(path("a.pfm"));
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.pixels, img.pixels);

  Image<float> rgb(2, 3, 3);
  for (std::size_t i = 0; i < rgb.pixels.size(); ++i) rgb.pixels[i] = 0.25f * static_cast<float>(i);
  write_pfm(path("c.pfm"), cview(rgb));
  const Image<float> rgb_back = read_pfm(path("c.pfm"));
  EXPECT_EQ(rgb_back.channels, 3);
  EXPECT_EQ(rgb_back.pixels, rgb.pixels);
}

TEST_F(IoTest, PfmBigEndianIsRead) {
  // 2 x 2, scale +1 (big endian): rows bottom-to-top, so the image is
  // [[3, 4], [1, 2]] top-to-bottom when the file stores 1, 2, 3, 4.
  std::string s = "Pf\n2 2\n1.0\n";
  for (float f : {1.f, 2.f, 3.f, 4.f}) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    for (int i = 3; i >= 0; --i) s += static_cast<char>((u >> (8 * i)) & 0xff);
  }
  write_text(path("be.pfm"), s);
  const Image<float> img = read_pfm(path("be.pfm"));
  EXPECT_EQ(img.pixels, (std::vector<float>{3.f, 4.f, 1.f, 2.f}));
}

// ------------------------------------------------------------------ disparity files

TEST_F(IoTest, DisparityQ4ConversionsAndFiles) {
  ImageS16 d(4, 2, 1);
  d.pixels = {0, 16, 17, 1000, kInvalidDispQ4, 8, 255 * 16, 3};
  const Image<float> f = disp_q4_to_float(cview(d));
  EXPECT_EQ(f.pixels[1], 1.0f);
  EXPECT_EQ(f.pixels[2], 1.0625f);
  EXPECT_EQ(f.pixels[3], 62.5f);
  EXPECT_TRUE(std::isinf(f.pixels[4]) && f.pixels[4] > 0);
  EXPECT_EQ(f.pixels[6], 255.f);

  write_disparity(path("d.PFM"), cview(d));
  EXPECT_EQ(read_pfm(path("d.PFM")).pixels, f.pixels);
  EXPECT_EQ(read_disparity(path("d.PFM")).pixels, d.pixels);

  write_disparity(path("d.png"), cview(d));
  const Image<std::uint16_t> raw = read_png_u16(path("d.png"));
  EXPECT_EQ(raw.pixels, (std::vector<std::uint16_t>{0, 16, 17, 1000, 0, 8, 4080, 3}));
  ImageS16 expect = d;
  expect.pixels[0] = kInvalidDispQ4;  // documented: disparity 0 reads back as invalid
  EXPECT_EQ(read_disparity(path("d.png")).pixels, expect.pixels);

  d.pixels[5] = -3;
  EXPECT_EQ(code_of([&] { write_disparity(path("neg.png"), cview(d)); }),
            ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(path("neg.png")));
  write_disparity(path("neg.pfm"), cview(d));  // PFM stores negatives
  EXPECT_EQ(read_pfm(path("neg.pfm")).pixels[5], -3.f / 16.f);
  EXPECT_EQ(code_of([&] { write_disparity(path("d.tiff"), cview(d)); }),
            ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(path("d.tiff")));
}

TEST_F(IoTest, DisparityColourMap) {
  // Luma rises through the stops; between them it is linear up to the
  // rounding of each channel, so it may dip by one level, never more.
  auto luma_at = [](int t) {
    std::uint8_t c[3];
    disparity_color(t, c);
    return (77 * c[0] + 150 * c[1] + 29 * c[2] + 128) >> 8;
  };
  int prev_luma = -1;
  for (int t = 0; t <= 1024; ++t) {
    EXPECT_GE(luma_at(t), prev_luma - 1) << t;
    prev_luma = luma_at(t);
  }
  EXPECT_EQ(luma_at(0), 23);
  EXPECT_EQ(luma_at(256), 66);
  EXPECT_EQ(luma_at(512), 109);
  EXPECT_EQ(luma_at(768), 168);
  EXPECT_EQ(luma_at(1024), 239);
  EXPECT_EQ(luma_at(-5), 23);     // clamped
  EXPECT_EQ(luma_at(2000), 239);
  std::uint8_t lo[3], hi[3];
  disparity_color(0, lo);
  disparity_color(1024, hi);
  EXPECT_EQ(lo[0], 16);
  EXPECT_EQ(lo[2], 80);
  EXPECT_EQ(hi[1], 245);

  ImageS16 d(3, 1, 1);
  d.pixels = {kInvalidDispQ4, 10 * 16, 73 * 16};  // invalid, d_min, beyond the range
  write_disparity_color(path("c.png"), cview(d), 10, 64);
  const ImageU8 c = read_image_u8(path("c.png"));
  ASSERT_EQ(c.channels, 3);
  EXPECT_EQ(c.at(0, 0, 0) + c.at(0, 0, 1) + c.at(0, 0, 2), 0);
  EXPECT_EQ(c.at(1, 0, 0), lo[0]);
  EXPECT_EQ(c.at(1, 0, 2), lo[2]);
  EXPECT_EQ(c.at(2, 0, 1), hi[1]);  // clamped to the top of the range
  EXPECT_EQ(code_of([&] { write_disparity_color(path("x.png"), cview(d), 0, 0); }),
            ErrorCode::kInvalidArgument);
}

// ------------------------------------------------------------------ PNG variants

TEST_F(IoTest, PngPaletteAlphaAndLowBitDepthsAreConverted) {
  // Palette with transparency: colours come out as RGB, transparency dropped.
  const std::vector<png_color> pal = {{10, 20, 30}, {200, 100, 50}, {0, 255, 0}};
  ASSERT_TRUE(write_png_raw(path("pal.png"), 3, 1, 8, PNG_COLOR_TYPE_PALETTE, {{2, 0, 1}}, false,
                            pal, {0, 128}));
  ImageU8 img = read_image_u8(path("pal.png"));
  EXPECT_EQ(img.channels, 3);
  EXPECT_EQ(img.pixels, (std::vector<std::uint8_t>{0, 255, 0, 10, 20, 30, 200, 100, 50}));

  ASSERT_TRUE(write_png_raw(path("ga.png"), 2, 1, 8, PNG_COLOR_TYPE_GRAY_ALPHA, {{7, 0, 9, 255}},
                            false, {}, {}));
  img = read_image_u8(path("ga.png"));
  EXPECT_EQ(img.channels, 1);
  EXPECT_EQ(img.pixels, (std::vector<std::uint8_t>{7, 9}));

  ASSERT_TRUE(write_png_raw(path("rgba.png"), 2, 1, 8, PNG_COLOR_TYPE_RGB_ALPHA,
                            {{1, 2, 3, 0, 4, 5, 6, 99}}, false, {}, {}));
  img = read_image_u8(path("rgba.png"));
  EXPECT_EQ(img.channels, 3);
  EXPECT_EQ(img.pixels, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6}));

  // 1, 2 and 4-bit gray are scaled to 0..255.
  ASSERT_TRUE(write_png_raw(path("g1.png"), 8, 1, 1, PNG_COLOR_TYPE_GRAY, {{0xA5}}, false, {}, {}));
  EXPECT_EQ(read_image_u8(path("g1.png")).pixels,
            (std::vector<std::uint8_t>{255, 0, 255, 0, 0, 255, 0, 255}));
  ASSERT_TRUE(write_png_raw(path("g2.png"), 4, 1, 2, PNG_COLOR_TYPE_GRAY, {{0x1B}}, false, {}, {}));
  EXPECT_EQ(read_image_u8(path("g2.png")).pixels, (std::vector<std::uint8_t>{0, 85, 170, 255}));
  ASSERT_TRUE(write_png_raw(path("g4.png"), 2, 1, 4, PNG_COLOR_TYPE_GRAY, {{0x3F}}, false, {}, {}));
  EXPECT_EQ(read_image_u8(path("g4.png")).pixels, (std::vector<std::uint8_t>{51, 255}));

  // Interlaced (Adam7) reads the same pixels as non-interlaced.
  const ImageU8 ref = pattern<std::uint8_t>(17, 9, 3, 42);
  std::vector<std::vector<std::uint8_t>> rows;
  for (int y = 0; y < 9; ++y) rows.emplace_back(ref.row(y), ref.row(y) + 17 * 3);
  ASSERT_TRUE(write_png_raw(path("il.png"), 17, 9, 8, PNG_COLOR_TYPE_RGB, rows, true, {}, {}));
  EXPECT_EQ(read_image_u8(path("il.png")).pixels, ref.pixels);

  // 16-bit RGB is neither an 8-bit image nor a 16-bit gray one.
  std::vector<std::vector<std::uint8_t>> rows16 = {std::vector<std::uint8_t>(12, 7)};
  ASSERT_TRUE(write_png_raw(path("rgb16.png"), 2, 1, 16, PNG_COLOR_TYPE_RGB, rows16, false, {}, {}));
  EXPECT_EQ(code_of([&] { read_image_u8(path("rgb16.png")); }), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([&] { read_png_u16(path("rgb16.png")); }), ErrorCode::kUnsupportedFormat);
}

// ------------------------------------------------------------------ Middlebury

TEST_F(IoTest, ReadsEveryMiddleburyPng) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  const std::string root = test::data_set_dir("middlebury");
  const std::vector<MiddleburyScene> scenes = read_datasets_tsv(root + "/datasets.tsv");
  ASSERT_EQ(scenes.size(), 4u);
  int files = 0;
  for (const MiddleburyScene& s : scenes) {
    for (const char* name : {"left", "right", "disp_left", "disp_right", "nonocc", "all", "disc"}) {
      const std::string p = root + "/" + s.name + "/" + name + ".png";
      if (!fs::exists(p)) {
        // Only tsukuba lacks a right-view ground truth.
        EXPECT_TRUE(s.name == "tsukuba" && std::string(name) == "disp_right") << p;
        continue;
      }
      const ImageU8 img = read_image_u8(p);
      ++files;
      EXPECT_EQ(img.width, s.width) << p;
      EXPECT_EQ(img.height, s.height) << p;
      const bool colour = std::string(name) == "left" || std::string(name) == "right";
      EXPECT_EQ(img.channels, colour ? 3 : 1) << p;
      EXPECT_EQ(img.pixels.size(), static_cast<std::size_t>(s.width) * s.height * img.channels);
    }
    // The README's mask properties: nonocc is a subset of all, disc > 0 is nonocc.
    const std::string d = root + "/" + s.name + "/";
    const ImageU8 nonocc = read_image_u8(d + "nonocc.png"), all = read_image_u8(d + "all.png"),
                  disc = read_image_u8(d + "disc.png");
    for (std::size_t i = 0; i < nonocc.pixels.size(); ++i) {
      ASSERT_TRUE(nonocc.pixels[i] != 255 || all.pixels[i] == 255) << s.name << " " << i;
      ASSERT_EQ(disc.pixels[i] > 0, nonocc.pixels[i] == 255) << s.name << " " << i;
    }
  }
  EXPECT_EQ(files, 27);
  // Tsukuba's left view, first pixel, is the same in every read.
  EXPECT_EQ(read_image_u8(root + "/tsukuba/left.png").pixels,
            read_image_u8(root + "/tsukuba/left.png").pixels);
}

TEST_F(IoTest, MiddleburyPngSurvivesPnmAndPngRewrites) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  const ImageU8 left = read_image_u8(test::data_set_dir("middlebury") + "/venus/left.png");
  write_ppm(path("v.ppm"), cview(left));
  write_png_u8(path("v.png"), cview(left));
  // 434 x 383 x 3 bytes of pixels after a 15-byte header, as the README says.
  EXPECT_EQ(fs::file_size(path("v.ppm")), 498681u);
  EXPECT_EQ(read_image_u8(path("v.ppm")).pixels, left.pixels);
  EXPECT_EQ(read_image_u8(path("v.png")).pixels, left.pixels);
}

// ------------------------------------------------------------------ bad input

TEST_F(IoTest, MissingEmptyAndUnknownFiles) {
  EXPECT_EQ(code_of([&] { read_image_u8(path("nope.png")); }), ErrorCode::kIoError);
  EXPECT_EQ(code_of([&] { read_pfm(path("nope.pfm")); }), ErrorCode::kIoError);
  EXPECT_EQ(code_of([&] { read_image_u8(dir_.string()); }), ErrorCode::kIoError);
  write_text(path("empty.png"), "");
  EXPECT_EQ(code_of([&] { read_image_u8(path("empty.png")); }), ErrorCode::kCorruptFile);
  EXPECT_EQ(code_of([&] { read_pfm(path("empty.png")); }), ErrorCode::kCorruptFile);
  write_text(path("text.png"), "hello world, not an image");
  EXPECT_EQ(code_of([&] { read_image_u8(path("text.png")); }), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([&] { read_pfm(path("text.png")); }), ErrorCode::kUnsupportedFormat);
  write_text(path("bmp.png"), "BM\x36\x00\x00\x00");
  EXPECT_EQ(code_of([&] { read_image_u8(path("bmp.png")); }), ErrorCode::kUnsupportedFormat);
  write_text(path("p4.pbm"), "P4\n8 1\n\xff");
  EXPECT_EQ(code_of([&] { read_image_u8(path("p4.pbm")); }), ErrorCode::kUnsupportedFormat);
}

TEST_F(IoTest, TruncatedPngAtEveryLengthIsCorrupt) {
  const ImageU8 img = pattern<std::uint8_t>(12, 8, 3, 1);
  write_png_u8(path("full.png"), cview(img));
  const auto full = read_bytes(path("full.png"));
  ASSERT_GT(full.size(), 300u);
  for (std::size_t len = 1; len < full.size(); ++len) {
    write_bytes(path("cut.png"), std::vector<std::uint8_t>(full.begin(), full.begin() + len));
    const ErrorCode c = code_of([&] { read_image_u8(path("cut.png")); });
    // Fewer than 8 bytes is not even a PNG signature.
    EXPECT_EQ(c, len < 8 ? ErrorCode::kUnsupportedFormat : ErrorCode::kCorruptFile) << len;
  }
}

TEST_F(IoTest, CorruptPngChunksAreRejected) {
  const ImageU8 img = pattern<std::uint8_t>(40, 30, 1, 2);
  write_png_u8(path("ok.png"), cview(img));
  const auto ok = read_bytes(path("ok.png"));
  const std::size_t ihdr = find_chunk(ok, "IHDR"), idat = find_chunk(ok, "IDAT");
  ASSERT_NE(ihdr, std::string::npos);
  ASSERT_NE(idat, std::string::npos);

  auto bad = ok;
  bad[ihdr + 8 + 13] ^= 0x01;  // IHDR CRC
  write_bytes(path("crc.png"), bad);
  EXPECT_EQ(code_of([&] { read_image_u8(path("crc.png")); }), ErrorCode::kCorruptFile);

  bad = ok;
  bad[idat + 8 + 5] ^= 0xFF;  // compressed pixel data (CRC now wrong)
  write_bytes(path("idat.png"), bad);
  EXPECT_EQ(code_of([&] { read_image_u8(path("idat.png")); }), ErrorCode::kCorruptFile);

  bad = ok;
  for (std::size_t i = idat + 8; i < idat + 20; ++i) bad[i] = 0xA5;  // garbage zlib, valid CRC
  fix_crc(bad, idat);
  write_bytes(path("zlib.png"), bad);
  EXPECT_EQ(code_of([&] { read_image_u8(path("zlib.png")); }), ErrorCode::kCorruptFile);

  // An IHDR claiming 100000 x 100000 (valid CRC) is refused before decoding.
  bad = ok;
  for (int k = 0; k < 2; ++k) {
    const std::uint32_t v = 100000;
    for (int i = 0; i < 4; ++i) bad[ihdr + 8 + 4 * k + i] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
  }
  fix_crc(bad, ihdr);
  write_bytes(path("huge.png"), bad);
  EXPECT_EQ(code_of([&] { read_image_u8(path("huge.png")); }), ErrorCode::kUnsupportedFormat);

  // Bit depth 3 does not exist.
  bad = ok;
  bad[ihdr + 8 + 8] = 3;
  fix_crc(bad, ihdr);
  write_bytes(path("depth.png"), bad);
  EXPECT_EQ(code_of([&] { read_image_u8(path("depth.png")); }), ErrorCode::kCorruptFile);
}

TEST_F(IoTest, MalformedPnmHeaders) {
  write_text(path("absurd.pgm"), "P5\n100000000 100000000\n255\n\x01\x02");
  EXPECT_EQ(code_of([&] { read_image_u8(path("absurd.pgm")); }), ErrorCode::kUnsupportedFormat);
  write_text(path("area.pgm"), "P5\n65535 65535\n255\n\x01");  // sides fine, 2^32 px not
  EXPECT_EQ(code_of([&] { read_image_u8(path("area.pgm")); }), ErrorCode::kUnsupportedFormat);
  write_text(path("overflow.ppm"), "P6\n99999999999999999999999 2\n255\n");
  EXPECT_EQ(code_of([&] { read_image_u8(path("overflow.ppm")); }), ErrorCode::kUnsupportedFormat);
  write_text(path("m16.pgm"), "P5\n2 2\n65535\n12345678");
  EXPECT_EQ(code_of([&] { read_image_u8(path("m16.pgm")); }), ErrorCode::kUnsupportedFormat);
  write_text(path("m0.pgm"), "P5\n2 2\n0\n1234");
  EXPECT_EQ(code_of([&] { read_image_u8(path("m0.pgm")); }), ErrorCode::kCorruptFile);
  write_text(path("short.ppm"), "P6\n4 4\n255\n" + std::string(47, 'x'));  // 48 needed
  EXPECT_EQ(code_of([&] { read_image_u8(path("short.ppm")); }), ErrorCode::kCorruptFile);
  write_text(path("zero.pgm"), "P5\n0 4\n255\n");
  EXPECT_EQ(code_of([&] { read_image_u8(path("zero.pgm")); }), ErrorCode::kCorruptFile);
  write_text(path("letters.pgm"), "P5\nab 4\n255\n");
  EXPECT_EQ(code_of([&] { read_image_u8(path("letters.pgm")); }), ErrorCode::kCorruptFile);
  write_text(path("nohdr.pgm"), "P5");
  EXPECT_EQ(code_of([&] { read_image_u8(path("nohdr.pgm")); }), ErrorCode::kCorruptFile);
  write_text(path("big.pgm"), "P2\n2 1\n255\n0 256\n");
  EXPECT_EQ(code_of([&] { read_image_u8(path("big.pgm")); }), ErrorCode::kCorruptFile);
  write_text(path("few.pgm"), "P2\n3 3\n255\n1 2 3\n");
  EXPECT_EQ(code_of([&] { read_image_u8(path("few.pgm")); }), ErrorCode::kCorruptFile);
  // ASCII files claiming a big image are refused before allocating.
  write_text(path("ascii_big.pgm"), "P2\n16384 16384\n255\n1 2 3\n");
  EXPECT_EQ(code_of([&] { read_image_u8(path("ascii_big.pgm")); }), ErrorCode::kCorruptFile);
}

TEST_F(IoTest, MalformedPfm) {
  write_text(path("t.pfm"), "Pf\n2 2\n-1\n" + std::string(15, '\0'));  // 16 bytes needed
  EXPECT_EQ(code_of([&] { read_pfm(path("t.pfm")); }), ErrorCode::kCorruptFile);
  write_text(path("s.pfm"), "Pf\n1 1\n0\n" + std::string(4, '\0'));
  EXPECT_EQ(code_of([&] { read_pfm(path("s.pfm")); }), ErrorCode::kCorruptFile);
  write_text(path("n.pfm"), "Pf\n1 1\nnan\n" + std::string(4, '\0'));
  EXPECT_EQ(code_of([&] { read_pfm(path("n.pfm")); }), ErrorCode::kCorruptFile);
  write_text(path("a.pfm"), "Pf\n100000000 100000000\n-1\n" + std::string(4, '\0'));
  EXPECT_EQ(code_of([&] { read_pfm(path("a.pfm")); }), ErrorCode::kUnsupportedFormat);
  write_text(path("w.pfm"), "Pf\n-2 1\n-1\n" + std::string(8, '\0'));
  EXPECT_EQ(code_of([&] { read_pfm(path("w.pfm")); }), ErrorCode::kCorruptFile);
  write_text(path("m.pfm"), "PX\n1 1\n-1\n" + std::string(4, '\0'));
  EXPECT_EQ(code_of([&] { read_pfm(path("m.pfm")); }), ErrorCode::kUnsupportedFormat);
}

// Random byte damage anywhere in small files: each read either succeeds or
// throws tristereo::Error (run under the sanitizer build to catch overreads).
TEST_F(IoTest, RandomlyDamagedFilesNeverCrash) {
  const ImageU8 img = pattern<std::uint8_t>(16, 12, 3, 3);
  write_png_u8(path("a.png"), cview(img));
  write_ppm(path("a.ppm"), cview(img));
  Image<float> f(5, 4, 1, 1.5f);
  write_pfm(path("a.pfm"), cview(f));
  std::uint32_t s = 12345;
  auto next = [&] { return s = s * 1664525u + 1013904223u; };
  int errors = 0, reads = 0;
  for (const char* name : {"a.png", "a.ppm", "a.pfm"}) {
    const auto good = read_bytes(path(name));
    for (int trial = 0; trial < 150; ++trial) {
      auto bad = good;
      const int hits = 1 + static_cast<int>(next() % 4);
      for (int h = 0; h < hits; ++h) bad[(next() >> 8) % bad.size()] = static_cast<std::uint8_t>(next() >> 24);
      write_bytes(path("bad"), bad);
      try {
        if (std::string(name) == "a.pfm") {
          read_pfm(path("bad"));
        } else {
          read_image_u8(path("bad"));
        }
        ++reads;
      } catch (const Error&) {
        ++errors;
      }
    }
  }
  EXPECT_EQ(errors + reads, 450);
  EXPECT_GT(errors, 0);
}

TEST_F(IoTest, WritersValidateBeforeCreatingFiles) {
  ImageU8 two(4, 4, 2);
  EXPECT_EQ(code_of([&] { write_png_u8(path("x.png"), cview(two)); }), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(path("x.png")));
  ImageView<const std::uint8_t> null_view{nullptr, 4, 4, 1, 4};
  EXPECT_EQ(code_of([&] { write_pgm(path("x.pgm"), null_view); }), ErrorCode::kInvalidArgument);
  const ImageU8 rgb(4, 4, 3);
  EXPECT_EQ(code_of([&] { write_pgm(path("x.pgm"), cview(rgb)); }), ErrorCode::kInvalidArgument);
  ImageView<const std::uint8_t> short_stride = cview(rgb);
  short_stride.stride_bytes = 5;
  EXPECT_EQ(code_of([&] { write_png_u8(path("x.png"), short_stride); }), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(path("x.pgm")));
  EXPECT_FALSE(fs::exists(path("x.png")));
  EXPECT_EQ(code_of([&] { write_png_u8(path("no/such/dir.png"), cview(rgb)); }), ErrorCode::kIoError);
  EXPECT_EQ(code_of([&] { write_pfm(path("no/such/dir.pfm"), cview(Image<float>(2, 2))); }),
            ErrorCode::kIoError);
}

// ------------------------------------------------------------------ PLY

struct PlyFile {
  std::string format;
  std::vector<std::string> properties;
  std::size_t vertices = 0, faces = 0;
  std::vector<std::array<float, 3>> xyz;
  std::vector<std::array<int, 3>> rgb;
  std::vector<std::array<int, 3>> tri;
};

// A small independent PLY parser for the two layouts we write.
PlyFile parse_ply(const std::string& p) {
  const auto b = read_bytes(p);
  const std::string text(b.begin(), b.end());
  const std::size_t end = text.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  PlyFile ply;
  std::istringstream hs(text.substr(0, end));
  std::string line;
  std::getline(hs, line);
  EXPECT_EQ(line, "ply");
  while (std::getline(hs, line)) {
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "format") {
      ls >> ply.format;
    } else if (kw == "element") {
      std::string what;
      std::size_t n;
      ls >> what >> n;
      (what == "vertex" ? ply.vertices : ply.faces) = n;
    } else if (kw == "property") {
      ply.properties.push_back(line.substr(9));
    }
  }
  std::size_t pos = end + 11;
  if (ply.format == "ascii") {
    std::istringstream body(text.substr(pos));
    for (std::size_t i = 0; i < ply.vertices; ++i) {
      std::array<float, 3> v;
      std::array<int, 3> c;
      body >> v[0] >> v[1] >> v[2] >> c[0] >> c[1] >> c[2];
      ply.xyz.push_back(v);
      ply.rgb.push_back(c);
    }
    for (std::size_t i = 0; i < ply.faces; ++i) {
      int n;
      std::array<int, 3> t;
      body >> n >> t[0] >> t[1] >> t[2];
      EXPECT_EQ(n, 3);
      ply.tri.push_back(t);
    }
    std::string rest;
    body >> rest;
    EXPECT_TRUE(body.eof() && rest.empty()) << "trailing data";
  } else {
    EXPECT_EQ(b.size(), pos + ply.vertices * 15 + ply.faces * 13);
    auto u32 = [&](std::size_t at) {
      return static_cast<std::uint32_t>(b[at] | (b[at + 1] << 8) | (b[at + 2] << 16) |
                                        (static_cast<std::uint32_t>(b[at + 3]) << 24));
    };
    for (std::size_t i = 0; i < ply.vertices; ++i, pos += 15) {
      std::array<float, 3> v;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = u32(pos + 4 * k);
        std::memcpy(&v[k], &u, 4);
      }
      ply.xyz.push_back(v);
      ply.rgb.push_back({b[pos + 12], b[pos + 13], b[pos + 14]});
    }
    for (std::size_t i = 0; i < ply.faces; ++i, pos += 13) {
      EXPECT_EQ(b[pos], 3);
      ply.tri.push_back({static_cast<int>(u32(pos + 1)), static_cast<int>(u32(pos + 5)),
                         static_cast<int>(u32(pos + 9))});
    }
  }
  return ply;
}

// 3 x 2 image, vertices at the four corners, two triangles; vertex 3 invalid.
struct SmallMesh {
  Mesh mesh;
  std::vector<std::int16_t> disp;
  ImageU8 gray;
  SmallMesh() : gray(3, 2, 1) {
    mesh.width = 3;
    mesh.height = 2;
    mesh.vertices = {{0, 0}, {2, 0}, {0, 1}, {2, 1}};
    mesh.row_start = {0, 2, 4};
    mesh.triangles = {{0, 2, 1}, {1, 2, 3}};
    disp = {32, 40, 16 * 10, kInvalidDispQ4};
    gray.pixels = {10, 20, 30, 40, 50, 60};
  }
};

TEST_F(IoTest, PlyPixelModeAsciiAndBinaryAgree) {
  SmallMesh m;
  for (bool binary : {false, true}) {
    const std::string p = path(binary ? "b.ply" : "a.ply");
    write_mesh_ply(p, m.mesh, m.disp, cview(m.gray), nullptr, binary);
    const PlyFile ply = parse_ply(p);
    EXPECT_EQ(ply.format, binary ? "binary_little_endian" : "ascii");
    EXPECT_EQ(ply.properties,
              (std::vector<std::string>{"float x", "float y", "float z", "uchar red",
                                        "uchar green", "uchar blue",
                                        "list uchar int vertex_indices"}));
    ASSERT_EQ(ply.vertices, 4u);
    ASSERT_EQ(ply.faces, 1u);  // the face touching the invalid vertex is dropped
    EXPECT_EQ(ply.xyz[0], (std::array<float, 3>{0.f, 0.f, 2.f}));
    EXPECT_EQ(ply.xyz[1], (std::array<float, 3>{2.f, 0.f, 2.5f}));
    EXPECT_EQ(ply.xyz[2], (std::array<float, 3>{0.f, 1.f, 10.f}));
    EXPECT_EQ(ply.xyz[3], (std::array<float, 3>{2.f, 1.f, 0.f}));
    EXPECT_EQ(ply.rgb[1], (std::array<int, 3>{30, 30, 30}));
    EXPECT_EQ(ply.rgb[3], (std::array<int, 3>{60, 60, 60}));
    EXPECT_EQ(ply.tri[0], (std::array<int, 3>{0, 2, 1}));
  }
}

TEST_F(IoTest, PlyCameraModeFollowsMiddleburyFormulas) {
  SmallMesh m;
  ImageU8 rgb(3, 2, 3);
  for (std::size_t i = 0; i < rgb.pixels.size(); ++i) rgb.pixels[i] = static_cast<std::uint8_t>(i);
  // f = 100 px, baseline 50 (mm), principal point (1, 0.5), doffs 2:
  // d = 2 -> Z = 5000 / 4 = 1250; d = 2.5 -> Z = 5000 / 4.5; d = 10 -> Z = 5000 / 12.
  const CameraParams cam{100.0, 50.0, 1.0, 0.5, 2.0};
  write_mesh_ply(path("m.ply"), m.mesh, m.disp, cview(rgb), &cam, true);
  const PlyFile ply = parse_ply(path("m.ply"));
  ASSERT_EQ(ply.vertices, 4u);
  ASSERT_EQ(ply.faces, 1u);
  EXPECT_EQ(ply.xyz[0][2], 1250.f);
  EXPECT_EQ(ply.xyz[0][0], static_cast<float>((0 - 1.0) * 1250.0 / 100.0));
  EXPECT_EQ(ply.xyz[0][1], static_cast<float>((0 - 0.5) * 1250.0 / 100.0));
  const double z1 = 5000.0 / 4.5;
  EXPECT_EQ(ply.xyz[1][2], static_cast<float>(z1));
  EXPECT_EQ(ply.xyz[1][0], static_cast<float>((2 - 1.0) * z1 / 100.0));
  EXPECT_EQ(ply.xyz[3], (std::array<float, 3>{0.f, 0.f, 0.f}));
  EXPECT_EQ(ply.rgb[1], (std::array<int, 3>{6, 7, 8}));  // pixel (2, 0)

  // d + doffs <= 0 has no finite depth: its faces go too.
  const CameraParams behind{100.0, 50.0, 1.0, 0.5, -2.0};  // vertex 0: d + doffs = 0
  write_mesh_ply(path("n.ply"), m.mesh, m.disp, cview(rgb), &behind, false);
  EXPECT_EQ(parse_ply(path("n.ply")).faces, 0u);
}

TEST_F(IoTest, PlyRejectsInconsistentInput) {
  SmallMesh m;
  auto disp = m.disp;
  disp.pop_back();
  EXPECT_EQ(code_of([&] { write_mesh_ply(path("x.ply"), m.mesh, disp, cview(m.gray), nullptr, true); }),
            ErrorCode::kSizeMismatch);
  const ImageU8 wrong(4, 2, 1);
  EXPECT_EQ(code_of([&] { write_mesh_ply(path("x.ply"), m.mesh, m.disp, cview(wrong), nullptr, true); }),
            ErrorCode::kSizeMismatch);
  Mesh bad = m.mesh;
  bad.triangles[1][2] = 4;
  EXPECT_EQ(code_of([&] { write_mesh_ply(path("x.ply"), bad, m.disp, cview(m.gray), nullptr, true); }),
            ErrorCode::kInvalidArgument);
  bad = m.mesh;
  bad.vertices[1].x = 3;
  EXPECT_EQ(code_of([&] { write_mesh_ply(path("x.ply"), bad, m.disp, cview(m.gray), nullptr, true); }),
            ErrorCode::kInvalidArgument);
  const CameraParams zero_f{0.0, 1.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(code_of([&] { write_mesh_ply(path("x.ply"), m.mesh, m.disp, cview(m.gray), &zero_f, true); }),
            ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(path("x.ply")));
}

TEST_F(IoTest, PlyReportsTheFacesItLeavesOut) {
  SmallMesh m;
  const MeshWriteReport pixels = write_mesh_ply(path("p.ply"), m.mesh, m.disp, cview(m.gray), nullptr, true);
  EXPECT_EQ(pixels.faces_written, 1u);
  EXPECT_EQ(pixels.faces_without_disparity, 1u);  // triangle 1 touches the invalid vertex 3
  EXPECT_EQ(pixels.faces_behind_camera, 0u);
  const CameraParams behind{100.0, 50.0, 1.0, 0.5, -2.0};  // vertex 0: d + doffs = 0
  const MeshWriteReport metric = write_mesh_ply(path("n.ply"), m.mesh, m.disp, cview(m.gray), &behind, true);
  EXPECT_EQ(metric.faces_written, 0u);
  EXPECT_EQ(metric.faces_without_disparity, 1u);
  EXPECT_EQ(metric.faces_behind_camera, 1u);
}

TEST_F(IoTest, PlyRefusesACameraThatOverflowsFloat) {
  SmallMesh m;
  const CameraParams huge{1e300, 1e300, 0.0, 0.0, 0.0};  // finite, but Z = B f / d is not
  EXPECT_EQ(code_of([&] { write_mesh_ply(path("x.ply"), m.mesh, m.disp, cview(m.gray), &huge, true); }),
            ErrorCode::kInvalidArgument);
  const CameraParams wide{1.0, 1e38, 1e38, 0.0, 0.0};  // finite Z, X beyond float
  EXPECT_EQ(code_of([&] { write_mesh_ply(path("x.ply"), m.mesh, m.disp, cview(m.gray), &wide, true); }),
            ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(path("x.ply")));
}

}  // namespace
}  // namespace tristereo
