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

#include "tristereo/trace.hpp"

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
  // Buffers for up to max_samples samples and max_triangles mesh triangles,
  // filled by up to `workers` workers.
  void configure(int max_samples, int max_triangles, int workers = 1);
  // Fills disp_q4[0 .. samples.count()) in place (kInvalidDispQ4 = invalid).
  // Returns the number of samples filled. Meshes: each round walks the
  // triangles that still have an invalid corner (no adjacency is built: the
  // first round's walk over all triangles costs less than building one, and
  // the list shrinks fast). With a pool (called from its owner thread), each
  // round's walk (meshes, once it has two chunks of triangles) or each
  // round's candidates (dense grids) are shared by its workers in chunks. The
  // result is the same for any pool.
  // confidence (optional): each filled sample's filled_confidence() of the
  // round that filled it (src/select/confidence.hpp); others untouched.
  int fill(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool = nullptr,
           std::uint8_t* confidence = nullptr);
  // The walks' chunks go to `trace` as work items (null = none; not owned).
  void set_trace(FrameTrace* trace) { trace_ = trace; }
  // Heap bytes the configured fill holds.
  std::size_t working_memory_bytes() const {
    return ((2 + worker_candidate_.size()) * static_cast<std::size_t>(max_samples_) +
            static_cast<std::size_t>(max_triangles_)) *
           sizeof(std::int32_t);
  }

 private:
  FrameTrace* trace_ = nullptr;
  int fill_grid(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool, int pending,
                std::uint8_t* confidence);
  int fill_mesh(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool, int pending,
                std::uint8_t* confidence);
  // Runs body(j0, j1) over [0, n) in chunks (on the pool's workers from two
  // chunks up); each keeps ids in pending_[j0, j0 + kept) and returns kept;
  // joins them up in order at pending_[0, total) and returns the total.
  template <class Body>
  int compacting(ThreadPool* pool, int n, int chunk, Body body);
  // Workers a mesh's walks use: the pool's, up to the candidate arrays configured.
  int mesh_workers(const ThreadPool* pool) const;
  int max_samples_ = 0;
  int max_triangles_ = 0;
  WorkChunks chunks_;                   // a round's pending samples, handed out on demand
  HomeChunks homes_;                    // mesh: a round's walk's chunks of triangles
  LargeArray<std::int32_t> pending_;    // invalid samples still to fill
  LargeArray<std::int32_t> candidate_;  // this round's smallest neighbour (grid: by pending index;
                                        // mesh: by sample id)
  LargeArray<std::int32_t> live_;       // mesh: triangles with an invalid corner
  std::vector<std::int32_t> chunk_live_;  // mesh, with a pool: how many each chunk of a round's walk kept
  std::vector<std::int32_t> chunk_kept_;  // with a pool: how many pending ids each chunk of a scan or round end kept
  std::vector<LargeArray<std::int32_t>> worker_candidate_;  // mesh, with a pool: workers 1.. offer here
};

}  // namespace tristereo
