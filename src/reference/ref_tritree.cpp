// Float reference tritree: readable, slow, and the specification in code.
//
// Exactness: every double below holds an integer. Coordinates are < 4096 and
// intensities <= 255, so the normal's components are below 2^22, each term of
// a residual below 2^34, a residual (|r| <= 255 area2 < 2^19 when the plane
// test runs, area2 <= 2048) squared below 2^38 and a triangle's SSE below 2^52
// (docs/model.md section 5): all exactly representable (< 2^53), so the sums
// are exact in any order, and the build uses -ffp-contract=off anyway. The
// final comparison SSE * 256 > mse_q8 * n_px * area2^2 can exceed 2^53, so it
// is made on the exact values converted to uint64.
#include "src/reference/ref_tritree.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "src/model/psnr_threshold.hpp"
#include "tristereo/status.hpp"

namespace tristereo::reference {

namespace {

using Key = std::pair<int, int>;  // (y, x): raster order
using EdgeKey = std::pair<Key, Key>;  // (lower endpoint, upper endpoint)

Key key_of(const Vertex& v) { return {v.y, v.x}; }

EdgeKey edge_key(const Vertex& p, const Vertex& q) {
  const Key a = key_of(p), b = key_of(q);
  return a < b ? EdgeKey{a, b} : EdgeKey{b, a};
}

long long twice_area(const Vertex& a, const Vertex& b, const Vertex& c) {
  return static_cast<long long>(b.x - a.x) * (c.y - a.y) -
         static_cast<long long>(b.y - a.y) * (c.x - a.x);
}

// The model's edge order: (len2, key(lower endpoint), key(upper endpoint)).
std::tuple<long long, Key, Key> edge_rank(const Vertex& p, const Vertex& q) {
  const long long dx = q.x - p.x, dy = q.y - p.y;
  const EdgeKey k = edge_key(p, q);
  return {dx * dx + dy * dy, k.first, k.second};
}

struct Tri {
  std::array<Vertex, 3> v;  // positive orientation
  bool leaf = true;
  int round_created = -1;
  bool wants = false;  // evaluated and wants to split: its split counts as a criterion split
};

class Builder {
 public:
  Builder(const ImageU8& gray, const TritreeParams& params)
      : gray_(gray), params_(params), mse_q8_(mse_threshold_q8(params.psnr_deci_db)) {}

  Mesh run() {
    const int w = gray_.width, h = gray_.height;
    add({Vertex{0, 0}, Vertex{w - 1, 0}, Vertex{w - 1, h - 1}}, -1);
    add({Vertex{0, 0}, Vertex{w - 1, h - 1}, Vertex{0, h - 1}}, -1);
    for (int round = 0;; ++round) {
      std::vector<int> candidates;
      for (int i = 0; i < static_cast<int>(tris_.size()); ++i) {
        if (tris_[i].leaf && tris_[i].round_created == round - 1) candidates.push_back(i);
      }
      if (candidates.empty()) break;
      // Triangles that want to split and whose own bisection is valid, in
      // ascending order of their sorted vertex keys.
      std::vector<std::pair<std::array<Key, 3>, int>> to_split;
      for (int i : candidates) {
        if (own_bisection_valid(i) && wants_split(tris_[i].v)) {
          std::array<Key, 3> keys = {key_of(tris_[i].v[0]), key_of(tris_[i].v[1]),
                                     key_of(tris_[i].v[2])};
          std::sort(keys.begin(), keys.end());
          to_split.push_back({keys, i});
          tris_[i].wants = true;
        }
      }
      std::sort(to_split.begin(), to_split.end());
      for (const auto& entry : to_split) process(entry.second, round);
    }
    return output();
  }

 private:
  void add(const std::array<Vertex, 3>& v, int round) {
    const int id = static_cast<int>(tris_.size());
    tris_.push_back(Tri{v, true, round});
    for (int i = 0; i < 3; ++i) leaves_of_edge_[edge_key(v[i], v[(i + 1) % 3])].insert(id);
  }

  void remove(int id) {
    tris_[id].leaf = false;
    const auto& v = tris_[id].v;
    for (int i = 0; i < 3; ++i) leaves_of_edge_[edge_key(v[i], v[(i + 1) % 3])].erase(id);
  }

