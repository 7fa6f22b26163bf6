// The 2.5D mesh as a PLY file (ASCII or binary little endian).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "src/io/file_util.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

using namespace io_detail;

namespace {

// A number for a message: 6 significant digits, never the 300 digits that
// std::to_string gives 1e300.
std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

[[noreturn]] void bad(ErrorCode code, const std::string& why) {
  throw Error(code, "write_mesh_ply: " + why);
}

void check_inputs(const Mesh& mesh, const std::vector<std::int16_t>& disp,
                  ImageView<const std::uint8_t> img, const CameraParams* camera) {
  check_write_view(img, 1, 3, "write_mesh_ply (left image)");
  if (img.width != mesh.width || img.height != mesh.height) {
    bad(ErrorCode::kSizeMismatch, "left image is " + std::to_string(img.width) + " x " +
                                      std::to_string(img.height) + ", mesh is " +
                                      std::to_string(mesh.width) + " x " +
                                      std::to_string(mesh.height));
  }
  if (disp.size() != mesh.vertices.size()) {
    bad(ErrorCode::kSizeMismatch, std::to_string(disp.size()) + " vertex disparities for " +
                                      std::to_string(mesh.vertices.size()) + " vertices");
  }
  if (mesh.vertices.size() > 0x7fffffffu) bad(ErrorCode::kInvalidArgument, "too many vertices");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vertex& v = mesh.vertices[i];
    if (v.x < 0 || v.x >= mesh.width || v.y < 0 || v.y >= mesh.height) {
      bad(ErrorCode::kInvalidArgument, "vertex " + std::to_string(i) + " at (" +
                                           std::to_string(v.x) + ", " + std::to_string(v.y) +
                                           ") lies outside the " + std::to_string(mesh.width) +
                                           " x " + std::to_string(mesh.height) + " image");
    }
  }
  const auto n = static_cast<std::int64_t>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::int32_t id : mesh.triangles[t]) {
      if (id < 0 || id >= n) {
        bad(ErrorCode::kInvalidArgument, "triangle " + std::to_string(t) + " references vertex " +
                                             std::to_string(id) + " (valid 0.." +
                                             std::to_string(n - 1) + ")");
      }
    }
  }
  if (camera) {
    const CameraParams& c = *camera;
    if (!(std::isfinite(c.focal_px) && c.focal_px > 0)) {
      bad(ErrorCode::kInvalidArgument, "camera focal_px " + short_number(c.focal_px) +
                                           " must be finite and > 0");
    }
    if (!(std::isfinite(c.baseline) && c.baseline > 0)) {
      bad(ErrorCode::kInvalidArgument, "camera baseline " + short_number(c.baseline) +
                                           " must be finite and > 0");
    }
    if (!std::isfinite(c.cx) || !std::isfinite(c.cy) || !std::isfinite(c.doffs)) {
      bad(ErrorCode::kInvalidArgument, "camera cx, cy and doffs must be finite");
    }
  }
}

void append_int_le(std::string& out, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) out += static_cast<char>((u >> (8 * i)) & 0xff);
}

}  // namespace

