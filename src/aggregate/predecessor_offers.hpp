// The mesh predecessors of the path optimizer (docs/model.md section 3b),
// offered edge by edge while a mesher emits its leaves, instead of by a scan
// of the finished mesh (PathMatcher::find_predecessors, which stays the
// reference and the fallback for any other mesh).
//
// A slot holds a key: the candidate's vertex id, with bit 31 set when a
// better kind of edge may still come. On a plain RTIN tile every edge is
// horizontal, vertical or at 45 degrees, so along each direction a candidate
// is either parallel to it (cosine^2 = 1, key bit clear) or at 45 degrees to
// it (cosine^2 = 1/2, bit set), and the smallest key is the model's choice:
// the larger cosine, ties to the smaller id. Other edges (the stretched ones
// of a moved last row or column) are compared exactly, after every key
// offer to the same slot (offer_exact).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>

#include "src/aggregate/samples.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// How far a mesh's predecessors lie from their samples: rows up (at least
// 1), and per pass (0 forward, 1 backward) the pixels ahead along the pass's
// x order per row up, rounded up (the shear of the path passes' tiles,
// PathMatcher's plan). Maxima, so parts of a mesh merge in any order.
struct PredecessorBounds {
  int reach_rows = 1;
  int shear[2] = {0, 0};

  void merge(const PredecessorBounds& o) {
    reach_rows = std::max(reach_rows, o.reach_rows);
    shear[0] = std::max(shear[0], o.shear[0]);
    shear[1] = std::max(shear[1], o.shear[1]);
  }
};

// Where a mesher writes the predecessors of its mesh's vertices: per vertex,
// `directions - 2` slots (directions 2 .. directions - 1), as keys
// (predecessor_of_slot); the layout of PathMatcher's table. `filled`,
// `reach` (a bound on the id distance of a predecessor) and `bounds` (the
// predecessors' extent: widen_predecessor_bounds over every slot) are set by
// the build that filled it.
struct PredecessorTable {
  std::int32_t* slots = nullptr;
  int directions = 0;  // 4 or 8
  bool filled = false;
  int reach = 0;
  PredecessorBounds bounds;
};

namespace predecessor_keys {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;
constexpr std::uint32_t kWorse = 0x80000000u;  // 45 degrees off the direction

inline void offer(std::uint32_t& slot, std::uint32_t key) { slot = std::min(slot, key); }

// An offer whose class is known at compile time. A parallel edge (class 0)
// is the slot's choice outright: it beats every 45-degree one, and a vertex
// has at most one edge in a given direction (the mesh is conforming), so no
// other parallel key can come. A plain store then, not a min.
template <std::uint32_t kClass>
inline void offer_class(std::uint32_t& slot, std::uint32_t id) {
  if constexpr (kClass == 0) {
    slot = id;
  } else {
    offer(slot, id | kClass);
  }
}

// The edge from vertex `from` to vertex `to` = from + (kEx, kEy) of a plain
// RTIN leaf, offered to both ends along the kSlots (2 or 6) directions.
template <int kSlots, int kEx, int kEy>
inline void offer_rtin_edge(std::uint32_t* keys, std::int32_t from, std::int32_t to) {
  if constexpr (kEy != 0) {
    // upper -> lower = (dx, dy), dy > 0; the lower end is p for the
    // directions that come from above (2, 4, 6), the upper end for 3, 5, 7.
    constexpr int dx = kEy > 0 ? kEx : -kEx, dy = kEy > 0 ? kEy : -kEy;
    static_assert(dx == 0 || dx == dy || dx == -dy, "RTIN edges are axis-parallel or diagonal");
    const auto upper = static_cast<std::uint32_t>(kEy > 0 ? from : to);
    const auto lower = static_cast<std::uint32_t>(kEy > 0 ? to : from);
    std::uint32_t* at_lower = keys + static_cast<std::size_t>(lower) * kSlots;
    std::uint32_t* at_upper = keys + static_cast<std::size_t>(upper) * kSlots;
    constexpr std::uint32_t vertical = dx == 0 ? 0u : kWorse;
    offer_class<vertical>(at_lower[0], upper);  // (0, 1)
    offer_class<vertical>(at_upper[1], lower);  // (0, -1)
    if constexpr (kSlots == 6) {
      if constexpr (dx >= 0) {  // (p - q) . u > 0 for u = (1, 1) and (-1, -1)
        constexpr std::uint32_t cls = dx == dy ? 0u : kWorse;
        offer_class<cls>(at_lower[2], upper);
        offer_class<cls>(at_upper[3], lower);
      }
      if constexpr (dx <= 0) {  // u = (-1, 1) and (1, -1)
        constexpr std::uint32_t cls = dx == -dy ? 0u : kWorse;
        offer_class<cls>(at_lower[4], upper);
        offer_class<cls>(at_upper[5], lower);
      }
    }
  }
}

// Any edge a-b of the mesh (v: the vertices), compared exactly with the
// slot's current candidate. Must come after every offer_rtin_edge to the
// same slots (it leaves plain ids, which those would not order).
template <int kSlots>
inline void offer_exact(std::uint32_t* keys, const Vertex* v, std::int32_t a, std::int32_t b) {
  if (v[a].y == v[b].y) return;
  if (v[a].y > v[b].y) std::swap(a, b);  // a above b
  const int ex = v[b].x - v[a].x, ey = v[b].y - v[a].y;  // ey > 0
  for (int s = 0; s < kSlots; ++s) {
    const int r = s + 2;
    const bool from_above = path_runs_forward(r);
    const std::int32_t p = from_above ? b : a, q = from_above ? a : b;
    const int dx = from_above ? ex : -ex, dy = from_above ? ey : -ey;  // p - q
    const PathDirection u = kPathDirections[r];
    if (s >= 2 && dx * u.dx + dy * u.dy <= 0) continue;  // vertical: the dot product is |dy| > 0
    std::uint32_t& slot = keys[static_cast<std::size_t>(p) * kSlots + static_cast<std::size_t>(s)];
    if (slot == kNone) {
      slot = static_cast<std::uint32_t>(q);
      continue;
    }
    const auto best = static_cast<std::int32_t>(slot & ~kWorse);
    const int bdx = v[p].x - v[best].x, bdy = v[p].y - v[best].y;
    bool better;
    if (s < 2) {  // cosine with (0, +-1): the smaller |dx| / |dy|, by cross-multiplication
      const int lhs = std::abs(dx * bdy), rhs = std::abs(bdx * dy);
      better = lhs < rhs || (lhs == rhs && q < best);
    } else {
      better = follows_better(dx, dy, bdx, bdy, u) || (!follows_better(bdx, bdy, dx, dy, u) && q < best);
    }
    if (better) slot = static_cast<std::uint32_t>(q);
  }
}

}  // namespace predecessor_keys

