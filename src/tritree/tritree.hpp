// The tritree mesher of the integer path (paper section 3.1; docs/model.md
// section 1 is the exact definition, docs/tritree.md explains the layout).
//
//   Tritree tree;
//   tree.configure(640, 480, params);   // allocates everything, throws Error
//   Mesh mesh;
//   tree.reserve(mesh);                 // so build() never grows `mesh`
//   tree.build(gray, mesh, &pool);      // no heap allocation; pool optional
//
// build() is begin() + rounds + finish(). A round is split into a parallel
// part, evaluate_round() (the criterion of each pending triangle, independent
// work writing one decision byte each), and a serial part, split_round()
// (longest-edge propagation in the model's fixed order). A thread pool can
// drive the stages itself and call evaluate_round() on disjoint bands; the
// result does not depend on how the bands are cut nor on the worker count.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

class ThreadPool;

class Tritree {
 public:
  // Allocates all storage for images up to max_width x max_height (2 ..
  // kMaxImageSide each). Throws Error(kInvalidArgument) naming the bad value
  // (sizes, params.max_area_px2 outside 1..kMaxAreaLimitPx2, psnr_deci_db
  // outside kMinPsnrDeciDb..kMaxPsnrDeciDb); the tree is then unconfigured.
  // The criterion needs no per-worker memory, so any pool size works later.
  void configure(int max_width, int max_height, const TritreeParams& params);
  bool configured() const { return max_width_ > 0; }

  // Reserves capacity in `mesh` so build() never allocates into it.
  // Throws Error(kNotConfigured) before configure().
  void reserve(Mesh& mesh) const;

  // Builds the mesh of `gray` (1 channel, 2 .. max size, stride >= width).
  // Throws Error on bad input, leaving `mesh` untouched. No heap allocation
  // once `mesh` has been reserve()d. With a started `pool` (called from its
  // owner thread), each round's criterion runs on all its workers; the mesh
  // is identical for every pool size.
  void build(ImageView<const std::uint8_t> gray, Mesh& mesh, ThreadPool* pool = nullptr);

  // --- Stages of build(), for drivers that parallelise evaluate_round().
  // Validates `gray` (kept by pointer until finish()) and seeds the two roots.
  void begin(ImageView<const std::uint8_t> gray);
  // Triangles waiting for evaluation in the current round (0 = done).
  int pending_count() const { return pending_count_; }
  // Writes the decision of pending triangles [begin, end): split now or not.
  // Reads shared state only; disjoint ranges may run concurrently.
  void evaluate_round(int begin, int end);
  // Serial: processes the triangles that decided to split, in the model's
  // order, then makes the triangles created by this round pending.
  void split_round();
  // Writes the canonical mesh (raster-order vertices, canonical triangles).
  void finish(Mesh& mesh);

  // --- Diagnostics of the last build.
  int rounds() const { return rounds_; }
  // Leaves whose refinement was blocked by an invalid terminal bisection.
  // Allocates; meant for tests and tools.
  std::vector<std::array<Vertex, 3>> blocked_leaves() const;

 private:
  // One leaf. Slots are recycled: a bisection writes one child over its
  // parent, so `birth` (unique per created triangle) tells a pending entry
  // whether its triangle still exists.
  struct Node {
    std::int16_t x[3];
    std::int16_t y[3];
    std::int32_t nb[3];     // neighbour across edge (i, i+1), -1 on the border
    std::uint32_t birth;
    std::uint8_t longest;   // index of the longest edge (model's edge order)
    std::uint8_t blocked;   // wanted to split but a terminal bisection was invalid
  };
  struct Pending {
    std::int32_t slot;
    std::uint32_t birth;
  };
  // Processing order key: the triangle's three vertex keys, sorted.
  struct OrderKey {
    std::uint64_t k01;
    std::uint32_t k2;
    std::int32_t pending_index;
  };
  static bool order_less(const OrderKey& p, const OrderKey& q) {
    return p.k01 != q.k01 ? p.k01 < q.k01 : p.k2 < q.k2;
  }

  Vertex vertex(const Node& n, int i) const { return Vertex{n.x[i], n.y[i]}; }
  void set_node(std::int32_t slot, const Vertex& a, const Vertex& b, const Vertex& c,
                std::int32_t nab, std::int32_t nbc, std::int32_t nca);
  void replace_link(std::int32_t slot, std::int32_t old_nb, std::int32_t new_nb);
  bool bisect_pair(std::int32_t t, std::int32_t n);
  void process(std::int32_t slot, std::uint32_t birth);
  void validate_image(ImageView<const std::uint8_t> gray) const;
  void promote_created();
  void sort_order(int count);

  int max_width_ = 0;
  int max_height_ = 0;
  TritreeParams params_;
  std::uint64_t mse_q8_ = 0;

  // Per-build state.
  ImageView<const std::uint8_t> gray_;
  int rounds_ = 0;
  std::uint32_t next_birth_ = 0;
  std::int64_t forced_splits_ = 0;
  std::int64_t criterion_splits_ = 0;

  std::vector<Node> nodes_;              // capacity: max leaves
  std::int32_t node_count_ = 0;
  std::vector<Pending> pending_;         // this round's triangles
  int pending_count_ = 0;
  std::vector<std::uint8_t> decision_;   // one per pending triangle
  std::vector<OrderKey> key_;            // per pending triangle, valid when it splits
  std::vector<Pending> created_;         // triangles created this round
  int created_count_ = 0;
  std::vector<OrderKey> order_;          // splitting triangles, sorted
  std::vector<OrderKey> order_tmp_;      // radix sort's second buffer
  std::vector<std::int32_t> radix_count_;  // max(W, H) + 1 counters
  std::vector<std::int32_t> vertex_id_;  // W x H grid, -1 = no vertex
  std::vector<std::int32_t> bucket_;     // counting sort of triangles by first id
  std::vector<Triangle> tri_scratch_;
};

}  // namespace tristereo
