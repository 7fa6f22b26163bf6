// Sample confidence and state (docs/model.md section 7), the integer path's
// rules; the float reference transcribes them on its own (src/reference).
#pragma once

#include <algorithm>
#include <cstdint>

#include "tristereo/mesh.hpp"

namespace tristereo {

// A measured sample whose best summed path cost is `best` and whose rival
// (the smallest summed cost two or more disparities away, 65535 when there is
// none) is `rival`: 128 + floor(127 (rival - best) / rival), 128 when rival
// is 0. rival >= best (best is the minimum), both <= 65535, so the product
// stays below 2^23.
inline std::uint8_t measured_confidence(std::uint32_t best, std::uint32_t rival) {
  if (rival == 0) return kMinMeasuredConfidence;
  return static_cast<std::uint8_t>(kMinMeasuredConfidence + 127u * (rival - best) / rival);
}

// The row DP keeps no summed costs to compare: every measured sample gets this.
constexpr std::uint8_t kRowDpMeasuredConfidence = 255;

// A sample filled in fill round r >= 1 (its nearest measured sample is r mesh
// edges away): max(1, 128 - 8 r).
inline std::uint8_t filled_confidence(int round) {
  return static_cast<std::uint8_t>(std::max(1, kMinMeasuredConfidence - 8 * std::min(round, 16)));
}

inline std::uint8_t state_of_confidence(std::uint8_t c) {
  return static_cast<std::uint8_t>(c == 0 ? SampleState::kInvalid
                                          : c < kMinMeasuredConfidence ? SampleState::kFilled
                                                                       : SampleState::kMeasured);
}

}  // namespace tristereo
