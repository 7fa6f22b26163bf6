// PNG through libpng.
//
// libpng reports errors by calling an error callback that must not return.
// Throwing a C++ exception through libpng's C frames is undefined, so the
// callbacks longjmp back to a setjmp in a small function whose frame holds no
// object with a destructor; that function returns false, and ordinary C++ code
// above it (which owns every buffer through RAII) throws tristereo::Error.
#include "src/io/png_codec.hpp"

#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "src/io/file_util.hpp"
#include "tristereo/io.hpp"
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
  // Palette images are read as one index per byte and expanded here, not by
  // libpng: its expansion maps an index beyond the palette to black with only
  // a warning, and such a file is corrupt. Their tRNS (transparency) is ignored.
  if (h.color_type == PNG_COLOR_TYPE_PALETTE) png_set_packing(png);
  if (h.color_type == PNG_COLOR_TYPE_GRAY && h.bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  // Alpha is dropped (no compositing). tRNS, like every ancillary chunk, never
  // reaches libpng (read_png_chunks), so transparency is ignored there too.
  if (h.color_type & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(png);
  if (keep16 && h.bit_depth == 16 && host_is_little_endian()) png_set_swap(png);
  *passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  return true;
}

bool png_read_pixels(png_structp png, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  return true;
}

bool png_read_one_row(png_structp png, png_bytep row) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_row(png, row, nullptr);
  return true;
}

// Reads the trailing chunks too, so a file cut after its pixel data still
// counts as truncated and their CRCs are checked.
bool png_read_trailer(png_structp png) {
  if (setjmp(png_jmpbuf(png))) return false;
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

namespace {

std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

// The chunk's type as text for a message: its four letters, or hex escapes.
std::string chunk_type_text(const std::uint8_t* t) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    if (t[i] >= 0x20 && t[i] < 0x7f) {
      s += static_cast<char>(t[i]);
    } else {
      static const char* hex = "0123456789abcdef";
      s += "\\x";
      s += hex[t[i] >> 4];
      s += hex[t[i] & 15];
    }
  }
  return s;
}

bool is_letter(std::uint8_t c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }

}  // namespace

PngChunks read_png_chunks(InputFile& f, std::vector<std::uint8_t> signature) {
  PngChunks out;
  out.bytes = std::move(signature);
  const std::string& path = f.path();
  auto corrupt = [&](const std::string& what) {
    throw Error(ErrorCode::kCorruptFile, "corrupt PNG '" + path + "': " + what);
  };
  for (;;) {
    const std::uint64_t at = f.position();
    const std::size_t start = out.bytes.size();
    if (f.read(out.bytes, 8) < 8) break;  // cut inside a chunk header: libpng says "truncated"
    const std::uint32_t length = be32(&out.bytes[start]);
    std::uint8_t type[4];
    std::memcpy(type, &out.bytes[start + 4], 4);
    const std::string name = "chunk '" + chunk_type_text(type) + "' at byte " + std::to_string(at);
    if (!is_letter(type[0]) || !is_letter(type[1]) || !is_letter(type[2]) || !is_letter(type[3]))
      corrupt(name + " has an invalid type (a chunk type is four ASCII letters)");
    // Data and CRC must be in the file: on a regular file that is a size
    // comparison, made before a single byte of the chunk is read.
    const std::uint64_t need = std::uint64_t{length} + 4;
    if (f.regular() && need > f.size() - std::min(f.size(), f.position())) {
      corrupt(name + " claims " + std::to_string(length) + " bytes, but the " + std::to_string(f.size()) +
              "-byte file ends " + std::to_string(f.size() - std::min(f.size(), f.position())) +
              " bytes after its header");
    }
    // The caps hold for streams too, whose size is unknown.
    // Bit 5 of the first letter (lower case) marks a chunk a decoder may ignore.
    const bool ancillary = (type[0] & 0x20) != 0;
    const std::uint32_t cap = ancillary ? kMaxPngAncillaryChunkBytes : kMaxPngChunkBytes;
    if (length > cap) {
      corrupt(name + " claims " + std::to_string(length) + " bytes, more than the " +
              std::to_string(cap) + "-byte limit on " +
              (ancillary ? "an ancillary chunk" : "a chunk") + " (include/tristereo/io.hpp)");
    }
    if (ancillary) {
      out.bytes.resize(start);
      if (!f.skip(need)) break;  // a stream that ends inside it: truncated
      continue;
    }
    // In pieces, so that memory follows what a stream really delivers.
    std::uint64_t left = need;
    while (left > 0) {
      if (out.bytes.size() >= kMaxReadFileBytes) {
        throw Error(ErrorCode::kUnsupportedFormat, "'" + path + "' is larger than the reader limit of " +
                                                       std::to_string(kMaxReadFileBytes) + " bytes");
      }
      const std::size_t piece = static_cast<std::size_t>(std::min<std::uint64_t>(left, std::uint64_t{1} << 16));
      const std::size_t got = f.read(out.bytes, piece);
      left -= got;
      if (got < piece) break;
    }
    if (left > 0 || std::memcmp(type, "IEND", 4) == 0) break;  // libpng ends at IEND too
  }
  out.file_bytes = f.position();
  return out;
}

