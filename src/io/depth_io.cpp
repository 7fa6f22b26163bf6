// Metric depth maps and point clouds from a disparity map (include/tristereo/depth.hpp).
#include <cmath>
#include <limits>

#include "src/io/file_util.hpp"
#include "tristereo/depth.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

using namespace io_detail;

namespace {

void check_camera(const CameraParams& c, const char* what) {
  if (!(c.focal_px > 0) || !std::isfinite(c.focal_px) || !(c.baseline > 0) || !std::isfinite(c.baseline) ||
      !std::isfinite(c.cx) || !std::isfinite(c.cy) || !std::isfinite(c.doffs))
    throw Error(ErrorCode::kInvalidArgument,
                std::string(what) + ": the camera needs a focal length and baseline > 0 and a finite "
                "principal point and doffs");
}

// Z in metres, or +inf when the pixel has no depth. In double, then rounded
// once to float: the 1e-4 relative accuracy the tests ask is far inside it.
double depth_m(double d_px, const CameraParams& c) {
  const double denom = d_px + c.doffs;
  if (!std::isfinite(denom) || !(denom > 0)) return std::numeric_limits<double>::infinity();
  return c.focal_px * c.baseline / denom;
}

double depth_m(std::int16_t q4, const CameraParams& c) {
  if (q4 == kInvalidDispQ4) return std::numeric_limits<double>::infinity();
  return depth_m(q4 / 16.0, c);
}

}  // namespace

void check_depth_limits(const DepthLimits& l) {
  const auto bad = [](double v) { return !std::isfinite(v) || v < 0; };
  if (bad(l.min_disparity_px))
    throw Error(ErrorCode::kInvalidArgument, "depth limits: min_disparity_px must be finite and >= 0");
  if (bad(l.min_depth_m))
    throw Error(ErrorCode::kInvalidArgument, "depth limits: min_depth_m must be finite and >= 0");
  if (bad(l.max_depth_m))
    throw Error(ErrorCode::kInvalidArgument, "depth limits: max_depth_m must be finite and >= 0");
  if (l.max_depth_m > 0 && !(l.max_depth_m > l.min_depth_m))
    throw Error(ErrorCode::kInvalidArgument, "depth limits: max_depth_m must be above min_depth_m (or 0: no limit)");
}

std::int64_t apply_depth_limits(ImageView<std::int16_t> disp_q4, const CameraParams& camera,
                                const DepthLimits& limits) {
  check_write_view(disp_q4, 1, 1, "apply_depth_limits");
  check_camera(camera, "apply_depth_limits");
  check_depth_limits(limits);
  std::int64_t removed = 0;
  for (int y = 0; y < disp_q4.height; ++y) {
    std::int16_t* row = disp_q4.row(y);
    for (int x = 0; x < disp_q4.width; ++x) {
      if (row[x] == kInvalidDispQ4) continue;
      const double effective = row[x] / 16.0 + camera.doffs;
      const double z = depth_m(row[x], camera);  // +inf when effective <= 0
      const bool keep = effective > 0 && effective >= limits.min_disparity_px && z >= limits.min_depth_m &&
                        (limits.max_depth_m == 0 || z <= limits.max_depth_m);
      if (!keep) {
        row[x] = kInvalidDispQ4;
        ++removed;
      }
    }
  }
  return removed;
}

Image<float> depth_m_from_disp_q4(ImageView<const std::int16_t> disp_q4, const CameraParams& camera) {
  check_write_view(disp_q4, 1, 1, "depth_m_from_disp_q4");
  check_camera(camera, "depth_m_from_disp_q4");
  Image<float> out(disp_q4.width, disp_q4.height, 1);
  for (int y = 0; y < disp_q4.height; ++y)
    for (int x = 0; x < disp_q4.width; ++x)
      out.at(x, y) = static_cast<float>(depth_m(disp_q4.row(y)[x], camera));
  return out;
}

Image<float> depth_m_from_disp_px(ImageView<const float> disp_px, const CameraParams& camera) {
  check_write_view(disp_px, 1, 1, "depth_m_from_disp_px");
  check_camera(camera, "depth_m_from_disp_px");
  Image<float> out(disp_px.width, disp_px.height, 1);
  for (int y = 0; y < disp_px.height; ++y)
    for (int x = 0; x < disp_px.width; ++x)
      out.at(x, y) = static_cast<float>(depth_m(static_cast<double>(disp_px.row(y)[x]), camera));
  return out;
}

