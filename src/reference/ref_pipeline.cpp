// The float reference, end to end: the plain transcription of docs/model.md.
#include <numeric>
#include <vector>

#include "src/pipeline/input_check.hpp"
#include "src/reference/ref_match.hpp"
#include "src/reference/ref_tritree.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/reference.hpp"

namespace tristereo {

namespace {
// Model section 0: BT.601 in Q8 with rounding.
ImageU8 gray_of(const ImageU8& in) {
  if (in.channels == 1) return in;
  ImageU8 g(in.width, in.height, 1);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const int r = in.at(x, y, 0), gr = in.at(x, y, 1), b = in.at(x, y, 2);
      g.at(x, y) = static_cast<std::uint8_t>((77 * r + 150 * gr + 29 * b + 128) >> 8);
    }
  return g;
}
}  // namespace

StereoOutput run_reference(const ImageU8& left, const ImageU8& right, const StereoParams& params) {
  check_stereo_inputs(left.view(), right.view(), kMaxImageSide, kMaxImageSide);
  validate_params(params);
  const ImageU8 lg = gray_of(left);
  const ImageU8 rg = gray_of(right);

  StereoOutput out;
  out.mesh = reference::build_tritree(lg, params.tritree);
  const Mesh& mesh = out.mesh;
  out.vertex_disp_q4.assign(mesh.vertices.size(), kInvalidDispQ4);
  if (params.dense) {
    out.disp_q4 = ImageS16(lg.width, lg.height, 1, kInvalidDispQ4);
    std::vector<int> xs(static_cast<std::size_t>(lg.width));
    std::iota(xs.begin(), xs.end(), 0);
    for (int y = 0; y < lg.height; ++y) {
      const std::vector<std::int16_t> row = reference::match_row(lg, rg, y, xs, params);
      for (int x = 0; x < lg.width; ++x) out.disp_q4.at(x, y) = row[static_cast<std::size_t>(x)];
    }
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      out.vertex_disp_q4[i] = out.disp_q4.at(mesh.vertices[i].x, mesh.vertices[i].y);
  } else {
    for (int y = 0; y < lg.height; ++y) {
      std::vector<int> xs;
      for (int i = mesh.row_start[static_cast<std::size_t>(y)]; i < mesh.row_start[static_cast<std::size_t>(y) + 1]; ++i)
        xs.push_back(mesh.vertices[static_cast<std::size_t>(i)].x);
      if (xs.empty()) continue;
      const std::vector<std::int16_t> row = reference::match_row(lg, rg, y, xs, params);
      for (std::size_t k = 0; k < xs.size(); ++k)
        out.vertex_disp_q4[static_cast<std::size_t>(mesh.row_start[static_cast<std::size_t>(y)]) + k] = row[k];
    }
    out.disp_q4 = reference::interpolate(mesh, out.vertex_disp_q4);
  }
  return out;
}

}  // namespace tristereo