  // Vertices rotated so that (v[0], v[1]) is the longest edge.
  std::array<Vertex, 3> rotated_to_longest(int id) const {
    const auto& v = tris_[id].v;
    int best = 0;
    for (int i = 1; i < 3; ++i) {
      if (edge_rank(v[best], v[(best + 1) % 3]) < edge_rank(v[i], v[(i + 1) % 3])) best = i;
    }
    return {v[best], v[(best + 1) % 3], v[(best + 2) % 3]};
  }

  // The other leaf on edge (p, q), or -1 on the border.
  int neighbour(int id, const Vertex& p, const Vertex& q) const {
    const auto it = leaves_of_edge_.find(edge_key(p, q));
    if (it == leaves_of_edge_.end()) return -1;
    for (int other : it->second) {
      if (other != id) return other;
    }
    return -1;
  }

  static Vertex midpoint(const Vertex& p, const Vertex& q) {
    return Vertex{(p.x + q.x) >> 1, (p.y + q.y) >> 1};  // floor: the model's snap
  }

  bool own_bisection_valid(int id) const {
    const auto r = rotated_to_longest(id);
    const Vertex m = midpoint(r[0], r[1]);
    return twice_area(r[0], m, r[2]) >= 2 && twice_area(m, r[1], r[2]) >= 2;
  }

  // Fill rule, pixel by pixel: inside every directed edge, ties decided by
  // the sign of the edge function at the pixel nudged by e * (sx, e * sy).
  bool owns(const std::array<Vertex, 3>& v, int px, int py) const {
    const int sx = (px == gray_.width - 1) ? -1 : 1;
    const int sy = (py == gray_.height - 1) ? -1 : 1;
    for (int i = 0; i < 3; ++i) {
      const Vertex& u = v[i];
      const Vertex& w = v[(i + 1) % 3];
      const long long ex = w.x - u.x, ey = w.y - u.y;
      const long long e = ex * (py - u.y) - ey * (px - u.x);
      if (e > 0) continue;
      if (e < 0) return false;
      const bool tie_owned = (-sx * ey > 0) || (ey == 0 && sy * ex > 0);
      if (!tie_owned) return false;
    }
    return true;
  }

  double intensity(const Vertex& p) const { return gray_.at(p.x, p.y); }

  bool wants_split(const std::array<Vertex, 3>& v) const {
    const Eigen::Vector3d a(v[0].x, v[0].y, intensity(v[0]));
    const Eigen::Vector3d b(v[1].x, v[1].y, intensity(v[1]));
    const Eigen::Vector3d c(v[2].x, v[2].y, intensity(v[2]));
    const Eigen::Vector3d normal = (b - a).cross(c - a);  // normal.z() == area2
    const double area2 = normal.z();
    if (area2 > 2.0 * params_.max_area_px2) return true;

    double sse = 0.0;
    long long n_px = 0;
    const int x_lo = std::min({v[0].x, v[1].x, v[2].x}), x_hi = std::max({v[0].x, v[1].x, v[2].x});
    const int y_lo = std::min({v[0].y, v[1].y, v[2].y}), y_hi = std::max({v[0].y, v[1].y, v[2].y});
    for (int y = y_lo; y <= y_hi; ++y) {
      for (int x = x_lo; x <= x_hi; ++x) {
        if (!owns(v, x, y)) continue;
        const Eigen::Vector3d p(x, y, gray_.at(x, y));
        const double r = normal.dot(p - a);  // area2 x the plane's intensity error
        sse += r * r;
        ++n_px;
      }
    }
    const std::uint64_t sse_exact = static_cast<std::uint64_t>(sse);
    const std::uint64_t a2 = static_cast<std::uint64_t>(area2);
    return sse_exact * 256 > mse_q8_ * static_cast<std::uint64_t>(n_px) * a2 * a2;
  }

