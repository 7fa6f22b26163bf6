// Private: Netpbm reader and writer behind tristereo/io.hpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tristereo/image.hpp"

namespace tristereo {
namespace io_detail {

bool is_pnm(const std::vector<std::uint8_t>& bytes);  // "P1".."P7"
ImageU8 decode_pnm(const std::vector<std::uint8_t>& bytes, const std::string& path);
// channels 1 -> P5, 3 -> P6; the view is already validated.
void encode_pnm(const std::string& path, ImageView<const std::uint8_t> img, int channels);

}  // namespace io_detail
}  // namespace tristereo