DecodedPng decode_png(const PngChunks& png, const std::string& path, bool want16) {
  const std::vector<std::uint8_t>& bytes = png.bytes;
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
                            : "; only 1, 2, 4 and 8-bit images are read here (a 16-bit PNG is a disparity "
                              "or depth map, not a camera image)"));
  }
  const bool gray = h.color_type == PNG_COLOR_TYPE_GRAY || h.color_type == PNG_COLOR_TYPE_GRAY_ALPHA;
  if (want16 && !gray) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "PNG '" + path + "' is a 16-bit colour image; only 16-bit gray is read");
  }
  const bool palette = h.color_type == PNG_COLOR_TYPE_PALETTE;
  const int channels = gray ? 1 : 3;
  const int decoded_channels = palette ? 1 : channels;  // palette: indices
  const int bytes_per_sample = want16 ? 2 : 1;
  const std::size_t decoded_row_bytes =
      static_cast<std::size_t>(h.width) * decoded_channels * bytes_per_sample;
  // Deflate expands at most ~1032:1, so a header claiming more pixel data
  // than that many times the file is a lie: refuse it before allocating.
  // Only the critical chunks count: metadata decodes into no pixel, and
  // must not buy an interlaced image's buffer.
  const std::uint64_t claimed = static_cast<std::uint64_t>(decoded_row_bytes) * h.height;
  if (claimed > static_cast<std::uint64_t>(kMaxPngExpansion) * bytes.size()) {
    const std::string holder = bytes.size() == png.file_bytes
                                   ? "a " + std::to_string(bytes.size()) + "-byte file"
                                   : "the " + std::to_string(bytes.size()) + " bytes of its image chunks (of " +
                                         std::to_string(png.file_bytes) + ")";
    throw Error(ErrorCode::kCorruptFile,
                "corrupt PNG '" + path + "': the header claims " + std::to_string(h.width) + " x " +
                    std::to_string(h.height) + " pixels (" + std::to_string(claimed) + " bytes), more than " +
                    holder + " can hold");
  }
  png_colorp plte = nullptr;
  int plte_size = 0;
  if (palette && png_get_PLTE(s.png, s.info, &plte, &plte_size) == 0) {
    throw Error(ErrorCode::kCorruptFile, "corrupt PNG '" + path + "': palette image without a palette");
  }
  int passes = 0;
  if (!png_setup_transforms(s.png, s.info, h, want16, &passes)) throw_png(path, ctx);
  if (png_get_rowbytes(s.png, s.info) != decoded_row_bytes) {
    throw Error(ErrorCode::kUnsupportedFormat, "PNG '" + path + "': unexpected row layout");
  }

  std::vector<std::uint8_t> decoded;
  if (passes == 1) {
    // Row by row, the buffer growing with the rows actually decoded: a file
    // that ends early costs what it held, not what its header claimed.
    std::vector<std::uint8_t> row(decoded_row_bytes);
    // Real images compress 1.5-4x: reserve at once when the claim is plausible
    // for this file, grow geometrically (one copy of the data on average) when not.
    if (claimed <= 16 * static_cast<std::uint64_t>(bytes.size())) decoded.reserve(static_cast<std::size_t>(claimed));
    for (png_uint_32 y = 0; y < h.height; ++y) {
      if (!png_read_one_row(s.png, row.data())) throw_png(path, ctx);
      decoded.insert(decoded.end(), row.begin(), row.end());
    }
  } else {
    // Interlaced: every pass touches every row; the size is bounded above.
    decoded.resize(static_cast<std::size_t>(claimed));
    std::vector<png_bytep> rows(h.height);
    for (png_uint_32 y = 0; y < h.height; ++y) rows[y] = decoded.data() + decoded_row_bytes * y;
    if (!png_read_pixels(s.png, rows.data())) throw_png(path, ctx);
  }
  if (!png_read_trailer(s.png)) throw_png(path, ctx);

  DecodedPng out;
  out.width = static_cast<int>(h.width);
  out.height = static_cast<int>(h.height);
  out.channels = channels;
  out.bytes_per_sample = bytes_per_sample;
  if (!palette) {
    out.pixels = std::move(decoded);
    return out;
  }
  out.pixels.resize(decoded.size() * 3);
  for (std::size_t i = 0; i < decoded.size(); ++i) {
    const int index = decoded[i];
    if (index >= plte_size) {
      const std::size_t x = i % h.width, y = i / h.width;
      throw Error(ErrorCode::kCorruptFile,
                  "corrupt PNG '" + path + "': pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                      ") has palette index " + std::to_string(index) + " but the palette has " +
                      std::to_string(plte_size) + " entries");
    }
    out.pixels[3 * i] = plte[index].red;
    out.pixels[3 * i + 1] = plte[index].green;
    out.pixels[3 * i + 2] = plte[index].blue;
  }
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
