// Split criterion of the tritree (docs/model.md section 1, "Split criterion").
#pragma once

#include <cstdint>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// True when triangle (a, b, c) (area2 > 0, inside `gray`) wants to split:
// area2 > 2 * max_area_px2, or else SSE * 256 > mse_q8 * n_px * area2^2 for the
// plane residuals over the pixels it owns (fill_rule.hpp). Exact integers only;
// stops summing as soon as the answer is known. mse_q8 from mse_threshold_q8().
// No allocation, no shared state: safe to call from several threads.
bool tritree_wants_split(ImageView<const std::uint8_t> gray, const Vertex& a, const Vertex& b,
                         const Vertex& c, int max_area_px2, std::uint64_t mse_q8);

}  // namespace tristereo
