// EXPERIMENT (issue 40): see support_prior.hpp. Serial, allocates per frame:
// a prototype to measure the idea, not the production form.
#include "src/select/support_prior.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "src/dp/subpixel.hpp"
#include "src/select/confidence.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {

namespace {
int find_root(std::vector<int>& parent, int a) {
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

// Least squares d = a x + b y + c over the samples with w != 0 (double: a prototype).
bool fit_plane(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& ds,
               const std::vector<char>& use, double* p) {
  double m[3][4] = {};
  int cnt = 0;
  for (std::size_t j = 0; j < xs.size(); ++j) {
    if (!use[j]) continue;
    const double r[3] = {xs[j], ys[j], 1.0};
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) m[a][b] += r[a] * r[b];
      m[a][3] += r[a] * ds[j];
    }
    ++cnt;
  }
  if (cnt < 3) return false;
  for (int c = 0; c < 3; ++c) {
    int piv = c;
    for (int r = c + 1; r < 3; ++r)
      if (std::abs(m[r][c]) > std::abs(m[piv][c])) piv = r;
    if (std::abs(m[piv][c]) < 1e-9) return false;
    for (int k = 0; k < 4; ++k) std::swap(m[c][k], m[piv][k]);
    for (int r = 0; r < 3; ++r) {
      if (r == c) continue;
      const double f = m[r][c] / m[c][c];
      for (int k = 0; k < 4; ++k) m[r][k] -= f * m[c][k];
    }
  }
  for (int c = 0; c < 3; ++c) p[c] = m[c][3] / m[c][c];
  return true;
}

int env_int(const char* name, int fallback) {
  const char* s = std::getenv(name);
  return s != nullptr && *s != '\0' ? std::atoi(s) : fallback;
}
}  // namespace

SupportPriorKnobs SupportPriorKnobs::from_env() {
  SupportPriorKnobs k;
  k.lambda = env_int("TRISTEREO_PP_LAMBDA", k.lambda);
  k.trunc = env_int("TRISTEREO_PP_T", k.trunc);
  k.min_conf = env_int("TRISTEREO_PP_CONF", k.min_conf);
  k.mode = env_int("TRISTEREO_PP_MODE", k.mode);
  k.smooth = env_int("TRISTEREO_PP_SMOOTH", k.smooth);
  k.which = env_int("TRISTEREO_PP_WHICH", k.which);
  k.uniq = env_int("TRISTEREO_PP_U", k.uniq);
  k.itau = env_int("TRISTEREO_PP_ITAU", k.itau);
  k.fill = env_int("TRISTEREO_PP_FILL", k.fill);
  k.seg_tau = env_int("TRISTEREO_PP_SEG", k.seg_tau);
  k.seg_min = env_int("TRISTEREO_PP_SEGMIN", k.seg_min);
  k.seg_res = env_int("TRISTEREO_PP_SEGRES", k.seg_res);
  return k;
}