MeshWriteReport write_mesh_ply(const std::string& path, const Mesh& mesh,
                               const std::vector<std::int16_t>& vertex_disp_q4,
                               ImageView<const std::uint8_t> left_gray_or_rgb,
                               const CameraParams* camera, bool binary) {
  check_inputs(mesh, vertex_disp_q4, left_gray_or_rgb, camera);
  const std::size_t nv = mesh.vertices.size();

  // Positions first: they decide which faces survive (the header needs the count).
  std::vector<float> xyz(3 * nv);
  // Per vertex: 1 = has a position; 0 = invalid disparity; 2 = at or behind infinity.
  enum : std::uint8_t { kNoDisparity = 0, kHasDepth = 1, kBehind = 2 };
  std::vector<std::uint8_t> has_depth(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const Vertex& v = mesh.vertices[i];
    const std::int16_t q = vertex_disp_q4[i];
    if (q == kInvalidDispQ4) {
      has_depth[i] = kNoDisparity;
      xyz[3 * i] = camera ? 0.f : static_cast<float>(v.x);
      xyz[3 * i + 1] = camera ? 0.f : static_cast<float>(v.y);
      xyz[3 * i + 2] = 0.f;
      continue;
    }
    const double d = static_cast<double>(q) / kDispOne;
    if (!camera) {
      has_depth[i] = kHasDepth;
      xyz[3 * i] = static_cast<float>(v.x);
      xyz[3 * i + 1] = static_cast<float>(v.y);
      xyz[3 * i + 2] = static_cast<float>(d);
      continue;
    }
    const double denom = d + camera->doffs;
    if (!(denom > 0)) {  // at or behind infinity: no finite point
      has_depth[i] = kBehind;
      xyz[3 * i] = xyz[3 * i + 1] = xyz[3 * i + 2] = 0.f;
      continue;
    }
    const double z = camera->baseline * camera->focal_px / denom;
    has_depth[i] = 1;
    xyz[3 * i] = static_cast<float>((v.x - camera->cx) * z / camera->focal_px);
    xyz[3 * i + 1] = static_cast<float>((v.y - camera->cy) * z / camera->focal_px);
    xyz[3 * i + 2] = static_cast<float>(z);
    // Finite but extreme camera values (1e308) overflow here: refuse rather
    // than write inf/nan vertices that viewers choke on.
    if (!std::isfinite(xyz[3 * i]) || !std::isfinite(xyz[3 * i + 1]) || !std::isfinite(xyz[3 * i + 2])) {
      bad(ErrorCode::kInvalidArgument,
          "the camera (focal length " + short_number(camera->focal_px) + " px, baseline " +
              short_number(camera->baseline) + ") puts vertex " + std::to_string(i) + " (" +
              std::to_string(v.x) + ", " + std::to_string(v.y) + ", disparity " +
              short_number(d) + ") at a point beyond float range; check the camera's values and units");
    }
  }
  MeshWriteReport report;
  for (const Triangle& t : mesh.triangles) {
    const std::uint8_t a = has_depth[t[0]], b = has_depth[t[1]], c = has_depth[t[2]];
    if (a == kHasDepth && b == kHasDepth && c == kHasDepth) {
      ++report.faces_written;
    } else if (a == kNoDisparity || b == kNoDisparity || c == kNoDisparity) {
      ++report.faces_without_disparity;
    } else {
      ++report.faces_behind_camera;
    }
  }
  const std::size_t nf = report.faces_written;

  std::string header = "ply\n";
  header += binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
  header += "comment tristereo 2.5D mesh, ";
  header += camera ? "metric camera coordinates (Middlebury model)\n"
                   : "pixel coordinates (x, y, disparity)\n";
  header += "element vertex " + std::to_string(nv) + "\n";
  header += "property float x\nproperty float y\nproperty float z\n";
  header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "element face " + std::to_string(nf) + "\n";
  header += "property list uchar int vertex_indices\nend_header\n";

  OutputFile file(path);
  file.write(header);
  const ImageView<const std::uint8_t>& img = left_gray_or_rgb;
  std::string chunk;
  chunk.reserve(1 << 16);
  auto flush_if_big = [&] {
    if (chunk.size() >= (1 << 16) - 64) {
      file.write(chunk);
      chunk.clear();
    }
  };
  for (std::size_t i = 0; i < nv; ++i) {
    const Vertex& v = mesh.vertices[i];
    const std::uint8_t* px = img.row(v.y) + static_cast<std::ptrdiff_t>(v.x) * img.channels;
    const std::uint8_t rgb[3] = {px[0], px[img.channels == 3 ? 1 : 0],
                                 px[img.channels == 3 ? 2 : 0]};
    if (binary) {
      for (int k = 0; k < 3; ++k) append_float_le(chunk, xyz[3 * i + k]);
      for (int k = 0; k < 3; ++k) chunk += static_cast<char>(rgb[k]);
    } else {
      for (int k = 0; k < 3; ++k) {
        append_float_text(chunk, xyz[3 * i + k]);
        chunk += ' ';
      }
      chunk += std::to_string(rgb[0]) + ' ' + std::to_string(rgb[1]) + ' ' +
               std::to_string(rgb[2]) + '\n';
    }
    flush_if_big();
  }
  for (const Triangle& t : mesh.triangles) {
    if (has_depth[t[0]] != kHasDepth || has_depth[t[1]] != kHasDepth || has_depth[t[2]] != kHasDepth)
      continue;
    if (binary) {
      chunk += static_cast<char>(3);
      for (int k = 0; k < 3; ++k) append_int_le(chunk, t[k]);
    } else {
      chunk += "3 " + std::to_string(t[0]) + ' ' + std::to_string(t[1]) + ' ' +
               std::to_string(t[2]) + '\n';
    }
    flush_if_big();
  }
  file.write(chunk);
  file.commit();
  return report;
}

}  // namespace tristereo
