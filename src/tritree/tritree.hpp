// The tritree mesher of the integer path (paper section 3.1; docs/model.md
// section 1 is the exact definition, docs/tritree.md explains the layout).
//
//   Tritree tree;
//   tree.configure(640, 480, params);   // allocates everything, throws Error
//   Mesh mesh;
//   tree.reserve(mesh);                 // so build() never grows `mesh`
//   tree.build(gray, mesh, &pool);      // no heap allocation; pool optional
//
// Refinement runs in rounds (docs/model.md section 1). The mesh is the least
// fixpoint of "split every leaf that wants to, with its longest-edge
// propagation", so it does not depend on the order in which splitting
// triangles are processed. build() uses that to run each round on all pool
// workers: after a few serial rounds the leaves are cut into spatial regions
// (kRegionsPerWorker per worker), which the workers take on demand each
// round, each its own home's first (HomeChunks); refining a region touches
// only its own nodes, and a propagation that would cross into another region
// is deferred. Deferred propagations are
// finished in a binary tree over the regions: when both halves of a group of
// neighbouring regions are done, the worker that finished last takes up the
// group's deferred propagations with the whole group as its territory, so
// only those crossing the middle border are left for the last worker.
// Any worker count gives the same mesh (and split counts) as the reference.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "platform/work_chunks.hpp"
#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

class ThreadPool;

class Tritree {
 public:
  static constexpr int kMaxRegions = 64;
  // Regions per pool worker (at most kMaxRegions in all). Taken on demand, so
  // a worker that runs slower (a busy core, a VM neighbour) or a region with
  // more work delays a round by at most about one region, and the regions
  // taken last (the smallest, see build()) are an eighth of a worker's share.
  // More regions mean more propagations crossing a border (finished in the
  // merge tree, mostly in parallel). 8 left both workers idle less than 4 at
  // the end of the rounds (0.5-0.9 ms against 0.75-1.1 ms per 640x480 build).
  static constexpr int kRegionsPerWorker = 8;

  // Allocates all storage for images up to max_width x max_height (2 ..
  // kMaxImageSide each). Throws Error(kInvalidArgument) naming the bad value
  // (sizes, params.max_area_px2 outside 1..kMaxAreaLimitPx2, psnr_deci_db
  // outside kMinPsnrDeciDb..kMaxPsnrDeciDb); the tree is then unconfigured.
  // kMaxRegions regions are allocated here, so any pool size works later.
  void configure(int max_width, int max_height, const TritreeParams& params);
  bool configured() const { return max_width_ > 0; }

  // Reserves capacity in `mesh` so build() never allocates into it.
  // Throws Error(kNotConfigured) before configure().
  void reserve(Mesh& mesh) const;

  // Bytes of the tree's own buffers (allocated capacities; src/tritree/tritree_memory.cpp).
  std::size_t working_memory_bytes() const;

  // Builds the mesh of `gray` (1 channel, 2 .. max size, stride >= width).
  // Throws Error on bad input, leaving `mesh` untouched. No heap allocation
  // once `mesh` has been reserve()d. With a started `pool` (called from its
  // owner thread), each round runs on all its workers; the mesh is identical
  // for every pool size.
  void build(ImageView<const std::uint8_t> gray, Mesh& mesh, ThreadPool* pool = nullptr);

  // --- Diagnostics of the last build.
  int rounds() const { return rounds_; }
  // Regions the leaves were cut into (1: the build ran on one thread).
  int regions() const { return region_count_; }
  // Propagations that crossed a region border and were deferred.
  std::int64_t deferred_propagations() const;
  // Wall time of the last build (monotonic clock), for benchmarks: the
  // refinement rounds, the output, and the time workers spent idle inside
  // parallel rounds (round wall time x workers - their busy time, summed over
  // workers: the ends of uneven rounds and the hand-offs).
  struct BuildTimes {
    std::int64_t rounds_ns = 0;
    std::int64_t round_idle_ns = 0;
    std::int64_t output_ns = 0;
  };
  const BuildTimes& build_times() const { return times_; }
  // True when a region of the last build ran out of node slots and the build
  // was redone on one region (same mesh, slower; see partition()).
  bool fell_back_to_one_region() const { return fell_back_; }
  // For tests: share out at most `slots` spare node slots among the regions
  // (configure() resets it to all of them), to force the fallback.
  void limit_spare_slots_for_testing(std::size_t slots) { spare_limit_ = slots; }
  // Leaves whose refinement was blocked by an invalid terminal bisection.
  // Allocates; meant for tests and tools.
  std::vector<std::array<Vertex, 3>> blocked_leaves() const;

