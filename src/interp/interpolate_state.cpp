#include "src/interp/interpolate_state.hpp"

#include <algorithm>

#include "src/select/confidence.hpp"
#include "src/tritree/fill_rule.hpp"

namespace tristereo {

namespace {

// (v - u) x (p - u): zero exactly when p is on the line through u and v.
// |coordinates| < 2^13, so the products fit int32 with room.
inline int edge_value(const Vertex& u, const Vertex& v, int px, int py) {
  return (v.x - u.x) * (py - u.y) - (v.y - u.y) * (px - u.x);
}

}  // namespace

void confidence_triangle(const Vertex& a, const Vertex& b, const Vertex& c, std::uint8_t conf_a,
                         std::uint8_t conf_b, std::uint8_t conf_c, bool invalid, const ConfidenceMaps& maps) {
  const int w = maps.confidence.width, h = maps.confidence.height;
  if (invalid) {
    for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
      std::uint8_t* conf = maps.confidence.row(y);
      std::uint8_t* state = maps.state.row(y);
      for (int x = x0; x < x1; ++x) conf[x] = state[x] = 0;
    });
    return;
  }
  for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
    std::uint8_t* conf = maps.confidence.row(y);
    std::uint8_t* state = maps.state.row(y);
    for (int x = x0; x < x1; ++x) {
      std::uint8_t m = 255;
      if (edge_value(b, c, x, y) != 0) m = std::min(m, conf_a);
      if (edge_value(c, a, x, y) != 0) m = std::min(m, conf_b);
      if (edge_value(a, b, x, y) != 0) m = std::min(m, conf_c);
      conf[x] = m;
      state[x] = state_of_confidence(m);
    }
  });
}

}  // namespace tristereo
