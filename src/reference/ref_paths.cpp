// Reference: path aggregation on the samples, winner, uniqueness, fill
// (docs/model.md sections 3b and 6), transcribed with plain loops and int64.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <set>

#include "src/reference/ref_match.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {
namespace reference {

namespace {
struct Dir {
  int dx, dy;
};
// Same numbering as the integer path: even = forward (raster order).
constexpr Dir kDirs[8] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {-1, 1}, {1, -1}};
}  // namespace

Samples make_samples(const Mesh* mesh, int width, int height) {
  Samples s;
  s.mesh = mesh;
  s.width = width;
  s.height = height;
  if (mesh == nullptr) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) s.points.push_back({x, y});
    s.neighbours.resize(s.points.size());
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if ((dx || dy) && qx >= 0 && qx < width && qy >= 0 && qy < height)
              s.neighbours[static_cast<std::size_t>(y * width + x)].push_back(qy * width + qx);
          }
    return s;
  }
  s.points = mesh->vertices;
  std::vector<std::set<int>> nb(s.points.size());
  for (const Triangle& t : mesh->triangles)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (a != b) nb[static_cast<std::size_t>(t[static_cast<std::size_t>(a)])].insert(t[static_cast<std::size_t>(b)]);
  for (const auto& n : nb) s.neighbours.emplace_back(n.begin(), n.end());
  return s;
}