 private:
  // One leaf. Slots are recycled: a bisection writes one child over its
  // parent, so `birth` (unique per created triangle) tells a pending entry
  // whether its triangle still exists. 32 bytes, aligned so that no node
  // straddles two cache lines (the walks over the lists miss on nodes).
  struct alignas(32) Node {
    std::int16_t x[3];
    std::int16_t y[3];
    std::int32_t nb[3];     // neighbour across edge (i, i+1), -1 on the border
    std::uint32_t birth;
    std::uint8_t longest;   // index of the longest edge (model's edge order)
    std::uint8_t blocked;   // wanted to split but a terminal bisection was invalid
    std::uint8_t wants;     // evaluated and wants to split: its split is a criterion split
    // Owner region. Set when the slot is first used and never rewritten in a
    // build, so a worker may read it on a node another worker is writing.
    std::uint8_t region;
  };
  static_assert(sizeof(Node) == 32, "two nodes per cache line");
  struct Pending {
    std::int32_t slot;
    std::uint32_t birth;
  };
  // A spatial part of the mesh, refined by one worker per round. It owns its
  // node slots (new ones come from [slot_begin, slot_end)) and a range of the
  // pending/created lists; Node::region says which region owns a slot.
  struct alignas(64) Region {
    std::int32_t slot_begin = 0, next_slot = 0, slot_end = 0;
    std::int32_t list_begin = 0, list_capacity = 0;
    std::int32_t pending_count = 0;   // after evaluate: the deferred ones, at the front
    std::int32_t created_count = 0;
    // Vertices created by this region's bisections, at new_vertices_[slot_begin ..):
    // each bisection also takes a slot of the region, so they fit.
    std::int32_t vertex_count = 0;
    std::int64_t criterion_splits = 0, forced_splits = 0;
    std::int64_t deferred = 0;  // entries left in pending by refine_region, all rounds
  };
  // Levels of the tree over regions in which deferred propagations are merged.
  static constexpr int kMergeLevels = 7;  // 2^(kMergeLevels - 1) >= kMaxRegions
  static_assert((1 << (kMergeLevels - 1)) >= kMaxRegions, "merge tree too shallow");

  Vertex vertex(const Node& n, int i) const { return Vertex{n.x[i], n.y[i]}; }
  int region_of(std::int32_t slot) const { return nodes_[slot].region; }
  void prefetch_node(std::int32_t slot) const {
#if defined(__GNUC__)
    __builtin_prefetch(&nodes_[static_cast<std::size_t>(slot)]);
#else
    (void)slot;
#endif
  }
  void set_node(std::int32_t slot, const Vertex& a, const Vertex& b, const Vertex& c,
                std::int32_t nab, std::int32_t nbc, std::int32_t nca);
  void replace_link(std::int32_t slot, std::int32_t old_nb, std::int32_t new_nb);
  std::int32_t new_slot(std::int32_t parent);
  void count_split(std::int32_t slot);
  enum class Bisect { kDone, kInvalid, kNoSlot };
  Bisect bisect_pair(std::int32_t t, std::int32_t n);
  // Regions [lo, hi) are the territory a propagation may touch.
  bool process(std::int32_t slot, std::uint32_t birth, int lo, int hi);
  void validate_image(ImageView<const std::uint8_t> gray) const;
  void begin(ImageView<const std::uint8_t> gray);
  bool refine(ImageView<const std::uint8_t> gray, ThreadPool* pool, int want_regions);
  void refine_region(int region, bool local);
  void merge_deferred(int region);
  void process_deferred(int lo, int hi);
  void partition(int region_count);
  void finish(Mesh& mesh, ThreadPool* pool);
  template <class Fn>
  void for_each_slot(Fn&& fn) const;
  template <class Fn>
  void for_each_slot_of_part(int part, int parts, Fn&& fn) const;

  int max_width_ = 0;
  int max_height_ = 0;
  TritreeParams params_;
  std::uint64_t mse_q8_ = 0;

  // Per-build state.
  ImageView<const std::uint8_t> gray_;
  int rounds_ = 0;
  BuildTimes times_;
  bool fell_back_ = false;
  std::size_t spare_limit_ = 0;            // see limit_spare_slots_for_testing()
  std::atomic<bool> out_of_slots_{false};  // a region had no free node slot
  std::int64_t criterion_splits_ = 0;    // of the rounds before partition()
  std::int64_t forced_splits_ = 0;

  std::vector<Node> nodes_;              // capacity: max leaves
  std::int32_t initial_slots_ = 0;       // slots [0, initial_slots_) exist before regions
  // Every bisection creates exactly one new vertex (docs/tritree.md, "Output"),
  // recorded here by the region that made it: new_vertices_[0, initial_vertices_)
  // before the regions were cut, then per region.
  std::vector<Vertex> new_vertices_;     // capacity: max leaves
  std::int32_t initial_vertices_ = 0;
  std::vector<Region> regions_;          // kMaxRegions, region_count_ in use
  int region_count_ = 1;
  HomeChunks region_homes_;              // a parallel round hands regions out, each worker's own first
  // Per merge level and group: how many of the group's two halves are done
  // this round (0 or 1 between rounds).
  std::atomic<int> merge_arrivals_[kMergeLevels][kMaxRegions] = {};
  HomeChunks chunk_homes_;               // the output hands leaf chunks out, each worker's own first
  WorkChunks finish_chunks_;             // the output hands bands out
  std::vector<Pending> pending_;         // per region: this round's triangles
  std::vector<Pending> created_;         // per region: triangles created this round
  std::vector<std::int32_t> vertex_id_;  // W x H grid, -1 = no vertex; partition scratch
  std::vector<std::int32_t> bucket_;     // counting sort of triangles by first id
  std::vector<Triangle> tri_banded_;     // rotated leaves grouped by output band (one per slot)
  std::vector<std::int32_t> band_of_row_;  // output band of each image row
  // Triangles of leaf chunk c whose first vertex is in output band b, then
  // where chunk c's share of band b starts in tri_banded_.
  std::vector<std::int32_t> band_fill_;  // kMaxRegions x kMaxRegions
};

// Every slot that holds a leaf: the slots that existed when the regions were
// cut, then each region's own.
template <class Fn>
void Tritree::for_each_slot(Fn&& fn) const {
  for (std::int32_t s = 0; s < initial_slots_; ++s) fn(s);
  for (int g = 0; g < region_count_; ++g) {
    for (std::int32_t s = regions_[g].slot_begin; s < regions_[g].next_slot; ++s) fn(s);
  }
}

}  // namespace tristereo
