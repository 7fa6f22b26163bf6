// Matching cost and aggregation at the DP samples (docs/model.md section 2).
//
// MatchContext is configured once for the largest frame and one StereoParams;
// per frame it holds the right image as reversed, padded rows so that the D
// costs of a left pixel read one contiguous ascending run:
//
//   right_rev(y)[offset(x) + k] = R(clamp(x - d_min - k, 0, W - 1), y),  k in [0, D)
//
// The replicated padding (D + |d_min| pixels each side) *is* the model's border
// rule, so the kernels never clamp. Use per frame:
//
//   ctx.begin_frame(left, right);          // validates sizes, records the views
//   ctx.prepare_right_rows(y0, y1);        // any row band, any worker thread
//   ctx.aggregate_sample(x, y, cost_q4, scratch);   // const: safe from many workers
//
// aggregate_sample reads right rows y - h/2 .. y + h/2 (clipped), so every band
// those rows belong to must be prepared first. No heap allocation per frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "src/kernels/kernel_set.hpp"
#include "src/memory/untouched_vector.hpp"
#include "tristereo/image.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

// Largest |d| such that 16 d +- 8 (a sub-pixel Q4 disparity) fits int16 and
// never equals kInvalidDispQ4: hence |d_min| + D <= kMaxDispMagnitude.
constexpr int kMaxDispMagnitude = 2048;
// Ranges of the adaptive-weight decay constants (exp(-t / gamma)), as in
// validate_params (src/model/params.cpp).
constexpr int kMaxAswGammaColor = 1000;
constexpr int kMaxAswGammaProximity = 100000;

// Throws Error(kInvalidArgument) naming the first field of `params` that the
// matching stages (cost, aggregation, DP) cannot take exactly.
void validate_match_params(const StereoParams& params);

// One worker's buffers for aggregate_sample, allocated once: the D sums and
// the window's per-pixel inputs of the fused window kernels (right run,
// left value, weight; up to kMaxWindowSide^2 pixels).
class CostScratch {
 public:
  CostScratch() = default;
  explicit CostScratch(int num_disp) { resize(num_disp); }
  void resize(int num_disp);
  // Bytes of the buffers above (allocated capacities).
  std::size_t working_memory_bytes() const;

 private:
  friend class MatchContext;
  std::vector<const std::uint8_t*> census_right_;  // window pixels x planes
  std::vector<std::uint8_t> census_left_;
  std::vector<std::uint16_t> census_q4_;            // ad_census: the census part
  std::vector<std::uint16_t> sum_u16_;
  std::vector<std::uint32_t> sum_u32_;
  std::vector<const std::uint8_t*> window_right_;
  std::vector<std::uint8_t> window_left_;
  std::vector<std::uint16_t> window_weight_;
};

// One worker's buffers for the census transform of a row band: the window's
// rows widened to u16 with the border replicated, and one row of planes.
class CensusScratch {
 public:
  void resize(int max_width);
  std::size_t working_memory_bytes() const;

 private:
  friend class MatchContext;
  int max_width_ = 0;
  std::vector<std::uint8_t> rows_;     // 9 padded rows
  std::vector<std::uint8_t> planes_;  // 8 rows of descriptor byte planes
};

class MatchContext {
 public:
  MatchContext() = default;
  // Same as configure().
  MatchContext(int max_width, int max_height, const StereoParams& params,
               const KernelSet& kernels);

  // Validates (max sizes 2..kMaxImageSide, validate_match_params), builds the
  // adaptive-weight tables and allocates the reversed right rows. `kernels` is
  // kept by reference (the dispatcher's sets are static).
  // Throws Error; on error the context keeps its previous configuration.
  void configure(int max_width, int max_height, const StereoParams& params,
                 const KernelSet& kernels);

  // Records the frame's gray views (not copied: they must outlive the frame's
  // aggregate_sample calls). Throws Error (nothing modified) unless both are
  // 1-channel, non-null, the same size, 2..max in each side, stride >= width.
  void begin_frame(ImageView<const std::uint8_t> left_gray,
                   ImageView<const std::uint8_t> right_gray);

  // Builds the reversed right rows [y_begin, y_end) of the current frame and,
  // for the census costs, both images' descriptors of those rows (then
  // `census` must be given, sized for max_width()). Bands of different
  // workers may run concurrently (disjoint rows, one scratch each).
  void prepare_right_rows(int y_begin, int y_end, CensusScratch* census = nullptr);

