// The tritree's share of Pipeline::working_memory_bytes(): every buffer that
// configure() sizes, by capacity. A buffer added to the tree belongs here too
// (tests/working_memory_test.cpp compares the pipeline's total with the heap).
#include "src/memory/capacity_bytes.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

std::size_t Tritree::working_memory_bytes() const {
  if (!configured()) return 0;
  std::size_t moments = capacity_bytes(side_moments_);
  for (const auto& level : half_moments_) moments += capacity_bytes(level);
  // need (1 byte), vertex ids and sort buckets (4 + 4 bytes) per pixel; one
  // leaf and one rotated triangle per possible leaf; one tile's moments; band starts.
  return pixel_capacity_ * (sizeof(std::uint8_t) + 2 * sizeof(std::int32_t)) + sizeof(std::int32_t) +
         leaf_capacity_ * (sizeof(Leaf) + sizeof(Triangle)) + moments + capacity_bytes(band_start_);
}

}  // namespace tristereo
