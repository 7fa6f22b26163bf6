#include "src/cost/byte_means.hpp"

#include <algorithm>

namespace tristereo {

namespace {

bool matches_q32(std::uint32_t inv_q15, std::uint64_t inv_q32, int max_sum) {
  for (std::uint32_t s = 0; s <= static_cast<std::uint32_t>(max_sum); ++s)
    if (byte_mean_q4(s, inv_q15) != ((16u * s * inv_q32 + (std::uint64_t{1} << 31)) >> 32))
      return false;
  return true;
}

}  // namespace

std::uint16_t byte_mean_inv_q15(int pixels, int max_sum) {
  if (pixels < 1 || max_sum < 0 || max_sum > 255) return 0;
  const std::uint64_t inv_q32 = (std::uint64_t{1} << 32) / static_cast<std::uint64_t>(pixels);
  const std::int64_t centre = (std::int64_t{1} << 15) / pixels;
  const std::int64_t lo = std::max<std::int64_t>(1, centre - 32), hi = std::min<std::int64_t>(0x7FFF, centre + 32);
  for (std::int64_t m = lo; m <= hi; ++m)
    if (matches_q32(static_cast<std::uint32_t>(m), inv_q32, max_sum)) return static_cast<std::uint16_t>(m);
  return 0;
}

}  // namespace tristereo
