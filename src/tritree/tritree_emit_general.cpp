// Pass 3 of the general tiles (the last column's and the last row's): their
// triangles off the moved last row and column are plain RTIN triangles and
// take the plain descent (rtin_descent.hpp); the others split at need, and
// their leaves, the stretched ones, offer their edges exactly once the row
// of tiles is done (docs/tritree.md).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "src/aggregate/predecessor_offers.hpp"
#include "src/tritree/rtin_descent.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

namespace {

using rtin_descent::emit_rtin;
using rtin_descent::kNeed;
using rtin_descent::PlainEmit;
using rtin_descent::rotated;

// A general tile's triangle with apex offset (dx, dy) from its hypotenuse's
// midpoint, known only at run time, handed to the descent of its shape (d is
// (+-h, +-h), (+-h, 0) or (0, +-h) for a power of two h <= kH).
template <int kSlots, int kH>
inline void emit_rtin_shape(PlainEmit& e, int dx, int dy, const std::uint8_t* need_m, const std::int32_t* id_m,
                            std::int32_t ia, std::int32_t ib, std::int32_t ic) {
  if (dx != kH && dx != -kH && dy != kH && dy != -kH) {
    if constexpr (kH > 1) emit_rtin_shape<kSlots, kH / 2>(e, dx, dy, need_m, id_m, ia, ib, ic);
    return;
  }
  const int code = (dx > 0 ? 0 : dx < 0 ? 1 : 2) * 3 + (dy > 0 ? 0 : dy < 0 ? 1 : 2);
  switch (code) {
    case 0: emit_rtin<kSlots, kH, kH>(e, need_m, id_m, ia, ib, ic); break;
    case 1: emit_rtin<kSlots, kH, -kH>(e, need_m, id_m, ia, ib, ic); break;
    case 2: emit_rtin<kSlots, kH, 0>(e, need_m, id_m, ia, ib, ic); break;
    case 3: emit_rtin<kSlots, -kH, kH>(e, need_m, id_m, ia, ib, ic); break;
    case 4: emit_rtin<kSlots, -kH, -kH>(e, need_m, id_m, ia, ib, ic); break;
    case 5: emit_rtin<kSlots, -kH, 0>(e, need_m, id_m, ia, ib, ic); break;
    case 6: emit_rtin<kSlots, 0, kH>(e, need_m, id_m, ia, ib, ic); break;
    default: emit_rtin<kSlots, 0, -kH>(e, need_m, id_m, ia, ib, ic); break;
  }
}

}  // namespace

// A general tile's triangle inside the grid with no corner on a moved line:
// its real corners are its virtual ones, so it is a plain RTIN triangle, and
// its whole subtree takes the plain descent (its leaves offer their edges by
// keys, before the band's stretched leaves offer theirs exactly).
template <int kSlots>
void Tritree::emit_general_rtin(Band& b, int ax, int ay, int bx, int by, int cx, int cy) {
  const int w = gray_.width;
  const auto need_stride = static_cast<std::size_t>(layout_.vw) + 1;
  PlainEmit e{need_stride, static_cast<std::size_t>(w), b.leaves + b.count, 0, 0, pred_keys_, vertices_, true};
  const auto id = [&](int x, int y) { return b.ids + static_cast<std::size_t>(y - b.ids_y0) * w + x; };
  const int mx = (ax + bx) / 2, my = (ay + by) / 2;
  emit_rtin_shape<kSlots, 32>(e, cx - mx, cy - my, need_ + static_cast<std::size_t>(my) * need_stride + mx,
                              id(mx, my), *id(ax, ay), *id(bx, by), *id(cx, cy));  // S <= 64
  b.count = static_cast<std::size_t>(e.out - b.leaves);
  b.criterion += e.criterion;
  b.forced += e.forced;
}