  // Bisects leaf x (longest edge AB) and, if any, its neighbour across AB.
  // Returns false and changes nothing when a child would have area2 < 2.
  bool bisect(int x, int n, int round) {
    const auto t = rotated_to_longest(x);
    const Vertex a = t[0], b = t[1], c = t[2];
    const Vertex m = midpoint(a, b);
    std::vector<std::array<Vertex, 3>> children = {{a, m, c}, {m, b, c}};
    if (n >= 0) {
      Vertex d{};
      for (const Vertex& p : tris_[n].v) {
        if (!(p == a) && !(p == b)) d = p;
      }
      // The neighbour is (B, A, D) in its own (positive) orientation.
      children.push_back({b, m, d});
      children.push_back({m, a, d});
    }
    for (const auto& ch : children) {
      if (twice_area(ch[0], ch[1], ch[2]) < 2) return false;
    }
    for (int id : {x, n}) {
      if (id < 0) continue;
      (tris_[id].wants ? criterion_splits_ : forced_splits_) += 1;
      remove(id);
    }
    for (const auto& ch : children) add(ch, round);
    return true;
  }

  // Longest-edge propagation (Rivara) until triangle id has been bisected.
  void process(int id, int round) {
    while (tris_[id].leaf) {
      int x = id;
      int n;
      for (;;) {
        const auto t = rotated_to_longest(x);
        n = neighbour(x, t[0], t[1]);
        if (n < 0) break;
        const auto tn = rotated_to_longest(n);
        if (edge_key(tn[0], tn[1]) == edge_key(t[0], t[1])) break;  // terminal pair
        x = n;
      }
      if (!bisect(x, n, round)) return;  // blocked: left as it is
    }
  }

  Mesh output() const {
    Mesh mesh;
    mesh.width = gray_.width;
    mesh.height = gray_.height;
    std::set<Key> keys;
    for (const Tri& t : tris_) {
      if (!t.leaf) continue;
      for (const Vertex& p : t.v) keys.insert(key_of(p));
    }
    std::map<Key, int> id_of;
    for (const Key& k : keys) {
      id_of[k] = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back(Vertex{k.second, k.first});
    }
    mesh.row_start.assign(gray_.height + 1, 0);
    for (const Vertex& p : mesh.vertices) ++mesh.row_start[p.y + 1];
    for (int y = 0; y < gray_.height; ++y) mesh.row_start[y + 1] += mesh.row_start[y];
    for (const Tri& t : tris_) {
      if (!t.leaf) continue;
      Triangle ids = {id_of.at(key_of(t.v[0])), id_of.at(key_of(t.v[1])),
                      id_of.at(key_of(t.v[2]))};
      std::rotate(ids.begin(), std::min_element(ids.begin(), ids.end()), ids.end());
      mesh.triangles.push_back(ids);
    }
    std::sort(mesh.triangles.begin(), mesh.triangles.end());
    mesh.forced_splits = forced_splits_;
    mesh.criterion_splits = criterion_splits_;
    return mesh;
  }

  const ImageU8& gray_;
  const TritreeParams params_;
  const std::uint64_t mse_q8_;
  std::vector<Tri> tris_;
  std::map<EdgeKey, std::set<int>> leaves_of_edge_;
  std::int64_t forced_splits_ = 0;
  std::int64_t criterion_splits_ = 0;
};

void check_range(const char* what, long long value, long long lo, long long hi) {
  if (value < lo || value > hi) {
    throw Error(ErrorCode::kInvalidArgument,
                std::string("reference tritree: ") + what + " = " + std::to_string(value) +
                    " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  }
}

}  // namespace

Mesh build_tritree(const ImageU8& gray, const TritreeParams& params) {
  check_range("image width", gray.width, 2, kMaxImageSide);
  check_range("image height", gray.height, 2, kMaxImageSide);
  check_range("image channels", gray.channels, 1, 1);
  const long long expected = static_cast<long long>(gray.width) * gray.height;
  check_range("image pixel count", static_cast<long long>(gray.pixels.size()), expected, expected);
  check_range("max_area_px2", params.max_area_px2, 1, kMaxAreaLimitPx2);
  check_range("psnr_deci_db", params.psnr_deci_db, kMinPsnrDeciDb, kMaxPsnrDeciDb);
  return Builder(gray, params).run();
}

}  // namespace tristereo::reference