  bool uses_census() const { return census_planes_ > 0; }
  // The census cost of every pixel of row y before aggregation: out + x *
  // stride holds H(x, y, k) = sum over the planes of popcount(CL xor CR), k in
  // [0, D). The box mean over a window is then sums of these rows (what
  // aggregate_sample computes per sample, docs/model.md section 2). The rows
  // y reads must be prepared.
  void census_pixel_costs(int y, std::uint16_t* out, std::size_t stride) const;
  // The same costs as bytes (each is at most 64).
  void census_pixel_costs(int y, std::uint8_t* out, std::size_t stride) const;
  int census_planes() const { return census_planes_; }
  // Census descriptor plane p of left pixel (x, y) of the current frame.
  std::uint8_t left_census(int p, int x, int y) const {
    return left_census_[(static_cast<std::size_t>(p) * max_height_ + y) * census_stride_ + x];
  }

  // cost_q4[k] = Ca_q4(x, y, d_min + k) for k in [0, D): the weighted mean of the
  // truncated absolute differences over the clipped window, in Q4 (0..4080),
  // with the exact Q32-reciprocal rounding of docs/model.md section 2.
  // Preconditions (not checked, hot path): 0 <= x < width(), 0 <= y < height(),
  // the window's right rows prepared, scratch sized for num_disp().
  void aggregate_sample(int x, int y, std::uint16_t* cost_q4, CostScratch& scratch) const;

  int max_width() const { return max_width_; }
  int max_height() const { return max_height_; }
  int width() const { return width_; }    // current frame
  int height() const { return height_; }  // current frame
  int num_disp() const { return params_.num_disp; }
  int d_min() const { return params_.d_min; }
  const StereoParams& params() const { return params_; }
  const KernelSet& kernels() const { return *kernels_; }
  bool configured() const { return kernels_ != nullptr; }
  // True when box sums fit the u16 lanes: window pixels * truncation <= 65535.
  bool uses_u16_box() const { return use_u16_box_; }
  // Bytes of the context's buffers (allocated capacities): the reversed right
  // rows and the weight tables.
  std::size_t working_memory_bytes() const;

  // Start of reversed right row y (for tests and SIMD benchmarks).
  const std::uint8_t* right_rev_row(int y) const {
    return right_rev_.data() + static_cast<std::size_t>(y) * rev_stride_;
  }
  // Index into right_rev_row(y) of the run of left pixel x.
  int rev_offset(int x) const { return rev_pad_ + (width_ - 1 - x) + params_.d_min; }

 private:
  int max_width_ = 0;
  int max_height_ = 0;
  StereoParams params_;
  const KernelSet* kernels_ = nullptr;
  bool use_u16_box_ = false;
  int rev_pad_ = 0;
  std::size_t rev_stride_ = 0;
  // Rows a frame does not reach stay untouched (src/memory/untouched_vector.hpp):
  // prepare_right_rows writes every byte the kernels read before they read it.
  UntouchedVector<std::uint8_t> right_rev_;
  // Census (cost kinds census, ad_census): left descriptors by plane, row and x;
  // right descriptors as reversed padded rows like right_rev_, by plane and row.
  // Untouched until a frame's prepare_right_rows writes them, like right_rev_.
  int census_planes_ = 0;
  std::size_t census_stride_ = 0;
  UntouchedVector<std::uint8_t> left_census_;
  UntouchedVector<std::uint8_t> right_census_rev_;
  void census_rows(ImageView<const std::uint8_t> img, int y, CensusScratch& scratch) const;
  template <class T>
  void census_pixel_costs_into(int y, T* out, std::size_t stride) const;
  void aggregate_census(int x0, int x1, int y0, int y1, std::uint16_t* cost_q4,
                        CostScratch& scratch) const;
  std::uint8_t ws_[256] = {};              // similarity weight by |L(p) - L(c)|
  std::vector<std::uint8_t> wp_;           // proximity weight by dx^2 + dy^2

  int width_ = 0;
  int height_ = 0;
  ImageView<const std::uint8_t> left_;
  ImageView<const std::uint8_t> right_;
};

}  // namespace tristereo
