// 16-bit disparity PNGs in both conventions users exchange: Q4 (value = 16 d)
// and KITTI (value = 256 d), written and read back exactly.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

std::string tmp(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("tristereo_dispfmt_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(DisparityFormat, KittiAndQ4RoundTripEveryStorableValue) {
  // Every Q4 value 1 .. 4095 (d < 256 px) plus invalid pixels.
  Image<std::int16_t> d(64, 65, 1);
  for (std::size_t i = 0; i < d.pixels.size(); ++i)
    d.pixels[i] = i % 97 == 3 ? kInvalidDispQ4 : static_cast<std::int16_t>(1 + i % 4095);
  for (DispPngScale s : {DispPngScale::kQ4, DispPngScale::kKitti}) {
    const std::string p = tmp(s == DispPngScale::kKitti ? "k.png" : "q.png");
    write_disparity(p, d.view(), s);
    EXPECT_EQ(read_disparity(p, s).pixels, d.pixels);
    // The raw file holds value = d * scale.
    const Image<std::uint16_t> raw = read_png_u16(p);
    EXPECT_EQ(raw.pixels[0], 1 * static_cast<int>(s) / 16);
    EXPECT_EQ(raw.pixels[3], 0);
    std::filesystem::remove(p);
  }
}

TEST(DisparityFormat, KittiValuesNotOnTheQ4GridRoundHalfUp) {
  Image<std::uint16_t> raw(4, 1, 1);
  raw.pixels = {256, 264, 263, 65535};  // 1 px, 1.03125 px, 1.02734 px, 255.996 px
  const std::string p = tmp("kraw.png");
  write_png_u16(p, raw.view());
  const Image<std::int16_t> q4 = read_disparity(p, DispPngScale::kKitti);
  EXPECT_EQ(q4.pixels[0], 16);
  EXPECT_EQ(q4.pixels[1], 17);  // 16.5 -> 17
  EXPECT_EQ(q4.pixels[2], 16);
  EXPECT_EQ(q4.pixels[3], 4096);
  // Read as Q4, 65535 is out of range, and the message suggests KITTI.
  try {
    read_disparity(p, DispPngScale::kQ4);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorruptFile);
    EXPECT_NE(std::string(e.what()).find("KITTI"), std::string::npos) << e.what();
  }
  std::filesystem::remove(p);
}

TEST(DisparityFormat, KittiRefusesWhatItCannotStore) {
  Image<std::int16_t> d(2, 1, 1, 16);
  d.pixels[1] = 4096;  // 256 px: 65536 does not fit
  try {
    write_disparity(tmp("big.png"), d.view(), DispPngScale::kKitti);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("(1, 0)"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(tmp("big.png")));
}

}  // namespace
}  // namespace tristereo