// A general tile's triangle (a, b, c) with hypotenuse a-b (virtual corners):
// dropped when outside, split when crossing, or when it can (virtual area2
// >= 4) and need(midpoint); the children are (c, a, m) and (b, c, m). Plain
// tiles take emit_plain instead.
void Tritree::emit(Band& b, int ax, int ay, int bx, int by, int cx, int cy) {
  const int xs[3] = {ax, bx, cx}, ys[3] = {ay, by, cy};
  const Where w = where(xs, ys);
  if (w == Where::kOutside) return;
  if (w == Where::kCrossing) {
    const int mx = (ax + bx) / 2, my = (ay + by) / 2;
    emit(b, cx, cy, ax, ay, mx, my);
    emit(b, bx, by, cx, cy, mx, my);
    return;
  }
  const bool on_x = layout_.stretch_x && (ax == layout_.vw || bx == layout_.vw || cx == layout_.vw);
  const bool on_y = layout_.stretch_y && (ay == layout_.vh || by == layout_.vh || cy == layout_.vh);
  if (!on_x && !on_y) {
    switch (pred_slots_) {
      case 0: emit_general_rtin<0>(b, ax, ay, bx, by, cx, cy); break;
      case 2: emit_general_rtin<2>(b, ax, ay, bx, by, cx, cy); break;
      default: emit_general_rtin<6>(b, ax, ay, bx, by, cx, cy); break;
    }
    return;
  }
  const int dx = bx - ax, dy = by - ay;
  if (dx * dx + dy * dy >= 8) {
    const int mx = (ax + bx) / 2, my = (ay + by) / 2;
    const std::uint8_t c = cell(mx, my);
    if (c & kNeed) {
      const bool apex_after = cy > my || (cy == my && cx > mx);
      (c & (apex_after ? 2 : 4) ? b.criterion : b.forced) += 1;
      emit(b, cx, cy, ax, ay, mx, my);
      emit(b, bx, by, cx, cy, mx, my);
      return;
    }
  }
  emit_leaf(b, ax, ay, bx, by, cx, cy);
}

// A general tile's leaf with a corner on a moved line, i.e. a stretched one
// (no triangle has all three corners on one line): its real corners' vertex
// ids, rotated to start at the smallest (orientation kept), in the mesh and
// in the row of tiles' stretched leaves, which offer their edges once the
// row's tiles are done (offer_stretched()).
void Tritree::emit_leaf(Band& b, int ax, int ay, int bx, int by, int cx, int cy) {
  const int w = gray_.width;
  const auto id = [&](int x, int y) {
    return b.ids[static_cast<std::size_t>(layout_.real_y(y) - b.ids_y0) * w + layout_.real_x(x)];
  };
  const Triangle t = rotated(id(ax, ay), id(bx, by), id(cx, cy));
  b.leaves[b.count++] = t;
  b.stretched[b.stretched_count++] = t;
}

// A row of tiles' stretched leaves offer their edges after all its other
// leaves offered theirs by keys to the same slots (offer_exact() must come
// last). As there (offer_leaf_edge), an edge goes down in one of its two
// leaves: only that one offers it, or the one leaf of an edge on the left
// border x = 0, where it goes up (on the right border x = W - 1 it goes down).
void Tritree::offer_stretched(const Band& b) const {
  const Vertex* v = vertices_;
  const auto offer = [&](auto slots) {
    const auto edge = [&](std::int32_t from, std::int32_t to) {
      if (v[from].y < v[to].y || (v[from].y > v[to].y && v[from].x == 0 && v[to].x == 0))
        predecessor_keys::offer_exact<decltype(slots)::value>(pred_keys_, v, from, to);
    };
    for (std::int64_t i = 0; i < b.stretched_count; ++i) {
      const Triangle& t = b.stretched[i];
      edge(t[0], t[1]);
      edge(t[1], t[2]);
      edge(t[2], t[0]);
    }
  };
  if (pred_slots_ == 2) offer(std::integral_constant<int, 2>{});
  if (pred_slots_ == 6) offer(std::integral_constant<int, 6>{});
}

// The stretched leaves (TritreeGrid::stretched), in the mesh's order: each
// row of tiles' region of them moved down to follow the one before (regions
// are in row order, so each moves down or stays).
void Tritree::collect_stretched() {
  stretched_count_ = 0;
  for (int ty = 0; ty < layout_.tiles_y; ++ty) {
    const Band& b = bands_[ty];
    std::copy(b.stretched, b.stretched + b.stretched_count, stretched_ + stretched_count_);
    stretched_count_ += static_cast<std::size_t>(b.stretched_count);
  }
}

template void Tritree::emit_general_rtin<0>(Band&, int, int, int, int, int, int);
template void Tritree::emit_general_rtin<2>(Band&, int, int, int, int, int, int);
template void Tritree::emit_general_rtin<6>(Band&, int, int, int, int, int, int);

}  // namespace tristereo
