// The tritree's share of Pipeline::working_memory_bytes(): every buffer that
// configure() sizes, by capacity. A buffer added to the tree belongs here too
// (tests/working_memory_test.cpp compares the pipeline's total with the heap).
#include "src/memory/capacity_bytes.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

std::size_t Tritree::working_memory_bytes() const {
  return capacity_bytes(nodes_) + capacity_bytes(new_vertices_) + capacity_bytes(regions_) +
         capacity_bytes(pending_) + capacity_bytes(created_) + capacity_bytes(vertex_id_) +
         capacity_bytes(bucket_) + capacity_bytes(tri_banded_) + capacity_bytes(band_of_row_) +
         capacity_bytes(band_fill_);
}

}  // namespace tristereo
