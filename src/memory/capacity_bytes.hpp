// Bytes a buffer holds allocated: what working_memory_bytes() accessors add up
// (capacity, not size: configure() allocates for the largest frame).
#pragma once

#include <cstddef>

namespace tristereo {

template <typename Vector>
std::size_t capacity_bytes(const Vector& v) {
  return v.capacity() * sizeof(typename Vector::value_type);
}

}  // namespace tristereo
