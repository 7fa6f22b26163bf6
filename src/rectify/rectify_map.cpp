// The fixed-point maps (include/tristereo/rectify.hpp): built once from the
// double-precision map of rectify_geometry.cpp, then read by every frame.
#include "src/rectify/rectify_map.hpp"

#include <cmath>
#include <string>

#include "src/kernels/dispatch.hpp"
#include "src/rectify/rectify_geometry.hpp"
#include "tristereo/params.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

RectifyMap build_one(const StereoRig& rig, const Rectification& rect, int camera) {
  const RawCamera& cam = camera == 0 ? rig.left : rig.right;
  RectifyMap m;
  m.width = rect.width;
  m.height = rect.height;
  m.raw_width = cam.width;
  m.raw_height = cam.height;
  const std::size_t px = static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height);
  m.xy.assign(2 * px, 0);
  m.frac.assign(px, 0);
  m.border_row.assign(static_cast<std::size_t>(m.height) + 1, 0);
  const RectifyProjector projector(rig, rect, camera);
  const double one = 1 << kRemapFracBits;
  // Positions further out than one pixel have every tap outside: clamping
  // them there keeps the integers small and changes no output.
  const double lo = -2 * one, hi_x = (m.raw_width + 1) * one, hi_y = (m.raw_height + 1) * one;
  for (int v = 0; v < m.height; ++v) {
    m.border_row[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(m.border.size());
    for (int u = 0; u < m.width; ++u) {
      double x, y;
      projector.raw(u, v, &x, &y);
      // std::nearbyint in the default rounding mode: to nearest, ties to even.
      const double X = std::isfinite(x) ? std::fmin(std::fmax(std::nearbyint(x * one), lo), hi_x) : lo;
      const double Y = std::isfinite(y) ? std::fmin(std::fmax(std::nearbyint(y * one), lo), hi_y) : lo;
      const int xi = static_cast<int>(X), yi = static_cast<int>(Y);
      const int ix = xi >> kRemapFracBits, iy = yi >> kRemapFracBits;  // floor (arithmetic shift)
      const std::uint16_t frac = static_cast<std::uint16_t>(((yi & 31) << kRemapFracBits) | (xi & 31));
      if (ix >= 0 && iy >= 0 && ix + 1 < m.raw_width && iy + 1 < m.raw_height) {
        const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(m.width) + static_cast<std::size_t>(u);
        m.xy[2 * i] = static_cast<std::int16_t>(ix);
        m.xy[2 * i + 1] = static_cast<std::int16_t>(iy);
        m.frac[i] = frac;
      } else {
        m.border.push_back({u, static_cast<std::int16_t>(ix), static_cast<std::int16_t>(iy), frac});
      }
    }
  }
  m.border_row[static_cast<std::size_t>(m.height)] = static_cast<std::int32_t>(m.border.size());
  m.border.shrink_to_fit();
  return m;
}

}  // namespace

std::size_t RectifyMap::memory_bytes() const {
  return xy.capacity() * sizeof(std::int16_t) + frac.capacity() * sizeof(std::uint16_t) +
         border.capacity() * sizeof(Border) + border_row.capacity() * sizeof(std::int32_t);
}

std::size_t RectifyMaps::memory_bytes() const { return left.memory_bytes() + right.memory_bytes(); }

RectifyMaps build_rectify_maps(const StereoRig& rig, const Rectification& rect) {
  for (const RawCamera* c : {&rig.left, &rig.right})
    if (c->width < 2 || c->height < 2 || c->width > kMaxImageSide || c->height > kMaxImageSide)
      throw Error(ErrorCode::kInvalidArgument, "calibration file '" + rig.path + "': raw images of " +
                                                   std::to_string(c->width) + "x" + std::to_string(c->height) +
                                                   " are outside 2.." + std::to_string(kMaxImageSide) + " per side");
  if (rect.width < 2 || rect.height < 2 || rect.width > kMaxImageSide || rect.height > kMaxImageSide)
    throw Error(ErrorCode::kInvalidArgument, "rectified size " + std::to_string(rect.width) + "x" +
                                                 std::to_string(rect.height) + " is outside 2.." +
                                                 std::to_string(kMaxImageSide) + " per side");
  RectifyMaps maps;
  maps.rect = rect;
  maps.left = build_one(rig, rect, 0);
  maps.right = build_one(rig, rect, 1);
  return maps;
}

std::uint8_t remap_border_pixel(const RectifyMap::Border& b, ImageView<const std::uint8_t> raw) {
  const std::int32_t fx = b.frac & 31, fy = b.frac >> 5;
  auto p = [&](int x, int y) -> std::int32_t {
    return x >= 0 && y >= 0 && x < raw.width && y < raw.height ? raw.row(y)[x] : 0;
  };
  const std::int32_t sum = p(b.ix, b.iy) * (32 - fx) * (32 - fy) + p(b.ix + 1, b.iy) * fx * (32 - fy) +
                           p(b.ix, b.iy + 1) * (32 - fx) * fy + p(b.ix + 1, b.iy + 1) * fx * fy;
  return static_cast<std::uint8_t>((sum + 512) >> 10);
}

void remap_rows(const RectifyMap& map, ImageView<const std::uint8_t> raw, ImageView<std::uint8_t> out, int v0, int v1,
                const KernelSet& kernels) {
  const std::size_t stride = static_cast<std::size_t>(raw.stride_bytes);
  for (int v = v0; v < v1; ++v) {
    const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(map.width);
    std::uint8_t* row = out.row(v);
    kernels.remap_bilinear_row_u8(raw.data, stride, map.xy.data() + 2 * i, map.frac.data() + i, map.width, row);
    for (std::int32_t k = map.border_row[static_cast<std::size_t>(v)]; k < map.border_row[static_cast<std::size_t>(v) + 1];
         ++k) {
      const RectifyMap::Border& b = map.border[static_cast<std::size_t>(k)];
      row[b.u] = remap_border_pixel(b, raw);
    }
  }
}

void remap_image(const RectifyMap& map, ImageView<const std::uint8_t> raw, ImageView<std::uint8_t> out,
                 KernelChoice kernels) {
  if (raw.data == nullptr || raw.channels != 1 || raw.width != map.raw_width || raw.height != map.raw_height ||
      raw.stride_bytes < raw.width)
    throw Error(ErrorCode::kSizeMismatch, "remap_image: the raw image must be gray, " + std::to_string(map.raw_width) +
                                              "x" + std::to_string(map.raw_height) + ", the map's raw size");
  if (out.data == nullptr || out.channels != 1 || out.width != map.width || out.height != map.height ||
      out.stride_bytes < out.width)
    throw Error(ErrorCode::kSizeMismatch, "remap_image: the output must be gray, " + std::to_string(map.width) + "x" +
                                              std::to_string(map.height) + ", the map's rectified size");
  remap_rows(map, raw, out, 0, map.height, kernel_set_for(kernels));
}

}  // namespace tristereo
