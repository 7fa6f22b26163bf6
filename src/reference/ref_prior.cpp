// Float reference of the support prior (docs/model.md section 6b): a plain
// transcription. The plane fit is defined by integer rules, so it is written
// with int64 here too; everything else is sets, maps and loops.
#include <algorithm>
#include <array>
#include <climits>
#include <cstdlib>
#include <map>
#include <vector>

#include "src/reference/ref_match.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {
namespace reference {

namespace {

std::int64_t fdiv(std::int64_t a, std::int64_t b) {  // floor(a / b), b > 0
  std::int64_t q = a / b;
  if ((a % b != 0) && (a < 0)) --q;
  return q;
}

struct Plane {
  std::int64_t xb = 0, yb = 0, db = 0, a = 0, b = 0, c = 0;
  std::int64_t at(std::int64_t x, std::int64_t y) const { return db + fdiv(c + a * (x - xb) + b * (y - yb) + 128, 256); }
};

// The least-squares plane of section 6b through the points; false when there is none.
bool fit(const std::vector<std::array<std::int64_t, 3>>& pts, Plane* out) {
  const auto n = static_cast<std::int64_t>(pts.size());
  if (n < 3) return false;
  std::int64_t sx = 0, sy = 0, sd = 0;
  for (const auto& p : pts) {
    sx += p[0];
    sy += p[1];
    sd += p[2];
  }
  Plane pl;
  pl.xb = fdiv(sx, n);
  pl.yb = fdiv(sy, n);
  pl.db = fdiv(sd, n);
  std::int64_t muu = 0, muv = 0, mvv = 0, muw = 0, mvw = 0, su = 0, sv = 0, sw = 0;
  for (const auto& p : pts) {
    const std::int64_t u = p[0] - pl.xb, v = p[1] - pl.yb, w = p[2] - pl.db;
    muu += u * u;
    muv += u * v;
    mvv += v * v;
    muw += u * w;
    mvw += v * w;
    su += u;
    sv += v;
    sw += w;
  }
  std::int64_t biggest = 0;
  for (std::int64_t m : {muu, muv, mvv, muw, mvw}) biggest = std::max(biggest, std::abs(m));
  int s = 0;
  while (biggest >= (std::int64_t{1} << (26 + s))) ++s;
  // M' = floor(M / 2^s) (the integer path shifts).
  const std::int64_t d = std::int64_t{1} << s;
  muu = fdiv(muu, d);
  muv = fdiv(muv, d);
  mvv = fdiv(mvv, d);
  muw = fdiv(muw, d);
  mvw = fdiv(mvw, d);
  const std::int64_t det = muu * mvv - muv * muv;
  if (det <= 0) return false;
  pl.a = fdiv(512 * (muw * mvv - mvw * muv) + det, 2 * det);
  pl.b = fdiv(512 * (mvw * muu - muw * muv) + det, 2 * det);
  if (std::abs(pl.a) > (1 << 20) || std::abs(pl.b) > (1 << 20)) return false;
  pl.c = fdiv(2 * (256 * sw - pl.a * su - pl.b * sv) + n, 2 * n);
  *out = pl;
  return true;
}

}  // namespace

void support_prior(const ImageU8& lg, const Samples& samples, const StereoParams& params,
                   const std::vector<std::vector<std::int64_t>>& summed, std::vector<std::int16_t>& disp,
                   std::vector<std::uint8_t>& conf, SampleValidity* v) {
  const SupportPriorParams& pp = params.prior;
  const int n = static_cast<int>(samples.points.size());
  const int nd = params.num_disp, dmin = params.d_min;
  auto I = [&](int i) { return static_cast<int>(lg.at(samples.points[static_cast<std::size_t>(i)].x, samples.points[static_cast<std::size_t>(i)].y)); };
  auto X = [&](int i) { return static_cast<std::int64_t>(samples.points[static_cast<std::size_t>(i)].x); };
  auto Y = [&](int i) { return static_cast<std::int64_t>(samples.points[static_cast<std::size_t>(i)].y); };
  const auto& nb = samples.neighbours;
  // 1. Support.
  std::vector<bool> support(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    support[static_cast<std::size_t>(i)] = disp[static_cast<std::size_t>(i)] != kInvalidDispQ4 && conf[static_cast<std::size_t>(i)] >= pp.support_conf;
  // 2. The prior: a plane's value (LLONG_MIN = none).
  const std::int64_t kNone = LLONG_MIN;
  std::vector<std::int64_t> pi(static_cast<std::size_t>(n), kNone);
  // Planes on two segment levels.
  std::vector<bool> covered(static_cast<std::size_t>(n), false);
  for (int tau : {pp.seg_fine, pp.seg_coarse}) {
    if (tau == 0) continue;
    // Components by a flood over the edges with |dI| <= tau, labelled by their smallest sample.
    std::vector<int> label(static_cast<std::size_t>(n), -1);
    for (int s0 = 0; s0 < n; ++s0) {
      if (label[static_cast<std::size_t>(s0)] >= 0) continue;
      std::vector<int> stack{s0};
      label[static_cast<std::size_t>(s0)] = s0;
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        for (int q : nb[static_cast<std::size_t>(i)])
          if (label[static_cast<std::size_t>(q)] < 0 && std::abs(I(q) - I(i)) <= tau) {
            label[static_cast<std::size_t>(q)] = s0;
            stack.push_back(q);
          }
      }
    }
    std::map<int, std::vector<int>> segments;
    for (int i = 0; i < n; ++i) segments[label[static_cast<std::size_t>(i)]].push_back(i);
    for (const auto& seg : segments) {
      std::vector<int> f0;
      bool other = false;
      for (int i : seg.second) {
        if (support[static_cast<std::size_t>(i)]) f0.push_back(i);
        else if (!covered[static_cast<std::size_t>(i)]) other = true;
      }
      if (!other || static_cast<int>(f0.size()) < pp.plane_min) continue;
      const std::int64_t t = pp.plane_tol_q4;
      Plane plane;
      bool ok = true;
      for (int k = 0; k < 4 && ok; ++k) {
        std::vector<std::array<std::int64_t, 3>> pts;
        for (int i : f0)
          if (k == 0 || std::abs(plane.at(X(i), Y(i)) - disp[static_cast<std::size_t>(i)]) <= 2 * t)
            pts.push_back({X(i), Y(i), disp[static_cast<std::size_t>(i)]});
        ok = fit(pts, &plane);
      }
      if (!ok) continue;
      std::int64_t inliers = 0, sq = 0;
      for (int i : f0) {
        const std::int64_t e = std::abs(plane.at(X(i), Y(i)) - disp[static_cast<std::size_t>(i)]);
        if (e <= t) ++inliers;
        sq += std::min(e * e, 4 * t * t);
      }
      const auto m = static_cast<std::int64_t>(f0.size());
      if (2 * inliers < m || sq > t * t * m) continue;
      for (int i : seg.second) {
        if (support[static_cast<std::size_t>(i)] || covered[static_cast<std::size_t>(i)]) continue;
        covered[static_cast<std::size_t>(i)] = true;
        pi[static_cast<std::size_t>(i)] = std::clamp<std::int64_t>(plane.at(X(i), Y(i)), 16 * dmin, 16 * (dmin + nd - 1));
      }
    }
  }
  // 3. Pass 2.
  v->prior_redecided = v->prior_rejected = v->prior_recovered = v->prior_lost = 0;
  for (int i = 0; i < n; ++i) {
    if (support[static_cast<std::size_t>(i)] || pi[static_cast<std::size_t>(i)] == kNone) continue;
    ++v->prior_redecided;
    const bool was_valid = disp[static_cast<std::size_t>(i)] != kInvalidDispQ4;
    const std::int64_t kp = std::clamp<std::int64_t>(fdiv(pi[static_cast<std::size_t>(i)] + 8, 16) - dmin, 0, nd - 1);
    std::vector<std::int64_t> s2(static_cast<std::size_t>(nd));
    for (int k = 0; k < nd; ++k)
      s2[static_cast<std::size_t>(k)] = summed[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] +
                                        pp.lambda_q4 * std::min<std::int64_t>(std::abs(k - kp), pp.trunc);
    const int k = static_cast<int>(std::min_element(s2.begin(), s2.end()) - s2.begin());
    std::int64_t rival = -1;
    for (int j = 0; j < nd; ++j)
      if (std::abs(j - k) > 1 && (rival < 0 || s2[static_cast<std::size_t>(j)] < rival)) rival = s2[static_cast<std::size_t>(j)];
    const std::int64_t best = s2[static_cast<std::size_t>(k)];
    if (pp.uniqueness_pct > 0 && rival >= 0 && 100 * rival <= (100 + pp.uniqueness_pct) * best) {
      disp[static_cast<std::size_t>(i)] = kInvalidDispQ4;
      ++v->prior_rejected;
      if (was_valid) ++v->prior_lost;
      continue;
    }
    if (!was_valid) ++v->prior_recovered;
    // The plane's value within half a pixel of the winner, else the fit through S'.
    const std::int64_t whole = 16 * (dmin + k);
    std::int64_t off = 0;
    if (params.dp.subpixel && std::abs(pi[static_cast<std::size_t>(i)] - whole) <= 8)
      off = pi[static_cast<std::size_t>(i)] - whole;
    else if (params.dp.subpixel && k > 0 && k < nd - 1)
      off = subpixel_offset_q4(params.dp, static_cast<int>(s2[static_cast<std::size_t>(k - 1)]), static_cast<int>(best),
                               static_cast<int>(s2[static_cast<std::size_t>(k + 1)]));
    disp[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(whole + off);
    // Confidence from S (the data): at k', against S's smallest value two or
    // more steps away (65535 when none); the lowest measured one when that is
    // not above S(k'); below the support.
    const auto& sum = summed[static_cast<std::size_t>(i)];
    std::int64_t data_rival = 65535;
    for (int j = 0; j < nd; ++j)
      if (std::abs(j - k) > 1) data_rival = std::min(data_rival, sum[static_cast<std::size_t>(j)]);
    const std::int64_t b0 = sum[static_cast<std::size_t>(k)];
    const std::int64_t c = data_rival <= b0 ? 128 : 128 + (127 * (data_rival - b0)) / data_rival;
    conf[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(std::min<std::int64_t>(std::max(128, pp.support_conf - 1), c));
  }
}

}  // namespace reference
}  // namespace tristereo
