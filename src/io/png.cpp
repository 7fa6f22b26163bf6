// PNG through libpng.
//
// libpng reports errors by calling an error callback that must not return.
// Throwing a C++ exception through libpng's C frames is undefined, so the
// callbacks longjmp back to a setjmp in a small function whose frame holds no
// object with a destructor; that function returns false, and ordinary C++ code
// above it (which owns every buffer through RAII) throws tristereo::Error.
#include "src/io/png_codec.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "src/io/file_util.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace io_detail {

namespace {

// Everything the libpng callbacks touch; plain data only.
struct PngContext {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  char message[256] = {0};
};

void on_png_error(png_structp png, png_const_charp msg) {
  auto* ctx = static_cast<PngContext*>(png_get_error_ptr(png));
  std::snprintf(ctx->message, sizeof(ctx->message), "%s", msg ? msg : "unknown libpng error");
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {
  // Warnings (e.g. a bad CRC in an ancillary chunk, which libpng then skips)
  // do not change the pixels we return.
}

void read_from_memory(png_structp png, png_bytep out, png_size_t n) {
  auto* ctx = static_cast<PngContext*>(png_get_io_ptr(png));
  if (n > ctx->size - ctx->pos) png_error(png, "file is truncated");
  std::memcpy(out, ctx->data + ctx->pos, n);
  ctx->pos += n;
}

struct ReadStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~ReadStructs() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

struct Header {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0, interlace = 0;
  int out_channels = 0, out_bit_depth = 0;
};

// Reads the header and installs the transforms. No destructors in this frame.
bool png_read_header(png_structp png, png_infop info, Header* h) {
  if (setjmp(png_jmpbuf(png))) return false;
  // Our own limits are checked after the header; let libpng accept any size
  // so the error names our limit, not libpng's default of 1e6.
  png_set_user_limits(png, 0x7fffffff, 0x7fffffff);
  png_read_info(png, info);
  png_get_IHDR(png, info, &h->width, &h->height, &h->bit_depth, &h->color_type, &h->interlace,
               nullptr, nullptr);
  return true;
}

bool png_setup_transforms(png_structp png, png_infop info, const Header& h, bool keep16,
                          int* passes) {
  if (setjmp(png_jmpbuf(png))) return false;
  if (h.color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (h.color_type == PNG_COLOR_TYPE_GRAY && h.bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  // Alpha and tRNS transparency are dropped (no compositing). The palette
  // expansion also turns tRNS into alpha, hence the tRNS test.
  if ((h.color_type & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS))
    png_set_strip_alpha(png);
  if (keep16 && h.bit_depth == 16 && host_is_little_endian()) png_set_swap(png);
  *passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  return true;
}

bool png_read_pixels(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  // Reads the trailing chunks too, so a file cut after its pixel data still
  // counts as truncated and their CRCs are checked.
  png_read_end(png, nullptr);
  return true;
}

[[noreturn]] void throw_png(const std::string& path, const PngContext& ctx) {
  throw Error(ErrorCode::kCorruptFile, "corrupt PNG '" + path + "': " + ctx.message);
}

}  // namespace

bool is_png(const std::vector<std::uint8_t>& bytes) {
  return bytes.size() >= 8 && png_sig_cmp(bytes.data(), 0, 8) == 0;
}

DecodedPng decode_png(const std::vector<std::uint8_t>& bytes, const std::string& path,
                      bool want16) {
  PngContext ctx;
  ctx.data = bytes.data();
  ctx.size = bytes.size();
  ReadStructs s;
  s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &ctx, on_png_error, on_png_warning);
  if (!s.png) throw Error(ErrorCode::kIoError, "libpng: cannot create read struct");
  s.info = png_create_info_struct(s.png);
  if (!s.info) throw Error(ErrorCode::kIoError, "libpng: cannot create info struct");
  png_set_read_fn(s.png, &ctx, read_from_memory);

  Header h;
  if (!png_read_header(s.png, s.info, &h)) throw_png(path, ctx);
  check_read_size(h.width, h.height, "PNG '" + path + "'");
  if (want16 != (h.bit_depth == 16)) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "PNG '" + path + "' has bit depth " + std::to_string(h.bit_depth) +
                    (want16 ? "; only 16-bit is read here"
                            : "; only 1, 2, 4 and 8-bit are read here (16-bit: read_png_u16)"));
  }
  const bool gray = h.color_type == PNG_COLOR_TYPE_GRAY || h.color_type == PNG_COLOR_TYPE_GRAY_ALPHA;
  if (want16 && !gray) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "PNG '" + path + "' is a 16-bit colour image; only 16-bit gray is read");
  }
  int passes = 0;
  if (!png_setup_transforms(s.png, s.info, h, want16, &passes)) throw_png(path, ctx);

  DecodedPng out;
  out.width = static_cast<int>(h.width);
  out.height = static_cast<int>(h.height);
  out.channels = gray ? 1 : 3;
  out.bytes_per_sample = want16 ? 2 : 1;
  const std::size_t row_bytes =
      static_cast<std::size_t>(out.width) * out.channels * out.bytes_per_sample;
  if (png_get_rowbytes(s.png, s.info) != row_bytes) {
    throw Error(ErrorCode::kUnsupportedFormat, "PNG '" + path + "': unexpected row layout");
  }
  out.pixels.resize(row_bytes * out.height);
  std::vector<png_bytep> rows(out.height);
  for (int y = 0; y < out.height; ++y) rows[y] = out.pixels.data() + row_bytes * y;
  if (!png_read_pixels(s.png, s.info, rows.data())) throw_png(path, ctx);
  return out;
}

namespace {

struct WriteStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~WriteStructs() { png_destroy_write_struct(&png, info ? &info : nullptr); }
};

bool png_write_all(png_structp png, png_infop info, std::FILE* f, png_uint_32 w, png_uint_32 h,
                   int bit_depth, int color_type, bool swap16, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (swap16) png_set_swap(png);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

void encode_png(const std::string& path, const void* data, std::ptrdiff_t stride_bytes, int width,
                int height, int channels, int bit_depth) {
  std::vector<png_bytep> rows(height);
  for (int y = 0; y < height; ++y) {
    // libpng's API takes non-const rows but only reads them when writing.
    rows[y] = const_cast<png_bytep>(static_cast<const png_byte*>(data) + stride_bytes * y);
  }
  PngContext ctx;
  WriteStructs s;
  s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, on_png_error, on_png_warning);
  if (!s.png) throw Error(ErrorCode::kIoError, "libpng: cannot create write struct");
  s.info = png_create_info_struct(s.png);
  if (!s.info) throw Error(ErrorCode::kIoError, "libpng: cannot create info struct");
  OutputFile file(path);
  const int color_type = channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY;
  if (!png_write_all(s.png, s.info, file.get(), static_cast<png_uint_32>(width),
                     static_cast<png_uint_32>(height), bit_depth, color_type,
                     bit_depth == 16 && host_is_little_endian(), rows.data())) {
    throw Error(ErrorCode::kIoError, "cannot write PNG '" + path + "': " + ctx.message);
  }
  file.commit();
}

}  // namespace io_detail
}  // namespace tristereo
