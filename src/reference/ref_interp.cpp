// Reference: per-triangle plane interpolation (docs/model.md section 4), with
// its own transcription of the fill rule (section 1) tested pixel by pixel.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <string>

#include "src/reference/ref_match.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace reference {

namespace {

// Does directed edge u -> v keep pixel p on the triangle's side? E > 0, or
// E == 0 and the sign of E at p nudged by e (sx, e sy) is positive.
bool edge_keeps(const Vertex& u, const Vertex& v, int px, int py, int width, int height) {
  const long long e = static_cast<long long>(v.x - u.x) * (py - u.y) -
                      static_cast<long long>(v.y - u.y) * (px - u.x);
  if (e > 0) return true;
  if (e < 0) return false;
  const int sx = px == width - 1 ? -1 : 1;
  const int sy = py == height - 1 ? -1 : 1;
  const long long first_order = -static_cast<long long>(sx) * (v.y - u.y);  // coefficient of e
  if (first_order != 0) return first_order > 0;
  return static_cast<long long>(sy) * (v.x - u.x) > 0;                       // coefficient of e^2
}

// Calls fn(x, y) for every pixel the triangle (a, b, c) owns: the pixels of
// its bounding box (clipped to the image) that all three edges keep.
template <class Fn>
void for_each_owned_pixel(const Vertex& a, const Vertex& b, const Vertex& c, int width, int height, Fn fn) {
  for (int y = std::max(0, std::min({a.y, b.y, c.y})); y <= std::min(height - 1, std::max({a.y, b.y, c.y})); ++y)
    for (int x = std::max(0, std::min({a.x, b.x, c.x})); x <= std::min(width - 1, std::max({a.x, b.x, c.x})); ++x)
      if (edge_keeps(a, b, x, y, width, height) && edge_keeps(b, c, x, y, width, height) &&
          edge_keeps(c, a, x, y, width, height))
        fn(x, y);
}

}  // namespace

ImageS16 interpolate(const Mesh& mesh, const std::vector<std::int16_t>& vertex_disp_q4) {
  if (vertex_disp_q4.size() != mesh.vertices.size())
    throw Error(ErrorCode::kSizeMismatch,
                "vertex_disp_q4 has " + std::to_string(vertex_disp_q4.size()) +
                    " entries, the mesh has " + std::to_string(mesh.vertices.size()) + " vertices");
  const int w = mesh.width, h = mesh.height;
  ImageS16 out(w, h, 1, kInvalidDispQ4);
  Image<int> owners(w, h, 1, 0);

  for (const Triangle& t : mesh.triangles) {
    const Vertex& a = mesh.vertices.at(static_cast<std::size_t>(t[0]));
    const Vertex& b = mesh.vertices.at(static_cast<std::size_t>(t[1]));
    const Vertex& c = mesh.vertices.at(static_cast<std::size_t>(t[2]));
    const std::int16_t da = vertex_disp_q4[static_cast<std::size_t>(t[0])];
    const std::int16_t db = vertex_disp_q4[static_cast<std::size_t>(t[1])];
    const std::int16_t dc = vertex_disp_q4[static_cast<std::size_t>(t[2])];
    const bool invalid = da == kInvalidDispQ4 || db == kInvalidDispQ4 || dc == kInvalidDispQ4;

    // Plane normal of the (x, y, d) points. Every coordinate is an integer
    // below 2^17 and every product below 2^53, so the doubles are exact.
    const Eigen::Vector3d pa(a.x, a.y, da), pb(b.x, b.y, db), pc(c.x, c.y, dc);
    const Eigen::Vector3d n = (pb - pa).cross(pc - pa);
    const double area2 = n.z();
    if (area2 <= 0)
      throw Error(ErrorCode::kInvalidArgument, "triangle with non-positive orientation");

    for_each_owned_pixel(a, b, c, w, h, [&](int x, int y) {
      ++owners.at(x, y);
      if (invalid) {
        out.at(x, y) = kInvalidDispQ4;
        return;
      }
      // N = area2 dA - n_x (x - Ax) - n_y (y - Ay): exact, |N| < 2^43.
      const double num = area2 * da - n.x() * (x - a.x) - n.y() * (y - a.y);
      // floor((2N + area2) / (2 area2)): the numerator is exact; if the true
      // quotient is not an integer it is at least 1/(2 area2) > 2^-27 from
      // one, while the division's rounding error is below 2^-37 (|q| < 2^16),
      // so the floor of the double quotient is the exact one.
      out.at(x, y) = static_cast<std::int16_t>(std::floor((2 * num + area2) / (2 * area2)));
    });
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (owners.at(x, y) != 1)
        throw Error(ErrorCode::kInvalidArgument,
                    "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is owned by " +
                        std::to_string(owners.at(x, y)) + " triangles, expected exactly 1");
  return out;
}

void interpolate_states(const Mesh& mesh, const std::vector<std::uint8_t>& vertex_state,
                        const std::vector<std::uint8_t>& vertex_confidence, ImageU8& state,
                        ImageU8& confidence) {
  const int w = mesh.width, h = mesh.height;
  state = ImageU8(w, h, 1, 0);
  confidence = ImageU8(w, h, 1, 0);
  for (const Triangle& t : mesh.triangles) {
    Eigen::Vector2d corner[3];
    std::uint8_t s[3], conf[3];
    bool invalid = false;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t id = static_cast<std::size_t>(t[k]);
      const Vertex& v = mesh.vertices.at(id);
      corner[k] = Eigen::Vector2d(v.x, v.y);
      s[k] = vertex_state.at(id);
      conf[k] = vertex_confidence.at(id);
      invalid = invalid || s[k] == static_cast<std::uint8_t>(SampleState::kInvalid);
    }
    const Vertex& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vertex& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Vertex& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    for_each_owned_pixel(a, b, c, w, h, [&](int x, int y) {
      if (invalid) {  // the pixel's disparity is invalid (section 4)
        state.at(x, y) = 0;
        confidence.at(x, y) = 0;
        return;
      }
      // Vertex k's barycentric weight at P is the signed area of P and the
      // opposite edge over the triangle's (integers below 2^26: exact).
      const Eigen::Vector2d p(x, y);
      std::uint8_t st = 255, cf = 255;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d& u = corner[(k + 1) % 3];
        const Eigen::Vector2d& v = corner[(k + 2) % 3];
        const Eigen::Vector2d e = v - u, q = p - u;
        const double weight_area2 = e.x() * q.y() - e.y() * q.x();
        if (weight_area2 == 0.0) continue;  // P on the edge opposite vertex k: no weight
        st = std::min(st, s[k]);
        cf = std::min(cf, conf[k]);
      }
      state.at(x, y) = st;
      confidence.at(x, y) = cf;
    });
  }
}

