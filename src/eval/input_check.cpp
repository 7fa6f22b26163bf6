// Signals that a score would mislead: a ground-truth scale off by a factor, or
// the disparity map and the ground truth given the wrong way round.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tristereo/eval.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {
// 16 v is exact in float for every finite v (a power-of-two scale).
bool off_q4_grid(float v) { return 16.f * v != std::floor(16.f * v); }
}  // namespace

EvalInputCheck check_eval_inputs(ImageView<const float> disp, ImageView<const float> gt) {
  if (disp.data == nullptr || gt.data == nullptr || disp.channels != 1 || gt.channels != 1) {
    throw Error(ErrorCode::kInvalidArgument, "check_eval_inputs: needs two one-channel maps");
  }
  if (disp.width != gt.width || disp.height != gt.height) {
    throw Error(ErrorCode::kSizeMismatch, "check_eval_inputs: the maps differ in size");
  }
  EvalInputCheck c;
  std::vector<float> ratios;
  for (int y = 0; y < gt.height; ++y) {
    const float* d = disp.row(y);
    const float* g = gt.row(y);
    for (int x = 0; x < gt.width; ++x) {
      ++c.pixels;
      const bool has_d = std::isfinite(d[x]);
      const bool has_g = std::isfinite(g[x]) && g[x] != 0.f;
      c.disp_none += !has_d;
      c.gt_unknown += !has_g;
      c.disp_off_q4_grid += has_d && off_q4_grid(d[x]);
      c.gt_off_q4_grid += has_g && off_q4_grid(g[x]);
      // The ratio is defined for positive values only: a zero or negative
      // disparity says nothing about a scale.
      if (has_d && has_g && d[x] > 0.f && g[x] > 0.f) ratios.push_back(g[x] / d[x]);
    }
  }
  c.both = static_cast<std::int64_t>(ratios.size());
  if (!ratios.empty()) {
    const std::size_t mid = ratios.size() / 2;
    std::nth_element(ratios.begin(), ratios.begin() + static_cast<std::ptrdiff_t>(mid), ratios.end());
    c.median_gt_over_disp = ratios[mid];
  }
  return c;
}

bool scale_looks_wrong(const EvalInputCheck& c) {
  return c.both > 0 && (c.median_gt_over_disp > 1.5 || c.median_gt_over_disp < 1.0 / 1.5);
}

bool files_look_swapped(const EvalInputCheck& c) {
  const std::int64_t disp_known = c.pixels - c.disp_none;
  return c.pixels > 0 && c.disp_none * 1000 >= c.pixels && c.gt_unknown * 10 <= c.disp_none &&
         c.gt_off_q4_grid == 0 && c.disp_off_q4_grid * 10 >= disp_known && disp_known > 0;
}

}  // namespace tristereo
