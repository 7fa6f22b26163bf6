// Reference: matching cost and aggregation (docs/model.md section 2).
#include <algorithm>
#include <cstdlib>
#include <string>

#include "src/model/exp_table.hpp"
#include "src/reference/ref_match.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace reference {

namespace {

void check_pair(const ImageU8& left, const ImageU8& right, int y) {
  if (left.channels != 1 || right.channels != 1)
    throw Error(ErrorCode::kUnsupportedFormat, "reference matcher takes gray (1-channel) images");
  if (left.width != right.width || left.height != right.height)
    throw Error(ErrorCode::kSizeMismatch, "left and right images differ in size");
  if (y < 0 || y >= left.height)
    throw Error(ErrorCode::kInvalidArgument,
                "row y = " + std::to_string(y) + " is outside 0.." + std::to_string(left.height - 1));
}

}  // namespace

std::uint64_t census_descriptor(const ImageU8& img, int x, int y, const CostParams& cost) {
  const int rx = cost.census_w / 2, ry = cost.census_h / 2;
  const int centre = img.at(x, y);
  std::uint64_t bits = 0;
  int b = 0;
  for (int dy = -ry; dy <= ry; ++dy)
    for (int dx = -rx; dx <= rx; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const int v = img.at(std::clamp(x + dx, 0, img.width - 1), std::clamp(y + dy, 0, img.height - 1));
      if (v < centre) bits |= std::uint64_t{1} << b;
      ++b;
    }
  return bits;
}

namespace {
int popcount64(std::uint64_t v) {
  int c = 0;
  for (int b = 0; b < 64; ++b) c += static_cast<int>((v >> b) & 1u);
  return c;
}

// The census descriptors of rows y0..y1 of img (all columns), row-major.
std::vector<std::uint64_t> census_rows(const ImageU8& img, int y0, int y1, const CostParams& cp) {
  std::vector<std::uint64_t> d;
  for (int y = y0; y <= y1; ++y)
    for (int x = 0; x < img.width; ++x) d.push_back(census_descriptor(img, x, y, cp));
  return d;
}
}  // namespace

std::vector<std::vector<int>> aggregated_costs(const ImageU8& left, const ImageU8& right, int y,
                                               const std::vector<int>& xs,
                                               const StereoParams& params) {
  check_pair(left, right, y);
  const int width = left.width, height = left.height;
  const CostParams& cp = params.cost;
  const int rx = cp.window_w / 2, ry = cp.window_h / 2;
  // The weight tables are part of the model's definition (integer-built).
  std::vector<std::uint8_t> ws(256), wp(static_cast<std::size_t>(rx * rx + ry * ry + 1));
  exp_decay_table_u8(cp.asw_gamma_color, 256, ws.data());
  exp_decay_table_u8(cp.asw_gamma_proximity, static_cast<int>(wp.size()), wp.data());

  // Census descriptors of the window's rows, and the mean Hamming distance over
  // the clipped box window in Q4 by the model's Q32 rule.
  const int wy0 = std::max(0, y - ry), wy1 = std::min(height - 1, y + ry);
  std::vector<std::uint64_t> cl, cr;
  if (cp.kind != CostKind::kAd) {
    cl = census_rows(left, wy0, wy1, cp);
    cr = census_rows(right, wy0, wy1, cp);
  }
  auto census_cost_q4 = [&](int x, int d) {
    std::uint64_t s = 0, n = 0;
    for (int py = wy0; py <= wy1; ++py)
      for (int px = std::max(0, x - rx); px <= std::min(width - 1, x + rx); ++px) {
        const std::size_t row = static_cast<std::size_t>(py - wy0) * static_cast<std::size_t>(width);
        const std::uint64_t l = cl[row + static_cast<std::size_t>(px)];
        const std::uint64_t r = cr[row + static_cast<std::size_t>(std::clamp(px - d, 0, width - 1))];
        s += static_cast<std::uint64_t>(popcount64(l ^ r));
        ++n;
      }
    const std::uint64_t inv = (std::uint64_t{1} << 32) / n;
    return static_cast<int>((s * inv * 16 + (std::uint64_t{1} << 31)) >> 32);
  };

  std::vector<std::vector<int>> result;
  for (int x : xs) {
    if (x < 0 || x >= width)
      throw Error(ErrorCode::kInvalidArgument, "sample x = " + std::to_string(x) + " outside the row");
    std::vector<int> ca(static_cast<std::size_t>(params.num_disp));
    for (int k = 0; k < params.num_disp; ++k) {
      const int d = params.d_min + k;
      std::uint64_t s = 0, sum_w = 0;
      for (int py = std::max(0, y - ry); py <= std::min(height - 1, y + ry); ++py) {
        for (int px = std::max(0, x - rx); px <= std::min(width - 1, x + rx); ++px) {
          const int l = left.at(px, py);
          const int r = right.at(std::clamp(px - d, 0, width - 1), py);
          const int cost = std::min(std::abs(l - r), cp.truncation);
          std::uint64_t w = 1;
          if (cp.weights == Weights::kAdaptive) {
            const int dx = px - x, dy = py - y;
            w = (std::uint64_t{ws[static_cast<std::size_t>(std::abs(l - left.at(x, y)))]} *
                 wp[static_cast<std::size_t>(dx * dx + dy * dy)]) >> 8;
          }
          s += w * static_cast<std::uint64_t>(cost);
          sum_w += w;
        }
      }
      // The model defines the mean by this Q32 reciprocal rule (not by a real
      // division), so it is transcribed in integers: inv = floor(2^32 / W),
      // Ca = (S * inv * 16 + 2^31) >> 32.
      const std::uint64_t inv = (std::uint64_t{1} << 32) / sum_w;
      const int ad = static_cast<int>((s * inv * 16 + (std::uint64_t{1} << 31)) >> 32);
      int cost = ad;
      if (cp.kind == CostKind::kCensus) {
        cost = census_cost_q4(x, d);
      } else if (cp.kind == CostKind::kAdCensus) {
        cost = std::min(kMaxCostQ4, census_cost_q4(x, d) +
                                        ((cp.ad_weight_q4 * ad + 8) >> 4));
      }
      ca[static_cast<std::size_t>(k)] = cost;
    }
    result.push_back(std::move(ca));
  }
  return result;
}

}  // namespace reference
}  // namespace tristereo
