// The tritree's share of Pipeline::working_memory_bytes(): every buffer that
// configure() sizes, by capacity. A buffer added to the tree belongs here too
// (tests/working_memory_test.cpp compares the pipeline's total with the heap).
#include "src/tritree/tritree.hpp"

namespace tristereo {

// One block (see configure()).
std::size_t Tritree::working_memory_bytes() const { return configured() ? arena_bytes_ : 0; }

}  // namespace tristereo
