// The fuzz harnesses' own helpers (tests/fuzz/): how inputs are drawn and how
// PNG CRCs are repaired. A wrong helper would silently narrow what is fuzzed.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_input.hpp"
#include "tests/fuzz/png_crc.hpp"
#include "tristereo/io.hpp"

namespace tristereo {
namespace {

TEST(FuzzInput, DrawsWithinRangesAndDefaultsToTheLowEnd) {
  const std::uint8_t bytes[] = {0xFF, 0x01, 0x02, 7, 200, 0xAB, 0xCD};
  fuzz::FuzzInput in(bytes, sizeof bytes);
  EXPECT_EQ(in.int_in(10, 10), 10);          // an empty span reads no byte
  EXPECT_EQ(in.remaining(), 7u);
  EXPECT_EQ(in.int_in(0, 255), 255);         // one byte
  EXPECT_EQ(in.int_in(-1, 1), -1 + 1 % 3);   // 0x01 % 3
  EXPECT_EQ(in.int_in(0, 999), (2 * 256 + 7) % 1000);  // two bytes, big-endian
  EXPECT_TRUE(in.flag() == false);           // 200 is even
  EXPECT_EQ(in.bytes(5), (std::vector<std::uint8_t>{0xAB, 0xCD}));
  EXPECT_EQ(in.remaining(), 0u);
  EXPECT_EQ(in.int_in(-8, 8), -8);           // exhausted: the low end
  EXPECT_EQ(in.byte(), 0);
  EXPECT_TRUE(in.rest().empty());
}

TEST(PngCrc, KnownAnswerAndRepair) {
  // The CRC every PNG ends with: IEND with no data.
  EXPECT_EQ(fuzz::png_crc32(reinterpret_cast<const std::uint8_t*>("IEND"), 4), 0xAE426082u);
  const std::string path = (std::filesystem::temp_directory_path() / "tristereo_png_crc_test.png").string();
  ImageU8 img(5, 3, 1);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = static_cast<std::uint8_t>(i * 17);
  write_png_u8(path, img.view());
  std::ifstream f(path, std::ios::binary);
  const std::vector<std::uint8_t> good((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::remove(path.c_str());
  ASSERT_GT(good.size(), 33u);
  ASSERT_TRUE(fuzz::has_png_signature(good.data(), good.size()));
  // Repairing a valid file changes nothing; a changed IHDR byte gets its CRC back.
  EXPECT_EQ(fuzz::with_png_crcs_fixed(good.data(), good.size()), good);
  std::vector<std::uint8_t> bad = good;
  bad[16 + 3] ^= 0x01;  // IHDR width 5 -> 4 (bytes 16..19)
  const std::vector<std::uint8_t> fixed = fuzz::with_png_crcs_fixed(bad.data(), bad.size());
  EXPECT_NE(fixed, bad);
  EXPECT_EQ(fuzz::png_crc32(&fixed[12], 17),
            (std::uint32_t{fixed[29]} << 24) | (fixed[30] << 16) | (fixed[31] << 8) | fixed[32]);
  // A truncated file keeps its incomplete last chunk as it was.
  const std::vector<std::uint8_t> cut(good.begin(), good.begin() + 30);
  EXPECT_EQ(fuzz::with_png_crcs_fixed(cut.data(), cut.size()), cut);
  EXPECT_FALSE(fuzz::has_png_signature(good.data() + 1, good.size() - 1));
}

}  // namespace
}  // namespace tristereo
