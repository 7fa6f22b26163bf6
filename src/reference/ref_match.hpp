// Float reference of the matching stages (docs/model.md sections 2-4): a plain
// transcription with no KernelSet, no SIMD, no incremental tricks, single
// thread, allocating freely. The integer path (src/cost, src/dp, src/interp)
// must equal it bit for bit. Where the model's definition *is* an integer rule
// (the Q32 normalisation, the weight tables), it is written with integers here
// too; elsewhere doubles are used on quantities they represent exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"

namespace tristereo {
namespace reference {

// Ca_q4(xs[i], y, d_min + k) as result[i][k], straight from the definition:
// per window pixel the clamped-border truncated difference and its weight.
// left_gray/right_gray: 1 channel, same size. Throws Error on bad input.
std::vector<std::vector<int>> aggregated_costs(const ImageU8& left_gray,
                                               const ImageU8& right_gray, int y,
                                               const std::vector<int>& xs,
                                               const StereoParams& params);

// Census descriptor of (x, y): bit b is 1 when the b-th neighbour of the
// census window (raster order, centre skipped, coordinates clamped) is below
// the centre.
std::uint64_t census_descriptor(const ImageU8& img, int x, int y, const CostParams& cost);

// Samples and their neighbours (docs/model.md section 3b): the mesh vertices
// with the mesh's edges, or (mesh == nullptr) every pixel of width x height
// with its 8 neighbours. Samples are numbered in raster order.
struct Samples {
  const Mesh* mesh = nullptr;
  int width = 0, height = 0;
  std::vector<Vertex> points;
  std::vector<std::vector<int>> neighbours;
};
Samples make_samples(const Mesh* mesh, int width, int height);

// Path aggregation, winner, sub-pixel and uniqueness at every sample (Q4,
// kInvalidDispQ4 where uniqueness rejects). *uniqueness_rejected counts those.
// confidence (optional): every sample's measured confidence from its summed
// costs (docs/model.md section 7), rejected or not.
std::vector<std::int16_t> match_paths(const ImageU8& left_gray, const ImageU8& right_gray,
                                      const Samples& samples, const StereoParams& params,
                                      int* uniqueness_rejected, int* lr_rejected,
                                      std::vector<std::uint8_t>* confidence = nullptr,
                                      std::vector<std::vector<std::int64_t>>* summed = nullptr);

// Support prior (docs/model.md section 6b) on the matcher's disparities and
// confidences, from the summed path costs `summed` (match_paths). Sets the
// validity's prior_* counts.
void support_prior(const ImageU8& left_gray, const Samples& samples, const StereoParams& params,
                   const std::vector<std::vector<std::int64_t>>& summed, std::vector<std::int16_t>& disp_q4,
                   std::vector<std::uint8_t>& confidence, SampleValidity* validity);

// Background fill (docs/model.md section 6); returns the number of samples
// filled. confidence (optional): a filled sample's confidence from its round
// (section 7); the others' untouched.
int fill_background(const Samples& samples, std::vector<std::int16_t>& disp_q4,
                    std::vector<std::uint8_t>* confidence = nullptr);

// P(g) = round(lambda * tau(g)) with halves up, via exact rational arithmetic.
std::int64_t gap_penalty(const DpParams& dp, int gap);

// One DP step by brute force, O(D^2): g(k) = min_j prev[j] + penalty |k - j|,
// ptr[k] the smallest minimising j, out[k] = cost[k] + g(k) - min g.
void dp_step_brute_force(const std::vector<std::int64_t>& cost,
                         const std::vector<std::int64_t>& prev, std::int64_t penalty,
                         std::vector<std::int64_t>& out, std::vector<int>& ptr);

// Exact minimiser of E = sum cost[i][k_i] + sum_{i>0} penalty[i] |k_i - k_{i-1}|
// (penalty[0] unused) with the model's ties: smallest k_n, then smallest
// back-pointers. Returns k_i per sample.
std::vector<int> dp_solve(const std::vector<std::vector<std::int64_t>>& cost,
                          const std::vector<std::int64_t>& penalty);

// Sub-pixel offset in Q4 from Ca at k-1, k, k+1 (0 when the parabola opens down).
int subpixel_offset_q4(int cm, int c0, int cp);
// The equiangular fit's offset (docs/model.md section 3), from the definition in double.
int equiangular_offset_q4(int cm, int c0, int cp);
// The offset of params.dp.subpixel_fit.
int subpixel_offset_q4(const DpParams& dp, int cm, int c0, int cp);

// Q4 disparities of the samples xs (strictly increasing, in [0, W)) of row y.
std::vector<std::int16_t> match_row(const ImageU8& left_gray, const ImageU8& right_gray, int y,
                                    const std::vector<int>& xs, const StereoParams& params);

// Dense Q4 map: every pixel from the plane of the one triangle that owns it
// (ownership by direct edge-function tests). Throws Error when a pixel is owned
// by no triangle or by several (the mesh is not a conforming cover).
ImageS16 interpolate(const Mesh& mesh, const std::vector<std::int16_t>& vertex_disp_q4);

// Pixel state and confidence maps (docs/model.md section 7): 0 for the pixels
// of a triangle with an invalid vertex; else each pixel the smallest of the
// values of its owning triangle's vertices whose weight in the plane at the
// pixel is not zero (all three inside, an edge's two ends on that edge, the
// vertex alone at a vertex).
void interpolate_states(const Mesh& mesh, const std::vector<std::uint8_t>& vertex_state,
                        const std::vector<std::uint8_t>& vertex_confidence, ImageU8& state,
                        ImageU8& confidence);

// Section 4's depth edges, after the two above: every triangle with three
// valid vertices whose disparities spread over more than spread_q4 (> 0)
// writes each pixel it owns again, a vertex's own pixel from that vertex and
// any other from the vertex nearest in `gray`, ties to the smaller disparity,
// then the smaller confidence: its disparity, and when `state` is not null
// its state and confidence too (vertex_state and vertex_confidence are read
// only then).
void interpolate_depth_edges(const Mesh& mesh, const std::vector<std::int16_t>& vertex_disp_q4,
                             const ImageU8& gray, int spread_q4, ImageS16& disp_q4,
                             const std::vector<std::uint8_t>* vertex_state = nullptr,
                             const std::vector<std::uint8_t>* vertex_confidence = nullptr,
                             ImageU8* state = nullptr, ImageU8* confidence = nullptr);

}  // namespace reference
}  // namespace tristereo
