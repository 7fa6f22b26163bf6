// The scalar twins of KernelSet::midpoints_row_q4 and midpoints_row_conf_q4:
// the side-2 level of the midpoint interpolation and the rounding to Q4, one
// grid row at a time, the second with the confidence and state beside it.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "src/kernels/kernel_set.hpp"
#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {

namespace {

// (a + b) / 2, exact when both are known (their sum is even and below 2^28);
// wraps without overflow when one is kMidpointUnknown (then unused).
inline std::int32_t midpoint(std::int32_t a, std::int32_t b) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b)) >> 1;
}

// Pixel state from its confidence: 0 invalid, 1..127 filled, 128..255
// measured (src/select/confidence.hpp's state_of_confidence).
inline std::uint8_t state_of(std::uint8_t c) {
  return static_cast<std::uint8_t>((c != 0 ? 1 : 0) + (c >> 7));
}

}  // namespace

void midpoints_row_q4_scalar(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below, int n,
                             int first_backslash, int frac_bits, std::int16_t* disp_q4) {
  const std::int32_t half = std::int32_t{1} << (frac_bits - 1);
  // Odd x whose square has the '\' diagonal: (x >> 1) & 1 equals this.
  const int backslash_pair = first_backslash ? 0 : 1;
  for (int x = 0; x < n; ++x) {
    std::int32_t v = row[x];
    if (v == kMidpointUnknown) {
      if (above == nullptr) v = midpoint(row[x - 1], row[x + 1]);
      else if ((x & 1) == 0) v = midpoint(above[x], below[x]);
      else if (((x >> 1) & 1) == backslash_pair) v = midpoint(above[x - 1], below[x + 1]);
      else v = midpoint(above[x + 1], below[x - 1]);
    }
    disp_q4[x] = static_cast<std::int16_t>((v + half) >> frac_bits);
  }
}

void midpoints_row_conf_q4_scalar(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                                  const std::uint8_t* conf_above, const std::uint8_t* conf_row,
                                  const std::uint8_t* conf_below, int n, int first_backslash, int frac_bits,
                                  std::int16_t* disp_q4, std::uint8_t* confidence, std::uint8_t* state) {
  const std::int32_t half = std::int32_t{1} << (frac_bits - 1);
  const int backslash_pair = first_backslash ? 0 : 1;
  for (int x = 0; x < n; ++x) {
    std::int32_t v = row[x];
    std::uint8_t c = conf_row[x];
    if (v == kMidpointUnknown) {  // the two points it averages, and the smaller of their confidences
      if (above == nullptr) {
        v = midpoint(row[x - 1], row[x + 1]);
        c = std::min(conf_row[x - 1], conf_row[x + 1]);
      } else if ((x & 1) == 0) {
        v = midpoint(above[x], below[x]);
        c = std::min(conf_above[x], conf_below[x]);
      } else if (((x >> 1) & 1) == backslash_pair) {
        v = midpoint(above[x - 1], below[x + 1]);
        c = std::min(conf_above[x - 1], conf_below[x + 1]);
      } else {
        v = midpoint(above[x + 1], below[x - 1]);
        c = std::min(conf_above[x + 1], conf_below[x - 1]);
      }
    }
    disp_q4[x] = static_cast<std::int16_t>((v + half) >> frac_bits);
    confidence[x] = c;
    state[x] = state_of(c);
  }
}

}  // namespace tristereo