SupportPriorStats apply_support_prior(const SupportPriorKnobs& kn, const SampleLayout& samples,
                                      const PathMatcher& pm, const StereoParams& params,
                                      ImageView<const std::uint8_t> left, std::int16_t* disp,
                                      std::uint8_t* conf) {
  SupportPriorStats st;
  if (kn.lambda <= 0 || samples.dense()) return st;
  const int n = samples.count();
  const Mesh& mesh = *samples.mesh;
  // Mesh adjacency (CSR, deduplicated).
  std::vector<int> deg(static_cast<std::size_t>(n) + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) deg[static_cast<std::size_t>(t[e])] += 2;
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i) start[i + 1] = start[i] + deg[i];
  std::vector<int> adj(static_cast<std::size_t>(start[n]));
  std::vector<int> fillp(start.begin(), start.end() - 1);
  for (const Triangle& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const int a = t[e];
      adj[fillp[a]++] = t[(e + 1) % 3];
      adj[fillp[a]++] = t[(e + 2) % 3];
    }
  std::vector<int> len(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    int* b = adj.data() + start[i];
    int* e = b + (fillp[i] - start[i]);
    std::sort(b, e);
    len[i] = static_cast<int>(std::unique(b, e) - b);
  }
  // Support and the prior.
  std::vector<char> support(static_cast<std::size_t>(n));
  std::vector<int> prior(static_cast<std::size_t>(n), INT_MIN), next;
  std::vector<int> pending;
  for (int i = 0; i < n; ++i) {
    support[i] = disp[i] != kInvalidDispQ4 && conf[i] >= kn.min_conf;
    if (support[i]) {
      prior[i] = disp[i];
      ++st.support;
    } else {
      pending.push_back(i);
    }
  }
  std::vector<int> vals;
  std::vector<std::pair<int, int>> writes;
  const int dmin0 = params.d_min, ndisp0 = params.num_disp;
  std::vector<int> inten(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) inten[i] = left.row(samples.y_of(i))[samples.x_of(i)];
  for (int phase = kn.itau > 0 ? 0 : 1; phase < 2; ++phase)
  while (!pending.empty()) {
    writes.clear();
    std::vector<int> keep;
    for (int i : pending) {
      vals.clear();
      for (int j = start[i]; j < start[i] + len[i]; ++j)
        if (prior[adj[j]] != INT_MIN && (phase == 1 || std::abs(inten[adj[j]] - inten[i]) <= kn.itau))
          vals.push_back(prior[adj[j]]);
      if (vals.empty()) {
        keep.push_back(i);
        continue;
      }
      int v;
      if (kn.mode == 0) {
        v = *std::min_element(vals.begin(), vals.end());
      } else if (kn.mode == 2) {
        std::sort(vals.begin(), vals.end());
        v = vals[(vals.size() - 1) / 2];
      } else {
        long long s = 0;
        for (int x : vals) s += x;
        const long long c = static_cast<long long>(vals.size());
        v = static_cast<int>(floor_div(2 * s + c, 2 * c));
      }
      writes.emplace_back(i, v);
    }
    if (writes.empty()) break;
    for (const auto& w : writes) prior[w.first] = w.second;
    pending.swap(keep);
  }
  for (int it = 0; it < kn.smooth; ++it) {
    next = prior;
    for (int i = 0; i < n; ++i) {
      if (support[i] || prior[i] == INT_MIN) continue;
      long long s = 0, c = 0;
      for (int j = start[i]; j < start[i] + len[i]; ++j)
        if (prior[adj[j]] != INT_MIN) {
          s += prior[adj[j]];
          ++c;
        }
      if (c > 0) next[i] = static_cast<int>(floor_div(2 * s + c, 2 * c));
    }
    prior.swap(next);
  }
  if (kn.seg_tau > 0) {
    // Segments of similar intensity on the mesh; a robust plane from each
    // segment's support replaces the propagated prior of its other samples.
    std::vector<int> parent(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) parent[i] = i;
    for (int i = 0; i < n; ++i)
      for (int j = start[i]; j < start[i] + len[i]; ++j) {
        const int q = adj[j];
        if (q > i && std::abs(inten[q] - inten[i]) <= kn.seg_tau) {
          const int a = find_root(parent, i), b = find_root(parent, q);
          if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
      }
    std::vector<int> order(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) order[i] = i;
    std::vector<int> root(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) root[i] = find_root(parent, i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return root[a] < root[b]; });
    std::vector<double> xs, ys, ds;
    std::vector<char> use;
    for (std::size_t g0 = 0; g0 < order.size();) {
      std::size_t g1 = g0;
      while (g1 < order.size() && root[order[g1]] == root[order[g0]]) ++g1;
      xs.clear(); ys.clear(); ds.clear();
      for (std::size_t j = g0; j < g1; ++j) {
        const int i = order[j];
        if (!support[i]) continue;
        xs.push_back(samples.x_of(i));
        ys.push_back(samples.y_of(i));
        ds.push_back(disp[i]);
      }
      const bool has_other = (g1 - g0) > xs.size();
      if (has_other && static_cast<int>(xs.size()) >= kn.seg_min) {
        use.assign(xs.size(), 1);
        double p[3];
        bool ok = fit_plane(xs, ys, ds, use, p);
        for (int it = 0; ok && it < 3; ++it) {
          for (std::size_t j = 0; j < xs.size(); ++j)
            use[j] = std::abs(p[0] * xs[j] + p[1] * ys[j] + p[2] - ds[j]) <= 2.0 * kn.seg_res;
          ok = fit_plane(xs, ys, ds, use, p);
        }
        if (ok) {
          double ss = 0;
          int in = 0;
          for (std::size_t j = 0; j < xs.size(); ++j) {
            const double r = p[0] * xs[j] + p[1] * ys[j] + p[2] - ds[j];
            if (std::abs(r) <= kn.seg_res) ++in;
            ss += std::min(r * r, 4.0 * kn.seg_res * kn.seg_res);
          }
          ok = in * 2 >= static_cast<int>(xs.size()) && ss <= static_cast<double>(kn.seg_res) * kn.seg_res * xs.size();
        }
        if (ok) {
          ++st.changed;
          for (std::size_t j = g0; j < g1; ++j) {
            const int i = order[j];
            if (support[i]) continue;
            const double v = p[0] * samples.x_of(i) + p[1] * samples.y_of(i) + p[2];
            prior[i] = static_cast<int>(std::lround(std::clamp(v, 16.0 * dmin0, 16.0 * (dmin0 + ndisp0 - 1))));
          }
        }
      }
      g0 = g1;
    }
    st.changed = 0;
  }
  if (kn.fill == 2) {  // diagnostic: the prior itself at every non-support sample
    for (int i = 0; i < n; ++i)
      if (!support[i]) {
        disp[i] = prior[i] == INT_MIN ? kInvalidDispQ4 : static_cast<std::int16_t>(prior[i]);
        conf[i] = 100;
      }
    return st;
  }
  // Pass 2.
  const int d = params.num_disp, dmin = params.d_min;
  const int uniq0 = params.validity.uniqueness_pct;
  std::vector<std::uint16_t> s(static_cast<std::size_t>(d));
  std::vector<std::uint32_t> s2(static_cast<std::size_t>(d));
  for (int i = 0; i < n; ++i) {
    if (support[i] || prior[i] == INT_MIN) continue;
    pm.summed_costs(i, s.data());
    int cls;
    if (disp[i] != kInvalidDispQ4) {
      cls = 1;
    } else {
      int k = 0;
      for (int q = 1; q < d; ++q)
        if (s[q] < s[k]) k = q;
      std::uint32_t other = 0xFFFF;
      for (int q = 0; q < d; ++q)
        if (std::abs(q - k) > 1) other = std::min<std::uint32_t>(other, s[q]);
      const bool uniq_fail = uniq0 > 0 && (k > 1 || k + 2 < d) &&
                             other * 100u <= std::uint32_t{s[k]} * static_cast<std::uint32_t>(100 + uniq0);
      cls = uniq_fail ? 2 : 4;
    }
    if ((kn.which & cls) == 0) continue;
    ++st.redecided;
    const int kp = std::clamp(static_cast<int>(floor_div(prior[i] + 8, 16)) - dmin, 0, d - 1);
    int k = 0;
    for (int q = 0; q < d; ++q) {
      s2[q] = s[q] + static_cast<std::uint32_t>(kn.lambda) * static_cast<std::uint32_t>(std::min(std::abs(q - kp), kn.trunc));
      if (s2[q] < s2[k]) k = q;
    }
    std::uint32_t other = 0xFFFFFFFFu;
    for (int q = 0; q < d; ++q)
      if (std::abs(q - k) > 1) other = std::min(other, s2[q]);
    if (kn.uniq > 0 && (k > 1 || k + 2 < d) &&
        static_cast<std::uint64_t>(other) * 100u <= static_cast<std::uint64_t>(s2[k]) * (100u + kn.uniq)) {
      if (disp[i] != kInvalidDispQ4) ++st.rejected;
      disp[i] = kInvalidDispQ4;
      continue;
    }
    int off = 0;
    if (params.dp.subpixel && k > 0 && k < d - 1)
      off = subpixel_offset_q4(params.dp.subpixel_fit, static_cast<int>(s2[k - 1]), static_cast<int>(s2[k]),
                               static_cast<int>(s2[k + 1]));
    const auto v = static_cast<std::int16_t>(kDispOne * (dmin + k) + off);
    if (v != disp[i]) ++st.changed;
    disp[i] = v;
    conf[i] = std::max<std::uint8_t>(conf[i], kMinMeasuredConfidence);
  }
  if (kn.fill == 1)
    for (int i = 0; i < n; ++i)
      if (disp[i] == kInvalidDispQ4 && prior[i] != INT_MIN) {
        disp[i] = static_cast<std::int16_t>(prior[i]);
        conf[i] = 100;
      }
  return st;
}

}  // namespace tristereo