void interpolate_depth_edges(const Mesh& mesh, const std::vector<std::int16_t>& vertex_disp_q4,
                             const ImageU8& gray, int spread_q4, ImageS16& disp_q4,
                             const std::vector<std::uint8_t>* vertex_state,
                             const std::vector<std::uint8_t>* vertex_confidence, ImageU8* state,
                             ImageU8* confidence) {
  if (spread_q4 <= 0) return;
  const int w = mesh.width, h = mesh.height;
  for (const Triangle& t : mesh.triangles) {
    int lo = INT_MAX, hi = INT_MIN;
    bool valid = true;
    for (std::size_t k = 0; k < 3; ++k) {
      const int d = vertex_disp_q4.at(static_cast<std::size_t>(t[k]));
      valid = valid && d != kInvalidDispQ4;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    if (!valid || hi - lo <= spread_q4) continue;
    const Vertex& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vertex& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Vertex& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    for_each_owned_pixel(a, b, c, w, h, [&](int x, int y) {
      // The chosen vertex: the smallest (intensity distance, disparity,
      // confidence), or the pixel's own vertex.
      std::size_t id = 0;
      long long best_key = LLONG_MAX;
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t v = static_cast<std::size_t>(t[k]);
        const Vertex& q = mesh.vertices[v];
        const long long dist = q.x == x && q.y == y ? -1 : std::abs(int{gray.at(x, y)} - int{gray.at(q.x, q.y)});
        const long long conf = state != nullptr ? vertex_confidence->at(v) : 0;
        const long long key = ((dist + 1) << 40) + ((vertex_disp_q4[v] + 65536LL) << 8) + conf;
        if (key < best_key) best_key = key, id = v;
      }
      disp_q4.at(x, y) = vertex_disp_q4[id];
      if (state != nullptr) {
        state->at(x, y) = vertex_state->at(id);
        confidence->at(x, y) = vertex_confidence->at(id);
      }
    });
  }
}

}  // namespace reference
}  // namespace tristereo
