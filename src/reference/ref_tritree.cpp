// Float reference tritree: readable, slow, and the specification in code
// (docs/model.md section 1).
//
// The hierarchy is generated literally: tile halves, each bisected at the
// exact midpoint of its longest edge, down to area 1 px^2 (virtual). Every
// triangle's test sums the plane residuals of the pixels it owns, tested one
// by one with the fill rule; need() is computed level by level from the
// smallest triangles up, then the mesh is read top-down.
//
// Exactness: every double below holds an integer. Coordinates are < 4096 and
// intensities <= 255, so the normal's components are below 2^22, a residual
// (|r| <= 255 area2 < 2^19 when the plane test runs, area2 <= 2048) squared
// is below 2^38 and a triangle's SSE below 2^52 (docs/model.md section 5):
// exactly representable, so the sums are exact in any order (the build uses
// -ffp-contract=off anyway). The final comparison can exceed 2^53, so it is
// made on the exact values converted to uint64.
#include "src/reference/ref_tritree.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "src/model/psnr_threshold.hpp"
#include "tristereo/status.hpp"

namespace tristereo::reference {

namespace {

using Key = std::pair<int, int>;  // (y, x): raster order
using Corners = std::array<Vertex, 3>;

Key key_of(const Vertex& v) { return {v.y, v.x}; }

long long twice_area(const Corners& t) {
  return static_cast<long long>(t[1].x - t[0].x) * (t[2].y - t[0].y) -
         static_cast<long long>(t[1].y - t[0].y) * (t[2].x - t[0].x);
}

enum class Where { kInside, kCrossing, kOutside };

struct Node {
  Corners v;      // virtual corners, positive orientation, v[0] v[1] the hypotenuse
  Where where;
  bool splittable;  // virtual area >= 2 px^2: children of area >= 1
  bool wants = false;
  int child[2] = {-1, -1};
};

class Builder {
 public:
  Builder(const ImageU8& gray, const TritreeParams& params)
      : gray_(gray), params_(params), mse_q8_(mse_threshold_q8(params.psnr_deci_db)) {
    w_ = gray.width;
    h_ = gray.height;
    vw_ = (w_ - 1) % 2 == 0 ? w_ - 1 : w_ - 2;
    vh_ = (h_ - 1) % 2 == 0 ? h_ - 1 : h_ - 2;
    tile_ = 2;
    while (tile_ * tile_ / 2 <= params.max_area_px2) tile_ *= 2;
  }

  Mesh run() {
    std::vector<Corners> leaves;
    if (vw_ == 0 || vh_ == 0) {
      // A side of 2 pixels: the two triangles of the diagonal, never split.
      leaves.push_back({Vertex{0, 0}, Vertex{w_ - 1, 0}, Vertex{w_ - 1, h_ - 1}});
      leaves.push_back({Vertex{0, 0}, Vertex{w_ - 1, h_ - 1}, Vertex{0, h_ - 1}});
      return output(leaves);
    }
    // The tiles' halves: '\' diagonal when x0/S + y0/S is even.
    std::vector<int> roots;
    for (int y0 = 0; y0 < vh_; y0 += tile_) {
      for (int x0 = 0; x0 < vw_; x0 += tile_) {
        const int x1 = x0 + tile_, y1 = y0 + tile_;
        const Vertex a{x0, y0}, b{x1, y0}, c{x1, y1}, d{x0, y1};
        if ((x0 / tile_ + y0 / tile_) % 2 == 0) {
          roots.push_back(add({a, c, b}));  // hypotenuse first: a-c
          roots.push_back(add({c, a, d}));
        } else {
          roots.push_back(add({b, d, a}));
          roots.push_back(add({d, b, c}));
        }
      }
    }
    // need(m), from the smallest triangles up.
    std::vector<int> order;
    for (int i = 0; i < static_cast<int>(nodes_.size()); ++i) order.push_back(i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return twice_area(nodes_[a].v) < twice_area(nodes_[b].v);
    });
    for (int i : order) {
      Node& n = nodes_[i];
      const Key m = midpoint_key(n.v);
      if (n.where == Where::kCrossing) {
        need_[m] = true;
      } else if (n.where == Where::kInside && n.splittable) {
        // The minimum area: only a triangle whose children would have at
        // least A_min (virtual area) may want to split.
        n.wants = twice_area(n.v) >= 4 * params_.min_area_px2 && wants_split(real(n.v));
        bool own = n.wants;
        for (int c : n.child) {
          if (c >= 0 && nodes_[c].splittable) own = own || need(midpoint_key(nodes_[c].v));
        }
        if (own) need_[m] = true;
      }
    }
    for (int r : roots) collect(r, leaves);
    return output(leaves);
  }

 private:
  // The real pixel of a virtual point: the last virtual column (row) moves one
  // pixel right (down) when W - 1 (H - 1) is odd.
  Vertex real(const Vertex& p) const {
    return Vertex{p.x == vw_ && vw_ != w_ - 1 ? p.x + 1 : p.x, p.y == vh_ && vh_ != h_ - 1 ? p.y + 1 : p.y};
  }
  Corners real(const Corners& t) const { return {real(t[0]), real(t[1]), real(t[2])}; }

