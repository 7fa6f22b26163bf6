// Public 8/16-bit image readers and writers: format detection by magic bytes.
#include <cstring>
#include <string>

#include "src/io/file_util.hpp"
#include "src/io/png_codec.hpp"
#include "src/io/pnm.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

using namespace io_detail;

namespace {

std::string describe_magic(const std::vector<std::uint8_t>& bytes) {
  std::string s;
  for (std::size_t i = 0; i < bytes.size() && i < 4; ++i) {
    const std::uint8_t c = bytes[i];
    if (c >= 0x20 && c < 0x7f) {
      s += static_cast<char>(c);
    } else {
      static const char* hex = "0123456789abcdef";
      s += "\\x";
      s += hex[c >> 4];
      s += hex[c & 15];
    }
  }
  return s;
}

void check_image_head(const std::vector<std::uint8_t>& head, const std::string& path) {
  if (is_png(head) || is_pnm(head)) return;
  throw Error(ErrorCode::kUnsupportedFormat,
              "'" + path + "' is not a PNG or PGM/PPM file (starts with \"" + describe_magic(head) + "\")");
}

void check_png_head(const std::vector<std::uint8_t>& head, const std::string& path) {
  if (is_png(head)) return;
  throw Error(ErrorCode::kUnsupportedFormat,
              "'" + path + "' is not a PNG file (starts with \"" + describe_magic(head) + "\")");
}

}  // namespace

static ImageU8 read_image_u8_unguarded(const std::string& path);

// std::bad_alloc never leaves a reader (file_util.hpp).
ImageU8 read_image_u8(const std::string& path) {
  return guard_memory(path, [&] { return read_image_u8_unguarded(path); });
}

ImageU8 read_image_u8_unguarded(const std::string& path) {
  InputFile f(path);
  std::vector<std::uint8_t> head;
  f.read(head, 8);  // a PNG's signature: its chunks are then walked, not read whole
  if (is_png(head)) {
    DecodedPng png = decode_png(read_png_chunks(f, std::move(head)), path, /*want16=*/false);
    ImageU8 img;
    img.width = png.width;
    img.height = png.height;
    img.channels = png.channels;
    img.pixels = std::move(png.pixels);
    return img;
  }
  return decode_pnm(f.read_rest(std::move(head), check_image_head), path);
}

static Image<std::uint16_t> read_png_u16_unguarded(const std::string& path);

// std::bad_alloc never leaves a reader (file_util.hpp).
Image<std::uint16_t> read_png_u16(const std::string& path) {
  return guard_memory(path, [&] { return read_png_u16_unguarded(path); });
}

Image<std::uint16_t> read_png_u16_unguarded(const std::string& path) {
  InputFile f(path);
  std::vector<std::uint8_t> head;
  f.read(head, 8);
  // Not a PNG: read_rest's head check throws ("is empty", or what the file starts with).
  if (!is_png(head)) head = f.read_rest(std::move(head), check_png_head);
  DecodedPng png = decode_png(read_png_chunks(f, std::move(head)), path, /*want16=*/true);
  Image<std::uint16_t> img(png.width, png.height, 1);
  std::memcpy(img.pixels.data(), png.pixels.data(), png.pixels.size());
  return img;
}

void write_png_u8(const std::string& path, ImageView<const std::uint8_t> img) {
  check_write_view(img, 1, 3, "write_png_u8");
  encode_png(path, img.data, img.stride_bytes, img.width, img.height, img.channels, 8);
}

void write_png_u16(const std::string& path, ImageView<const std::uint16_t> img) {
  check_write_view(img, 1, 1, "write_png_u16");
  encode_png(path, img.data, img.stride_bytes, img.width, img.height, 1, 16);
}

void write_pgm(const std::string& path, ImageView<const std::uint8_t> img) {
  check_write_view(img, 1, 1, "write_pgm");
  encode_pnm(path, img, 1);
}

void write_ppm(const std::string& path, ImageView<const std::uint8_t> img) {
  check_write_view(img, 3, 3, "write_ppm");
  encode_pnm(path, img, 3);
}

}  // namespace tristereo