// The predecessor a slot names: a key (offered by a mesher) or an id from
// PathMatcher's scan (whose -1 is kNone and whose ids have bit 31 clear).
inline std::int32_t predecessor_of_slot(std::int32_t slot) {
  const auto key = static_cast<std::uint32_t>(slot);
  return key == predecessor_keys::kNone ? -1 : static_cast<std::int32_t>(key & ~predecessor_keys::kWorse);
}

// Widens *b by the predecessors in slots first_slot, first_slot + slot_step,
// ... (< kSlots) of vertices [begin, end) (v: the vertices). Slot s is
// direction s + 2: the forward pass's when s is even. kSlots (2 or 6) is
// known at compile time, so the loop over a vertex's slots unrolls.
template <int kSlots>
inline void widen_predecessor_bounds(const std::int32_t* slots, const Vertex* v, std::int32_t begin,
                                     std::int32_t end, int first_slot, int slot_step, PredecessorBounds* b) {
  int reach_rows = b->reach_rows, shear[2] = {b->shear[0], b->shear[1]};
  for (std::int32_t i = begin; i < end; ++i) {
    const Vertex p = v[i];
    const std::int32_t* at = slots + static_cast<std::size_t>(i) * kSlots;
    for (int s = first_slot; s < kSlots; s += slot_step) {
      const int q = predecessor_of_slot(at[s]);
      if (q < 0) continue;
      const int dy = std::max(1, std::abs(p.y - v[q].y));
      const int pass = s & 1;  // path_runs_forward(s + 2) ? 0 : 1
      const int ahead = pass == 0 ? v[q].x - p.x : p.x - v[q].x;  // along the pass's x order
      reach_rows = std::max(reach_rows, dy);
      if (ahead > 0) shear[pass] = std::max(shear[pass], (ahead + dy - 1) / dy);
    }
  }
  b->reach_rows = reach_rows;
  b->shear[0] = shear[0];
  b->shear[1] = shear[1];
}

// The same for a table of 2 or 6 slots per vertex, known at run time.
inline void widen_predecessor_bounds(const std::int32_t* slots, int slots_per_vertex, const Vertex* v,
                                     std::int32_t begin, std::int32_t end, int first_slot, int slot_step,
                                     PredecessorBounds* b) {
  if (slots_per_vertex == 2)
    widen_predecessor_bounds<2>(slots, v, begin, end, first_slot, slot_step, b);
  else
    widen_predecessor_bounds<6>(slots, v, begin, end, first_slot, slot_step, b);
}

}  // namespace tristereo