  static Key midpoint_key(const Corners& t) {
    return {(t[0].y + t[1].y) / 2, (t[0].x + t[1].x) / 2};  // exact: the hypotenuse has even extents
  }
  bool need(const Key& m) const {
    const auto it = need_.find(m);
    return it != need_.end() && it->second;
  }

  Where where_of(const Corners& t) const {
    int min_x = t[0].x, max_x = t[0].x, min_y = t[0].y, max_y = t[0].y;
    for (const Vertex& p : t) {
      min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
      min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
    }
    if (min_x >= vw_ || min_y >= vh_) return Where::kOutside;
    if (max_x <= vw_ && max_y <= vh_) return Where::kInside;
    return Where::kCrossing;
  }

  // Adds a triangle (v[0] v[1] its hypotenuse) and, unless it is outside or
  // too small, its two children: bisected at the hypotenuse's midpoint M into
  // (C, A, M) and (B, C, M), each again listed hypotenuse first.
  int add(const Corners& v) {
    const int id = static_cast<int>(nodes_.size());
    Corners oriented = v;
    if (twice_area(oriented) < 0) std::swap(oriented[0], oriented[1]);
    nodes_.push_back(Node{oriented, where_of(oriented), twice_area(oriented) >= 4});
    if (nodes_[id].where == Where::kOutside || !nodes_[id].splittable) return id;
    const Vertex a = oriented[0], b = oriented[1], c = oriented[2];
    const Vertex m{(a.x + b.x) / 2, (a.y + b.y) / 2};
    const int c0 = add({c, a, m});
    const int c1 = add({b, c, m});
    nodes_[id].child[0] = c0;
    nodes_[id].child[1] = c1;
    return id;
  }

  void collect(int id, std::vector<Corners>& leaves) {
    const Node& n = nodes_[id];
    if (n.where == Where::kOutside) return;
    bool split = n.where == Where::kCrossing;
    if (!split && n.splittable && need(midpoint_key(n.v))) {
      split = true;
      (n.wants ? criterion_splits_ : forced_splits_) += 1;
    }
    if (split) {
      collect(n.child[0], leaves);
      collect(n.child[1], leaves);
    } else {
      leaves.push_back(real(n.v));
    }
  }

  // Fill rule, pixel by pixel: inside every directed edge, ties decided by
  // the sign of the edge function at the pixel nudged by e * (sx, e * sy).
  bool owns(const Corners& v, int px, int py) const {
    const int sx = (px == w_ - 1) ? -1 : 1;
    const int sy = (py == h_ - 1) ? -1 : 1;
    for (int i = 0; i < 3; ++i) {
      const Vertex& u = v[i];
      const Vertex& t = v[(i + 1) % 3];
      const long long ex = t.x - u.x, ey = t.y - u.y;
      const long long e = ex * (py - u.y) - ey * (px - u.x);
      if (e > 0) continue;
      if (e < 0) return false;
      const bool tie_owned = (-sx * ey > 0) || (ey == 0 && sy * ex > 0);
      if (!tie_owned) return false;
    }
    return true;
  }

  double intensity(const Vertex& p) const { return gray_.at(p.x, p.y); }

  // The paper's test on the real triangle: area, then the plane's PSNR.
  bool wants_split(const Corners& v) const {
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

  Mesh output(const std::vector<Corners>& leaves) const {
    Mesh mesh;
    mesh.width = w_;
    mesh.height = h_;
    std::set<Key> keys;
    for (const Corners& t : leaves) {
      for (const Vertex& p : t) keys.insert(key_of(p));
    }
    std::map<Key, int> id_of;
    for (const Key& k : keys) {
      id_of[k] = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back(Vertex{k.second, k.first});
    }
    mesh.row_start.assign(h_ + 1, 0);
    for (const Vertex& p : mesh.vertices) ++mesh.row_start[p.y + 1];
    for (int y = 0; y < h_; ++y) mesh.row_start[y + 1] += mesh.row_start[y];
    for (const Corners& t : leaves) {
      Triangle ids = {id_of.at(key_of(t[0])), id_of.at(key_of(t[1])), id_of.at(key_of(t[2]))};
      std::rotate(ids.begin(), std::min_element(ids.begin(), ids.end()), ids.end());
      mesh.triangles.push_back(ids);
    }
    mesh.forced_splits = forced_splits_;
    mesh.criterion_splits = criterion_splits_;
    return mesh;
  }

  const ImageU8& gray_;
  const TritreeParams params_;
  const std::uint64_t mse_q8_;
  int w_ = 0, h_ = 0, vw_ = 0, vh_ = 0, tile_ = 2;
  std::vector<Node> nodes_;
  std::map<Key, bool> need_;
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
  check_range("min_area_px2", params.min_area_px2, 1, largest_min_area_px2(params.max_area_px2));
  return Builder(gray, params).run();
}

}  // namespace tristereo::reference
