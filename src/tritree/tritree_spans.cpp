// The general tiles' span records (Tritree::SpanCache in tritree.hpp): the
// owned-pixel rows of their stretched and border triangles, found by the
// fill rule (for_each_owned_span, two divisions per edge) once per kind of
// tile instead of once per tile.
#include <cstdint>

#include "src/tritree/fill_rule.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

// Tile (tx, ty) (in tiles) of a general kind: the last column's but the last
// row's (0, 1 by its diagonal), the last row's but the last column's (2, 3);
// the corner tile has no kind.
void Tritree::begin_span_tile(const TileScratch& sc, int tx, int ty) const {
  SpanCache& c = *sc.spans;
  const bool last_x = tx + 1 == layout_.tiles_x, last_y = ty + 1 == layout_.tiles_y;
  c.current = nullptr;
  if (last_x == last_y) return;
  const int diagonal = RtinLayout::backslash(tx * tile_, ty * tile_, tile_) ? 0 : 1;
  SpanKind& k = c.kinds[static_cast<std::size_t>((last_x ? 0 : 2) + diagonal)];
  if (k.unusable) return;
  c.current = &k;
  c.cursor = 0;
  c.recording = !k.recorded;
  if (c.recording) k.n_records = k.n_rows = 0;
}

void Tritree::end_span_tile(const TileScratch& sc) {
  SpanCache& c = *sc.spans;
  if (c.current != nullptr && c.recording) c.current->recorded = true;
  c.current = nullptr;
}

namespace {

// A recorded triangle's sums: the geometric ones as recorded, the image's
// from its rows.
template <class Record, class Row>
PixelMoments replay(const Record& r, const Row* rows, ImageView<const std::uint8_t> gray, int ox, int oy) {
  PixelMoments m;
  m.n = r.n, m.sx = r.sx, m.sy = r.sy, m.sxx = r.sxx, m.sxy = r.sxy, m.syy = r.syy;
  for (const Row* row = rows + r.first; row != rows + r.first + r.count; ++row) {
    const std::uint8_t* px = gray.row(oy + row->dy) + ox;
    std::int32_t si = 0, sxi = 0, sii = 0;
    for (int x = row->x0; x < row->x1; ++x) {
      const std::int32_t i = px[x];
      si += i, sxi += x * i, sii += i * i;
    }
    m.si += si, m.sxi += sxi, m.syi += row->dy * si, m.sii += sii;
  }
  return m;
}

}  // namespace

// moments_by_spans() of a general tile's triangle (real corners rx, ry; sums
// relative to the tile origin (ox, oy)), its rows from the tile kind's record.
PixelMoments Tritree::tile_moments_by_spans(const int* rx, const int* ry, int ox, int oy,
                                            const TileScratch& sc) const {
  SpanCache& c = *sc.spans;
  if (c.current == nullptr) return moments_by_spans(rx, ry, ox, oy);
  SpanKind& k = *c.current;
  const auto u16 = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint16_t>(v)); };
  const std::uint64_t key_xy = u16(rx[0] - ox) | u16(rx[1] - ox) << 16 | u16(rx[2] - ox) << 32 | u16(ry[0] - oy) << 48;
  const auto key_y = static_cast<std::uint32_t>(u16(ry[1] - oy) | u16(ry[2] - oy) << 16);
  if (!c.recording) {
    if (c.cursor >= k.n_records || k.records[c.cursor].key_xy != key_xy || k.records[c.cursor].key_y != key_y) {
      c.current = nullptr;  // out of step with the record: the rest of this tile afresh
      return moments_by_spans(rx, ry, ox, oy);
    }
    return replay(k.records[c.cursor++], k.rows, gray_, ox, oy);
  }
  // Recording: the rows by the fill rule, and their geometric sums (beyond
  // the bound configure() sized, never reached by the model's tiles, the
  // kind is left uncached).
  const auto give_up = [&] {
    k.unusable = true;
    c.current = nullptr;
    return moments_by_spans(rx, ry, ox, oy);
  };
  if (k.n_records == span_records_) return give_up();
  SpanRecord& r = k.records[k.n_records];
  r.key_xy = key_xy;
  r.key_y = key_y;
  r.first = static_cast<std::uint16_t>(k.n_rows);
  bool fits = true;
  for_each_owned_span(Vertex{rx[0], ry[0]}, Vertex{rx[1], ry[1]}, Vertex{rx[2], ry[2]}, gray_.width, gray_.height,
                      [&](int y, int x0, int x1) {
                        if (x1 <= x0) return;
                        if (k.n_rows == span_rows_) {
                          fits = false;
                          return;
                        }
                        k.rows[k.n_rows++] = SpanRow{static_cast<std::int16_t>(y - oy),
                                                     static_cast<std::int16_t>(x0 - ox),
                                                     static_cast<std::int16_t>(x1 - ox)};
                      });
  if (!fits) return give_up();
  r.count = static_cast<std::uint16_t>(k.n_rows - r.first);
  r.n = r.sx = r.sy = r.sxx = r.sxy = r.syy = 0;
  for (std::uint32_t j = r.first; j < k.n_rows; ++j) {
    const SpanRow& row = k.rows[j];
    for (std::int32_t x = row.x0; x < row.x1; ++x)
      r.n += 1, r.sx += x, r.sy += row.dy, r.sxx += x * x, r.sxy += x * row.dy, r.syy += row.dy * row.dy;
  }
  ++k.n_records;
  return replay(r, k.rows, gray_, ox, oy);
}

}  // namespace tristereo