DepthWriteReport write_depth(const std::string& path, ImageView<const float> depth) {
  check_write_view(depth, 1, 1, "write_depth");
  const std::string ext = lower_extension(path);
  if (ext != ".pfm" && ext != ".png")
    throw Error(ErrorCode::kInvalidArgument,
                "depth file '" + path + "': the extension must be .pfm (metres) or .png (uint16 millimetres)");
  DepthWriteReport r;
  if (ext == ".pfm") {
    for (int y = 0; y < depth.height; ++y)
      for (int x = 0; x < depth.width; ++x) (std::isfinite(depth.row(y)[x]) ? r.valid : r.invalid)++;
    write_pfm(path, depth);
    return r;
  }
  Image<std::uint16_t> mm(depth.width, depth.height, 1);
  for (int y = 0; y < depth.height; ++y)
    for (int x = 0; x < depth.width; ++x) {
      const float z = depth.row(y)[x];
      std::uint16_t v = 0;
      if (!std::isfinite(z) || !(z > 0)) {
        ++r.invalid;
      } else if (static_cast<double>(z) * 1000.0 + 0.5 >= 65536.0) {
        ++r.out_of_range;
        ++r.invalid;
      } else {
        v = static_cast<std::uint16_t>(std::floor(static_cast<double>(z) * 1000.0 + 0.5));
        if (v == 0) {  // under half a millimetre: not representable, 0 means invalid
          ++r.invalid;
        } else {
          ++r.valid;
        }
      }
      mm.at(x, y) = v;
    }
  write_png_u16(path, mm.view());
  return r;
}

std::int64_t write_points_ply(const std::string& path, ImageView<const std::int16_t> disp_q4,
                              ImageView<const std::uint8_t> left, const CameraParams& camera, bool binary) {
  check_write_view(disp_q4, 1, 1, "write_points_ply (disparity)");
  check_write_view(left, 1, 3, "write_points_ply (left image)");
  check_camera(camera, "write_points_ply");
  if (left.width != disp_q4.width || left.height != disp_q4.height)
    throw Error(ErrorCode::kSizeMismatch, "write_points_ply: the left image is " + std::to_string(left.width) +
                                              "x" + std::to_string(left.height) + ", the disparity map " +
                                              std::to_string(disp_q4.width) + "x" +
                                              std::to_string(disp_q4.height));
  std::int64_t n = 0;
  for (int y = 0; y < disp_q4.height; ++y)
    for (int x = 0; x < disp_q4.width; ++x)
      if (std::isfinite(depth_m(disp_q4.row(y)[x], camera))) ++n;
  std::string header = "ply\nformat ";
  header += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  header += "comment tristereo point cloud: metres, camera frame of the left view (x right, y down, z forward)\n";
  header += "element vertex " + std::to_string(n) + "\n";
  header += "property float x\nproperty float y\nproperty float z\n";
  header += "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  OutputFile file(path);
  file.write(header);
  std::string chunk;
  chunk.reserve(1 << 16);
  for (int y = 0; y < disp_q4.height; ++y)
    for (int x = 0; x < disp_q4.width; ++x) {
      const double z = depth_m(disp_q4.row(y)[x], camera);
      if (!std::isfinite(z)) continue;
      const float xyz[3] = {static_cast<float>((x - camera.cx) * z / camera.focal_px),
                            static_cast<float>((y - camera.cy) * z / camera.focal_px), static_cast<float>(z)};
      // A point finite in double can still overflow float: refused (before the
      // rename, so nothing appears under the path) rather than written as inf.
      if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
        throw Error(ErrorCode::kInvalidArgument,
                    "write_points_ply: the camera puts pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                        ") at a point beyond float range; check the camera's values and units");
      const std::uint8_t* px = left.row(y) + static_cast<std::ptrdiff_t>(x) * left.channels;
      const std::uint8_t rgb[3] = {px[0], px[left.channels == 3 ? 1 : 0], px[left.channels == 3 ? 2 : 0]};
      if (binary) {
        for (float v : xyz) append_float_le(chunk, v);
        for (std::uint8_t c : rgb) chunk += static_cast<char>(c);
      } else {
        for (float v : xyz) {
          append_float_text(chunk, v);
          chunk += ' ';
        }
        chunk += std::to_string(rgb[0]) + ' ' + std::to_string(rgb[1]) + ' ' + std::to_string(rgb[2]) + '\n';
      }
      if (chunk.size() >= (1 << 16) - 64) {
        file.write(chunk);
        chunk.clear();
      }
    }
  file.write(chunk);
  file.commit();
  return n;
}

}  // namespace tristereo
