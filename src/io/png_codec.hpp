// Private: the libpng wrapper used by the public readers and writers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "src/io/file_util.hpp"

namespace tristereo {
namespace io_detail {

struct DecodedPng {
  int width = 0, height = 0, channels = 0;  // channels: 1 or 3
  int bytes_per_sample = 1;                 // 2: host-endian uint16 samples
  std::vector<std::uint8_t> pixels;         // tightly packed rows
};

bool is_png(const std::vector<std::uint8_t>& bytes);

// What decode_png reads: the signature and the critical chunks (IHDR, PLTE,
// IDAT, IEND, and any unknown critical chunk, which libpng then refuses) as
// they are in the file, every ancillary chunk left out.
struct PngChunks {
  std::vector<std::uint8_t> bytes;
  std::uint64_t file_bytes = 0;  // of the file walked, ancillary chunks included (for messages)
};

// Walks the chunks of the PNG file `f` whose first bytes (the signature) are
// already in `signature`. Every chunk's length is checked before anything is
// read or allocated for it: at most kMaxPngChunkBytes (the PNG limit), at most
// kMaxPngAncillaryChunkBytes for an ancillary chunk, and never more than the
// rest of a regular file; a violation is kCorruptFile naming the file, the
// chunk and its offset. Ancillary chunks (text, ICC profile, EXIF, unknown)
// are skipped by seeking, never read: none changes the pixels we return.
// Critical chunks are read in bounded pieces, so a stream that ends early
// costs what it held. A short file is not an error here: libpng reports it.
PngChunks read_png_chunks(InputFile& f, std::vector<std::uint8_t> signature);

// want16 = false: 1/2/4/8-bit, gray or colour, out as 8-bit gray/RGB.
// want16 = true: 16-bit gray only. Errors as documented in tristereo/io.hpp.
DecodedPng decode_png(const PngChunks& png, const std::string& path, bool want16);

// Rows are read through stride_bytes; channels 1 or 3; bit_depth 8 or 16.
void encode_png(const std::string& path, const void* data, std::ptrdiff_t stride_bytes, int width,
                int height, int channels, int bit_depth);

}  // namespace io_detail
}  // namespace tristereo
