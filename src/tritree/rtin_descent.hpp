// The descent of a plain RTIN triangle in pass 3 (docs/tritree.md): its
// shape known at compile time, its leaves written rotated, their edges
// offered to the path predecessors by keys. The plain tiles' (tritree_build.cpp)
// and the general tiles' subtrees off the moved lines (tritree_emit_general.cpp)
// each instantiate it in their own file, so the compiler inlines each
// caller's as it would alone (shared, some levels were left out of line).
#pragma once

#include <cstddef>
#include <cstdint>

#include "src/aggregate/predecessor_offers.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {
namespace rtin_descent {

constexpr std::uint8_t kNeed = 1;  // bit 0 of a need byte

// What the descent reads and writes, all in locals, so the leaf stores cannot make the compiler reload the
// tree's members.
struct PlainEmit {
  std::size_t need_stride;
  std::size_t id_stride;
  Triangle* out;
  std::int64_t criterion, forced;
  std::uint32_t* pred_keys;  // kSlots per vertex (predecessor_offers.hpp), when kSlots > 0
  const Vertex* vertices;
  bool left_border;  // the tile is on x = 0
};

// A leaf's ids, rotated to start at the smallest (orientation kept).
inline Triangle rotated(std::int32_t ia, std::int32_t ib, std::int32_t ic) {
  if (ia < ib && ia < ic) return Triangle{ia, ib, ic};
  if (ib < ic) return Triangle{ib, ic, ia};
  return Triangle{ic, ia, ib};
}

// A plain leaf's edge from -> to = from + (kEx, kEy), in the leaf's positive
// orientation. An edge inside the mesh belongs to two leaves, going down in
// one and up in the other: only the one going down offers it. An edge on the
// mesh's border belongs to one leaf: going up on the left border x = 0 (the
// only border a plain tile has, besides the top one, whose edges are
// horizontal); an edge on a general tile's side is offered by that tile.
template <int kSlots, int kEx, int kEy>
inline void offer_leaf_edge(PlainEmit& e, std::int32_t from, std::int32_t to) {
  if constexpr (kEy > 0) {
    predecessor_keys::offer_rtin_edge<kSlots, kEx, kEy>(e.pred_keys, from, to);
  } else if constexpr (kEy < 0 && kEx == 0) {
    if (e.left_border && e.vertices[from].x == 0)
      predecessor_keys::offer_rtin_edge<kSlots, kEx, kEy>(e.pred_keys, from, to);
  }
}

// The triangle whose hypotenuse has midpoint m and whose apex is c = m + d,
// d = (kDx, kDy) known at compile time: positive orientation puts a = m +
// (-kDy, kDx) and b = m + (kDy, -kDx). need_m and id_m point at m's need byte
// and vertex id; ia, ib, ic are the corners' ids. The shape fixes everything
// the descent used to compute per node: where the children's midpoints are,
// which of m's two "wants" bits is this triangle's, and which corner comes
// first in raster order, which is the one with the smallest id (plain tiles'
// ids are raster-ordered), so a leaf's rotation is a compile-time choice.
template <int kSlots, int kDx, int kDy>
inline void emit_rtin(PlainEmit& e, const std::uint8_t* need_m, const std::int32_t* id_m, std::int32_t ia,
                      std::int32_t ib, std::int32_t ic) {
  if constexpr (kDx * kDx + kDy * kDy >= 2) {  // hypotenuse^2 = 4 |d|^2 >= 8: may split
    const std::uint8_t c = *need_m;
    if (c & kNeed) {
      constexpr bool apex_after = kDy > 0 || (kDy == 0 && kDx > 0);
      const std::int64_t wants = (c >> (apex_after ? 1 : 2)) & 1;
      e.criterion += wants;
      e.forced += 1 - wants;
      const std::int32_t im = *id_m;
      // Children (c, a, m) and (b, c, m): their midpoints are m - d1 and m - d2.
      constexpr int d1x = (kDy - kDx) / 2, d1y = -(kDx + kDy) / 2;
      constexpr int d2x = -(kDx + kDy) / 2, d2y = (kDx - kDy) / 2;
      const auto ns = static_cast<std::ptrdiff_t>(e.need_stride);
      const auto is = static_cast<std::ptrdiff_t>(e.id_stride);
      emit_rtin<kSlots, d1x, d1y>(e, need_m - d1x - d1y * ns, id_m - d1x - d1y * is, ic, ia, im);
      emit_rtin<kSlots, d2x, d2y>(e, need_m - d2x - d2y * ns, id_m - d2x - d2y * is, ib, ic, im);
      return;
    }
  }
  // The first corner in raster order (smallest y, then x): a (-kDy, kDx) ~ (y
  // kDx, x -kDy), b (y -kDx, x kDy), c (y kDy, x kDx), relative to m.
  constexpr auto before = [](int y0, int x0, int y1, int x1) { return y0 < y1 || (y0 == y1 && x0 < x1); };
  constexpr bool a_first = before(kDx, -kDy, -kDx, kDy) && before(kDx, -kDy, kDy, kDx);
  constexpr bool b_first = !a_first && before(-kDx, kDy, kDy, kDx);
  if constexpr (a_first) {
    *e.out++ = Triangle{ia, ib, ic};
  } else if constexpr (b_first) {
    *e.out++ = Triangle{ib, ic, ia};
  } else {
    *e.out++ = Triangle{ic, ia, ib};
  }
  if constexpr (kSlots > 0) {
    // Edges a -> b, b -> c, c -> a (a = m + (-kDy, kDx), b = m + (kDy, -kDx), c = m + d).
    offer_leaf_edge<kSlots, 2 * kDy, -2 * kDx>(e, ia, ib);
    offer_leaf_edge<kSlots, kDx - kDy, kDy + kDx>(e, ib, ic);
    offer_leaf_edge<kSlots, -kDy - kDx, kDx - kDy>(e, ic, ia);
  }
}

}  // namespace rtin_descent
}  // namespace tristereo
