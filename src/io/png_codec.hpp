// Private: the libpng wrapper used by the public readers and writers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tristereo {
namespace io_detail {

struct DecodedPng {
  int width = 0, height = 0, channels = 0;  // channels: 1 or 3
  int bytes_per_sample = 1;                 // 2: host-endian uint16 samples
  std::vector<std::uint8_t> pixels;         // tightly packed rows
};

bool is_png(const std::vector<std::uint8_t>& bytes);

// want16 = false: 1/2/4/8-bit, gray or colour, out as 8-bit gray/RGB.
// want16 = true: 16-bit gray only. Errors as documented in tristereo/io.hpp.
DecodedPng decode_png(const std::vector<std::uint8_t>& bytes, const std::string& path, bool want16);

// Rows are read through stride_bytes; channels 1 or 3; bit_depth 8 or 16.
void encode_png(const std::string& path, const void* data, std::ptrdiff_t stride_bytes, int width,
                int height, int channels, int bit_depth);

}  // namespace io_detail
}  // namespace tristereo
