// PNG chunk CRCs recomputed, so mutated files get past libpng's CRC check.
//
// libpng rejects a critical chunk whose CRC does not match, and a random
// mutation almost never keeps the CRC right: without this, a fuzzer spends its
// time on CRC errors and rarely reaches the header and pixel checks behind
// them. The PNG harnesses read every input as it is and, when it starts with
// the PNG signature, once more with every complete chunk's CRC repaired.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tristereo::fuzz {

// CRC-32 of the PNG specification (ISO 3309, polynomial 0xEDB88320,
// reflected, initial and final XOR 0xFFFFFFFF).
inline std::uint32_t png_crc32(const std::uint8_t* p, std::size_t n) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xFFFFFFFFu;
}

inline bool has_png_signature(const std::uint8_t* data, std::size_t size) {
  static const std::uint8_t kSig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (size < 8) return false;
  for (int i = 0; i < 8; ++i)
    if (data[i] != kSig[i]) return false;
  return true;
}

// A copy of a PNG file with the CRC of every chunk that lies wholly inside the
// file recomputed (a truncated last chunk is left as it is).
inline std::vector<std::uint8_t> with_png_crcs_fixed(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> out(data, data + size);
  std::size_t pos = 8;
  while (pos + 12 <= out.size()) {
    const std::size_t len = (std::size_t{out[pos]} << 24) | (std::size_t{out[pos + 1]} << 16) |
                            (std::size_t{out[pos + 2]} << 8) | out[pos + 3];
    if (len > out.size() - pos - 12) break;
    const std::uint32_t crc = png_crc32(&out[pos + 4], len + 4);  // type + data
    const std::size_t at = pos + 8 + len;
    for (int k = 0; k < 4; ++k) out[at + k] = static_cast<std::uint8_t>(crc >> (24 - 8 * k));
    pos = at + 4;
  }
  return out;
}

}  // namespace tristereo::fuzz
