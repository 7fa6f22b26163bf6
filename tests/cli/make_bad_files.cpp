// Writes the hostile PNG files of tests/cli/cases.txt into a folder: files a
// PNG library would not write on purpose, so they are put together chunk by
// chunk here (zlib for the pixel data, CRC-32 as the PNG spec defines it).
//
//   make_bad_files DIR
//     DIR/huge_claim.png   67 bytes whose header claims 16384 x 16384 RGB
//     DIR/palette_oob.png  8 x 8 palette image, 2 colours, pixels using index 5
//     DIR/text_claim.png   52 bytes: a 4 x 4 header, then a tEXt chunk whose
//                          length field claims 2^31 - 16 bytes (issue 41)
//     DIR/iccp_claim.png   the same with an iCCP chunk
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using Bytes = std::vector<std::uint8_t>;

std::uint32_t crc32_png(const Bytes& data) {
  std::uint32_t c = 0xffffffffu;
  for (std::uint8_t b : data) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xffffffffu;
}

void put32(Bytes& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}

void chunk(Bytes& png, const char* type, const Bytes& body) {
  put32(png, static_cast<std::uint32_t>(body.size()));
  Bytes typed(type, type + 4);
  typed.insert(typed.end(), body.begin(), body.end());
  png.insert(png.end(), typed.begin(), typed.end());
  put32(png, crc32_png(typed));
}

Bytes png_file(std::uint32_t w, std::uint32_t h, std::uint8_t depth, std::uint8_t color, const Bytes& plte,
               const Bytes& raw_rows) {
  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  Bytes ihdr;
  put32(ihdr, w);
  put32(ihdr, h);
  for (std::uint8_t b : {depth, color, std::uint8_t{0}, std::uint8_t{0}, std::uint8_t{0}}) ihdr.push_back(b);
  chunk(png, "IHDR", ihdr);
  if (!plte.empty()) chunk(png, "PLTE", plte);
  uLongf n = compressBound(static_cast<uLong>(raw_rows.size()));
  Bytes z(n);
  if (compress2(z.data(), &n, raw_rows.data(), static_cast<uLong>(raw_rows.size()), 9) != Z_OK) return {};
  z.resize(n);
  chunk(png, "IDAT", z);
  chunk(png, "IEND", {});
  return png;
}

// The signature, a 4 x 4 gray IHDR, then the header of a `type` chunk whose
// length field claims 2^31 - 16 bytes, and the first 11 of them: 52 bytes.
Bytes claiming_chunk(const char* type) {
  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  Bytes ihdr;
  put32(ihdr, 4);
  put32(ihdr, 4);
  ihdr.insert(ihdr.end(), {8, 0, 0, 0, 0});  // 8-bit gray, no interlace
  chunk(png, "IHDR", ihdr);
  put32(png, 0x7ffffff0u);
  png.insert(png.end(), type, type + 4);
  for (char c : std::string("Comment\0abc", 11)) png.push_back(static_cast<std::uint8_t>(c));
  return png;
}

bool save(const std::string& path, const Bytes& b) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const bool ok = !b.empty() && std::fwrite(b.data(), 1, b.size(), f) == b.size();
  return std::fclose(f) == 0 && ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_bad_files DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  // One filter byte of the first row: the rest of the claimed 805 MB is missing.
  const Bytes huge = png_file(16384, 16384, 8, 2, {}, {0});
  Bytes rows;
  for (int y = 0; y < 8; ++y) {
    rows.push_back(0);                          // filter: none
    for (int x = 0; x < 8; ++x) rows.push_back(x < 4 ? 1 : 5);  // 5: beyond the 2 colours
  }
  const Bytes oob = png_file(8, 8, 8, 3, {255, 0, 0, 0, 0, 255}, rows);
  if (!save(dir + "/huge_claim.png", huge) || !save(dir + "/palette_oob.png", oob) ||
      !save(dir + "/text_claim.png", claiming_chunk("tEXt")) ||
      !save(dir + "/iccp_claim.png", claiming_chunk("iCCP"))) {
    std::fprintf(stderr, "make_bad_files: cannot write into %s\n", dir.c_str());
    return 1;
  }
  std::printf("huge_claim.png: %zu bytes\n", huge.size());
  return 0;
}
