// Filling invalid samples from their valid neighbours (docs/model.md section 6).
//
// Rounds: in each, every invalid sample that has a neighbour valid at the start
// of the round takes the smallest disparity among those neighbours (the
// background: an occluded band belongs to the farther surface), and becomes
// valid for the next round. Stops after a round that filled nothing; samples
// with no valid sample in their connected component stay invalid. Neighbours
// are the mesh edges (sparse) or the 8 surrounding pixels (dense). The result
// does not depend on any processing order.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "src/aggregate/samples.hpp"
#include "src/memory/large_array.hpp"
#include "platform/work_chunks.hpp"

namespace tristereo {

class ThreadPool;

class SampleFill {
 public:
  // Buffers for up to max_samples samples and max_triangles mesh triangles.
  void configure(int max_samples, int max_triangles);
  // Builds the mesh adjacency ahead of fill() (sparse mode; it only needs the
  // mesh, so it can run beside the matching). The next fill() of the same mesh
  // uses it; any other fill() builds its own.
  void prepare(const SampleLayout& samples);
  // Fills disp_q4[0 .. samples.count()) in place (kInvalidDispQ4 = invalid).
  // Returns the number of samples filled. With a pool (called from its owner
  // thread), each round's candidates are found by its workers in chunks; the
  // result is the same for any pool.
  int fill(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool = nullptr);
  // Heap bytes the configured fill holds.
  std::size_t working_memory_bytes() const {
    return (3 * static_cast<std::size_t>(max_samples_) + 1 + 6 * static_cast<std::size_t>(max_triangles_)) *
           sizeof(std::int32_t);
  }

 private:
  void build_adjacency(const SampleLayout& samples);
  int max_samples_ = 0;
  int max_triangles_ = 0;
  const Mesh* prepared_for_ = nullptr;  // prepare()'s mesh, until the next fill()
  WorkChunks chunks_;                   // a round's pending samples, handed out on demand
  LargeArray<std::int32_t> offsets_;    // CSR over samples (sparse)
  LargeArray<std::int32_t> neighbours_;
  LargeArray<std::int32_t> pending_;    // invalid samples still to fill
  LargeArray<std::int32_t> candidate_;  // this round's smallest neighbour
};

}  // namespace tristereo
