// The float reference, end to end: the plain transcription of docs/model.md.
#include <cstdlib>
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

namespace {
ImageU8 mirrored(const ImageU8& g) {
  ImageU8 m(g.width, g.height, 1);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) m.at(x, y) = g.at(g.width - 1 - x, y);
  return m;
}

// Sample disparities of one view (the left image is the reference): the
// configured optimizer, and for the paths uniqueness and the left-right check
// from the summed costs (lr_source = costs).
// confidence (optional): each sample's measured confidence (docs/model.md
// section 7): from the summed costs, or 255 with the row DP.
std::vector<std::int16_t> match_view(const ImageU8& lg, const ImageU8& rg,
                                     const reference::Samples& samples,
                                     const StereoParams& params, int* uniqueness_rejected,
                                     int* lr_rejected, std::vector<std::uint8_t>* confidence = nullptr,
                                     std::vector<std::vector<std::int64_t>>* summed = nullptr) {
  *uniqueness_rejected = 0;
  *lr_rejected = 0;
  if (params.optimizer == Optimizer::kPaths)
    return reference::match_paths(lg, rg, samples, params, uniqueness_rejected, lr_rejected, confidence, summed);
  if (confidence != nullptr) confidence->assign(samples.points.size(), 255);
  std::vector<std::int16_t> disp;
  for (int y = 0; y < lg.height; ++y) {
    std::vector<int> xs;
    for (const Vertex& v : samples.points)
      if (v.y == y) xs.push_back(v.x);
    if (xs.empty()) continue;
    const std::vector<std::int16_t> row = reference::match_row(lg, rg, y, xs, params);
    disp.insert(disp.end(), row.begin(), row.end());
  }
  return disp;
}
}  // namespace

StereoOutput run_reference(const ImageU8& left, const ImageU8& right, const StereoParams& params) {
  check_stereo_inputs(left.view(), right.view(), kMaxImageSide, kMaxImageSide);
  validate_params(params);
  const ImageU8 lg = gray_of(left);
  const ImageU8 rg = gray_of(right);
  const int w = lg.width, h = lg.height;

  StereoOutput out;
  out.mesh = reference::build_tritree(lg, params.tritree);
  const Mesh& mesh = out.mesh;
  const reference::Samples samples = reference::make_samples(params.dense ? nullptr : &mesh, w, h);
  std::vector<std::uint8_t> conf;
  std::vector<std::vector<std::int64_t>> summed;
  const bool prior = support_prior_applies(params);
  std::vector<std::int16_t> disp = match_view(lg, rg, samples, params, &out.validity.uniqueness_rejected,
                                              &out.validity.lr_rejected, &conf, prior ? &summed : nullptr);
  out.validity.samples = static_cast<std::int32_t>(disp.size());
  // Section 6b: the support prior.
  if (prior) reference::support_prior(lg, samples, params, summed, disp, conf, &out.validity);

  // Left-right check by a second pass: the right view is the left view of the mirrored pair.
  if (params.validity.lr_max_diff_q4 >= 0 && params.validity.lr_source == LrSource::kMirroredPass) {
    const ImageU8 ml = mirrored(rg), mr = mirrored(lg);
    Mesh right_mesh;
    if (!params.dense) right_mesh = reference::build_tritree(ml, params.tritree);
    const reference::Samples rs = reference::make_samples(params.dense ? nullptr : &right_mesh, w, h);
    int unused = 0, unused_lr = 0;
    std::vector<std::int16_t> rdisp = match_view(ml, mr, rs, params, &unused, &unused_lr);
    if (params.validity.fill != FillMode::kNone) reference::fill_background(rs, rdisp);
    ImageS16 right_map(w, h, 1, kInvalidDispQ4);
    if (params.dense) {
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) right_map.at(x, y) = rdisp[static_cast<std::size_t>(y * w + x)];
    } else {
      right_map = reference::interpolate(right_mesh, rdisp);
      reference::interpolate_depth_edges(right_mesh, rdisp, ml, params.interp.edge_spread_q4, right_map);
    }
    for (std::size_t i = 0; i < disp.size(); ++i) {
      if (disp[i] == kInvalidDispQ4) continue;
      const Vertex p = samples.points[i];
      const int xr = p.x - static_cast<int>(floor_div(disp[i] + 8, 16));
      bool ok = xr >= 0 && xr < w;
      if (ok) {
        const int r = right_map.at(w - 1 - xr, p.y);
        ok = r != kInvalidDispQ4 && std::abs(disp[i] - r) <= params.validity.lr_max_diff_q4;
      }
      if (!ok) {
        disp[i] = kInvalidDispQ4;
        ++out.validity.lr_rejected;
      }
    }
  }
  if (params.validity.fill != FillMode::kNone)
    out.validity.filled = reference::fill_background(samples, disp, &conf);

  // Section 7: invalid samples have confidence 0; those below the minimum
  // confidence become invalid; the state follows from the confidence.
  std::vector<std::uint8_t> state(disp.size());
  for (std::size_t i = 0; i < disp.size(); ++i) {
    if (disp[i] == kInvalidDispQ4) conf[i] = 0;
    if (conf[i] != 0 && conf[i] < params.validity.min_confidence) {
      disp[i] = kInvalidDispQ4;
      conf[i] = 0;
      ++out.validity.min_confidence_rejected;
    }
    state[i] = static_cast<std::uint8_t>(conf[i] == 0     ? SampleState::kInvalid
                                         : conf[i] < 128 ? SampleState::kFilled
                                                         : SampleState::kMeasured);
  }

  if (params.dense) {
    out.disp_q4 = ImageS16(w, h, 1, kInvalidDispQ4);
    out.pixel_state = ImageU8(w, h, 1, 0);
    out.pixel_confidence = ImageU8(w, h, 1, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const auto i = static_cast<std::size_t>(y * w + x);
        out.disp_q4.at(x, y) = disp[i];
        out.pixel_state.at(x, y) = state[i];
        out.pixel_confidence.at(x, y) = conf[i];
      }
    out.vertex_disp_q4.resize(mesh.vertices.size());
    out.vertex_state.resize(mesh.vertices.size());
    out.vertex_confidence.resize(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const int x = mesh.vertices[i].x, y = mesh.vertices[i].y;
      out.vertex_disp_q4[i] = out.disp_q4.at(x, y);
      out.vertex_state[i] = out.pixel_state.at(x, y);
      out.vertex_confidence[i] = out.pixel_confidence.at(x, y);
    }
  } else {
    out.vertex_disp_q4 = disp;
    out.vertex_state = state;
    out.vertex_confidence = conf;
    out.disp_q4 = reference::interpolate(mesh, out.vertex_disp_q4);
    reference::interpolate_states(mesh, out.vertex_state, out.vertex_confidence, out.pixel_state,
                                  out.pixel_confidence);
    reference::interpolate_depth_edges(mesh, out.vertex_disp_q4, lg, params.interp.edge_spread_q4, out.disp_q4,
                                       &out.vertex_state, &out.vertex_confidence, &out.pixel_state,
                                       &out.pixel_confidence);
  }
  return out;
}

}  // namespace tristereo
