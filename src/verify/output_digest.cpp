// Platform-independent digests and first-difference reports of frame outputs.
#include <cinttypes>
#include <cstdio>
#include <string>

#include "tristereo/mesh.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {

namespace {
// FNV-1a, 64-bit, fed with little-endian integers so the digest does not depend
// on the host byte order.
class Fnv1a64 {
 public:
  void add_u8(std::uint8_t b) { h_ = (h_ ^ b) * 0x100000001b3ULL; }
  void add_i64(std::int64_t v) {
    auto u = static_cast<std::uint64_t>(v);
    for (int i = 0; i < 8; ++i) add_u8(static_cast<std::uint8_t>(u >> (8 * i)));
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
  return buf;
}

std::string fmt(const char* f, long long a, long long b, long long c, long long d) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}
}  // namespace

std::string digest_hex(const StereoOutput& out) {
  Fnv1a64 h;
  h.add_i64(out.mesh.width);
  h.add_i64(out.mesh.height);
  h.add_i64(static_cast<std::int64_t>(out.mesh.vertices.size()));
  for (const Vertex& v : out.mesh.vertices) {
    h.add_i64(v.x);
    h.add_i64(v.y);
  }
  h.add_i64(static_cast<std::int64_t>(out.mesh.triangles.size()));
  for (const Triangle& t : out.mesh.triangles)
    for (int i = 0; i < 3; ++i) h.add_i64(t[i]);
  for (std::int16_t d : out.vertex_disp_q4) h.add_i64(d);
  h.add_i64(out.disp_q4.width);
  h.add_i64(out.disp_q4.height);
  for (std::int16_t d : out.disp_q4.pixels) h.add_i64(d);
  return hex64(h.value());
}

std::string state_digest_hex(const StereoOutput& out) {
  Fnv1a64 h;
  for (const std::vector<std::uint8_t>* v : {&out.vertex_state, &out.vertex_confidence}) {
    h.add_i64(static_cast<std::int64_t>(v->size()));
    for (std::uint8_t b : *v) h.add_u8(b);
  }
  for (const ImageU8* m : {&out.pixel_state, &out.pixel_confidence}) {
    h.add_i64(m->width);
    h.add_i64(m->height);
    for (std::uint8_t b : m->pixels) h.add_u8(b);
  }
  return hex64(h.value());
}

std::string first_difference(const StereoOutput& e, const StereoOutput& a) {
  const Mesh& me = e.mesh;
  const Mesh& ma = a.mesh;
  if (me.width != ma.width || me.height != ma.height)
    return fmt("mesh size differs: %lldx%lld vs %lldx%lld", me.width, me.height, ma.width, ma.height);
  if (me.vertices.size() != ma.vertices.size())
    return "vertex count differs: " + std::to_string(me.vertices.size()) + " vs " +
           std::to_string(ma.vertices.size());
  for (std::size_t i = 0; i < me.vertices.size(); ++i)
    if (!(me.vertices[i] == ma.vertices[i]))
      return "vertex " + std::to_string(i) + " differs: (" + std::to_string(me.vertices[i].x) + ", " +
             std::to_string(me.vertices[i].y) + ") vs (" + std::to_string(ma.vertices[i].x) + ", " +
             std::to_string(ma.vertices[i].y) + ")";
  if (me.triangles.size() != ma.triangles.size())
    return "triangle count differs: " + std::to_string(me.triangles.size()) + " vs " +
           std::to_string(ma.triangles.size());
  for (std::size_t i = 0; i < me.triangles.size(); ++i)
    if (me.triangles[i] != ma.triangles[i])
      return "triangle " + std::to_string(i) + " differs";
  if (me.row_start != ma.row_start) return "row index differs";
  if (me.forced_splits != ma.forced_splits || me.criterion_splits != ma.criterion_splits)
    return "split counts differ: forced " + std::to_string(me.forced_splits) + " vs " +
           std::to_string(ma.forced_splits) + ", criterion " + std::to_string(me.criterion_splits) +
           " vs " + std::to_string(ma.criterion_splits);
  if (e.vertex_disp_q4.size() != a.vertex_disp_q4.size()) return "vertex disparity count differs";
  for (std::size_t i = 0; i < e.vertex_disp_q4.size(); ++i)
    if (e.vertex_disp_q4[i] != a.vertex_disp_q4[i])
      return "sample disparity differs at vertex " + std::to_string(i) + " (" +
             std::to_string(me.vertices[i].x) + ", " + std::to_string(me.vertices[i].y) +
             "): " + std::to_string(e.vertex_disp_q4[i]) + " vs " +
             std::to_string(a.vertex_disp_q4[i]) + " (Q4)";
  if (e.disp_q4.width != a.disp_q4.width || e.disp_q4.height != a.disp_q4.height)
    return "dense map size differs";
  for (int y = 0; y < e.disp_q4.height; ++y)
    for (int x = 0; x < e.disp_q4.width; ++x)
      if (e.disp_q4.at(x, y) != a.disp_q4.at(x, y))
        return fmt("dense map differs at (%lld, %lld): %lld vs %lld (Q4)", x, y, e.disp_q4.at(x, y),
                   a.disp_q4.at(x, y));
  const struct {
    const char* what;
    const std::vector<std::uint8_t>& e;
    const std::vector<std::uint8_t>& a;
  } per_vertex[] = {{"vertex state", e.vertex_state, a.vertex_state},
                    {"vertex confidence", e.vertex_confidence, a.vertex_confidence}};
  for (const auto& v : per_vertex) {
    if (v.e.size() != v.a.size())
      return std::string(v.what) + " count differs: " + std::to_string(v.e.size()) + " vs " +
             std::to_string(v.a.size());
    for (std::size_t i = 0; i < v.e.size(); ++i)
      if (v.e[i] != v.a[i])
        return std::string(v.what) + " differs at vertex " + std::to_string(i) + ": " + std::to_string(v.e[i]) +
               " vs " + std::to_string(v.a[i]);
  }
  const struct {
    const char* what;
    const ImageU8& e;
    const ImageU8& a;
  } per_pixel[] = {{"pixel state", e.pixel_state, a.pixel_state},
                   {"pixel confidence", e.pixel_confidence, a.pixel_confidence}};
  for (const auto& m : per_pixel) {
    if (m.e.width != m.a.width || m.e.height != m.a.height) return std::string(m.what) + " map size differs";
    for (int y = 0; y < m.e.height; ++y)
      for (int x = 0; x < m.e.width; ++x)
        if (m.e.at(x, y) != m.a.at(x, y))
          return m.what + fmt(" differs at (%lld, %lld): %lld vs %lld", x, y, m.e.at(x, y), m.a.at(x, y));
  }
  if (!(e.validity == a.validity))
    return "validity counts differ: filled " + std::to_string(e.validity.filled) + " vs " +
           std::to_string(a.validity.filled) + ", below the minimum confidence " +
           std::to_string(e.validity.min_confidence_rejected) + " vs " +
           std::to_string(a.validity.min_confidence_rejected);
  return "";
}

}  // namespace tristereo