std::vector<std::int16_t> match_paths(const ImageU8& left, const ImageU8& right,
                                      const Samples& samples, const StereoParams& params,
                                      int* uniqueness_rejected, int* lr_rejected,
                                      std::vector<std::uint8_t>* confidence,
                                      std::vector<std::vector<std::int64_t>>* summed) {
  const int n = static_cast<int>(samples.points.size());
  const int nd = params.num_disp;
  const PathParams& pp = params.paths;
  // Costs at the samples, row by row.
  std::vector<std::vector<std::int64_t>> cost(static_cast<std::size_t>(n));
  for (int y = 0, i = 0; y < samples.height; ++y) {
    std::vector<int> xs;
    const int first = i;
    while (i < n && samples.points[static_cast<std::size_t>(i)].y == y) xs.push_back(samples.points[static_cast<std::size_t>(i++)].x);
    if (xs.empty()) continue;
    const auto ca = aggregated_costs(left, right, y, xs, params);
    for (std::size_t j = 0; j < xs.size(); ++j)
      cost[static_cast<std::size_t>(first) + j].assign(ca[j].begin(), ca[j].end());
  }
  auto point = [&](int i) { return samples.points[static_cast<std::size_t>(i)]; };
  // Predecessor of i along u: horizontal = the row's neighbouring sample;
  // otherwise the neighbour on u's side (strictly) with (p - q).u > 0 and the
  // largest cos^2 = dot^2 / len^2, ties to the smaller index.
  auto predecessor = [&](int i, Dir u) {
    const Vertex p = point(i);
    if (u.dy == 0) {
      const int q = i - u.dx;
      return (q >= 0 && q < n && point(q).y == p.y) ? q : -1;
    }
    int best = -1;
    std::int64_t bdot = 0, blen = 1;
    for (int q : samples.neighbours[static_cast<std::size_t>(i)]) {
      const std::int64_t dx = p.x - point(q).x, dy = p.y - point(q).y;
      if (dy * u.dy <= 0) continue;
      const std::int64_t dot = dx * u.dx + dy * u.dy;
      if (dot <= 0) continue;
      const std::int64_t len = dx * dx + dy * dy;
      const std::int64_t lhs = dot * dot * blen, rhs = bdot * bdot * len;
      if (best < 0 || lhs > rhs || (lhs == rhs && q < best)) {
        best = q;
        bdot = dot;
        blen = len;
      }
    }
    return best;
  };
  std::vector<std::vector<std::int64_t>> total(static_cast<std::size_t>(n), std::vector<std::int64_t>(static_cast<std::size_t>(nd), 0));
  for (int r = 0; r < pp.directions; ++r) {
    const Dir u = kDirs[r];
    const bool forward = (r % 2) == 0;
    std::vector<std::vector<std::int64_t>> path(static_cast<std::size_t>(n));
    for (int step = 0; step < n; ++step) {
      const int i = forward ? step : n - 1 - step;
      const int q = predecessor(i, u);
      std::vector<std::int64_t>& out = path[static_cast<std::size_t>(i)];
      out = cost[static_cast<std::size_t>(i)];
      if (q >= 0) {
        const std::vector<std::int64_t>& prev = path[static_cast<std::size_t>(q)];
        const int gap = std::max(std::abs(point(i).x - point(q).x), std::abs(point(i).y - point(q).y));
        DpParams t1, t2;
        t1.lambda_q4 = pp.p1_q4;
        t1.gap = pp.gap;
        t2.lambda_q4 = pp.p2_q4;
        t2.gap = pp.gap;
        const std::int64_t p1 = gap_penalty(t1, gap);
        std::int64_t p2 = std::max(p1, gap_penalty(t2, gap));
        if (pp.p2_edge_scale > 0) {
          const std::int64_t di = std::abs(left.at(point(i).x, point(i).y) - left.at(point(q).x, point(q).y));
          p2 = p1 + (p2 - p1) * pp.p2_edge_scale / (pp.p2_edge_scale + di);
        }
        const std::int64_t m = *std::min_element(prev.begin(), prev.end());
        for (int k = 0; k < nd; ++k) {
          std::int64_t best = std::min(prev[static_cast<std::size_t>(k)], m + p2);
          if (k > 0) best = std::min(best, prev[static_cast<std::size_t>(k - 1)] + p1);
          if (k + 1 < nd) best = std::min(best, prev[static_cast<std::size_t>(k + 1)] + p1);
          out[static_cast<std::size_t>(k)] += best - m;
        }
      }
      for (int k = 0; k < nd; ++k) total[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] += out[static_cast<std::size_t>(k)];
    }
  }
  if (summed != nullptr) *summed = total;
  std::vector<std::int16_t> disp(static_cast<std::size_t>(n));
  std::vector<int> winner(static_cast<std::size_t>(n), -1);  // k, or -1 when uniqueness rejected it
  int rejected = 0;
  for (int i = 0; i < n; ++i) {
    const std::vector<std::int64_t>& s = total[static_cast<std::size_t>(i)];
    const int k = static_cast<int>(std::min_element(s.begin(), s.end()) - s.begin());  // first minimum
    if (confidence != nullptr) {
      if (confidence->size() != static_cast<std::size_t>(n)) confidence->assign(static_cast<std::size_t>(n), 0);
      // Measured confidence: 128 + floor(127 (rival - best) / rival), rival the
      // smallest S two or more disparities from k (65535 when none), 128 when
      // rival = 0. The numerator is an integer below 2^23 and so is rival: a
      // quotient that is not an integer is at least 2^-23 from one, far more
      // than the division's rounding error, so the floor is exact.
      std::int64_t rival = 65535;
      for (int j = 0; j < nd; ++j)
        if (std::abs(j - k) > 1) rival = std::min(rival, s[static_cast<std::size_t>(j)]);
      const double best = static_cast<double>(s[static_cast<std::size_t>(k)]);
      (*confidence)[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
          rival == 0 ? 128 : 128 + static_cast<int>(std::floor(127.0 * (static_cast<double>(rival) - best) /
                                                               static_cast<double>(rival))));
    }
    bool unique = true;
    if (params.validity.uniqueness_pct > 0)
      for (int j = 0; j < nd; ++j)
        if (std::abs(j - k) > 1 &&
            100 * s[static_cast<std::size_t>(j)] <= (100 + params.validity.uniqueness_pct) * s[static_cast<std::size_t>(k)])
          unique = false;
    if (!unique) {
      disp[static_cast<std::size_t>(i)] = kInvalidDispQ4;
      ++rejected;
      continue;
    }
    winner[static_cast<std::size_t>(i)] = k;
    int off = 0;
    if (params.dp.subpixel && k > 0 && k < nd - 1)
      off = subpixel_offset_q4(params.dp, static_cast<int>(s[static_cast<std::size_t>(k - 1)]), static_cast<int>(s[static_cast<std::size_t>(k)]),
                               static_cast<int>(s[static_cast<std::size_t>(k + 1)]));
    disp[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(16 * (params.d_min + k) + off);
  }
  if (uniqueness_rejected) *uniqueness_rejected = rejected;
  // Left-right check from the summed costs: the right view's disparity index
  // at right pixel xr of row y is the k minimising S(q, k) over the row's
  // samples q with q_x - d_min - k = xr (ties: the smallest k).
  int lr_count = 0;
  if (params.validity.lr_max_diff_q4 >= 0 && params.validity.lr_source == LrSource::kSummedCosts) {
    std::vector<int> row_first(static_cast<std::size_t>(n)), row_last(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      row_first[static_cast<std::size_t>(i)] = (i > 0 && point(i - 1).y == point(i).y) ? row_first[static_cast<std::size_t>(i - 1)] : i;
    for (int i = n - 1; i >= 0; --i)
      row_last[static_cast<std::size_t>(i)] = (i + 1 < n && point(i + 1).y == point(i).y) ? row_last[static_cast<std::size_t>(i + 1)] : i;
    for (int i = 0; i < n; ++i) {
      const int k = winner[static_cast<std::size_t>(i)];
      if (k < 0) continue;
      const Vertex p = point(i);
      const int xr = p.x - params.d_min - k;
      bool ok = xr >= 0 && xr < samples.width;
      if (ok) {
        std::int64_t best = 0;
        int kr = -1;
        for (int j = row_first[static_cast<std::size_t>(i)]; j <= row_last[static_cast<std::size_t>(i)]; ++j) {
          const int kj = point(j).x - params.d_min - xr;
          if (kj < 0 || kj >= nd) continue;
          const std::int64_t c = total[static_cast<std::size_t>(j)][static_cast<std::size_t>(kj)];
          if (kr < 0 || c < best || (c == best && kj < kr)) {
            best = c;
            kr = kj;
          }
        }
        ok = 16 * std::abs(k - kr) <= params.validity.lr_max_diff_q4;
      }
      if (!ok) {
        disp[static_cast<std::size_t>(i)] = kInvalidDispQ4;
        ++lr_count;
      }
    }
  }
  if (lr_rejected) *lr_rejected = lr_count;
  return disp;
}

int fill_background(const Samples& samples, std::vector<std::int16_t>& disp,
                    std::vector<std::uint8_t>* confidence) {
  int filled = 0;
  for (int round = 1;; ++round) {
    std::vector<std::int16_t> next = disp;
    int now = 0;
    for (std::size_t i = 0; i < disp.size(); ++i) {
      if (disp[i] != kInvalidDispQ4) continue;
      int best = INT_MAX;
      for (int q : samples.neighbours[i])
        if (disp[static_cast<std::size_t>(q)] != kInvalidDispQ4) best = std::min(best, static_cast<int>(disp[static_cast<std::size_t>(q)]));
      if (best != INT_MAX) {
        next[i] = static_cast<std::int16_t>(best);
        // The nearest measured sample is `round` edges away.
        if (confidence != nullptr) (*confidence)[i] = static_cast<std::uint8_t>(std::max(1, 128 - 8 * round));
        ++now;
      }
    }
    disp = next;
    filled += now;
    if (now == 0) return filled;
  }
}

}  // namespace reference
}  // namespace tristereo
