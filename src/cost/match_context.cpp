// Cost + aggregation at the samples (docs/model.md section 2).
#include "src/cost/match_context.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <utility>

#include "src/memory/capacity_bytes.hpp"
#include "src/model/exp_table.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

// Slack after every buffer a kernel walks, so SIMD twins may round D up to a
// whole vector without reading past the allocation.
constexpr int kKernelSlack = 64;
// Q32 reciprocal of the weight sum (docs/model.md section 2).
constexpr int kInvShift = 32;
constexpr int kWeightShift = 8;  // w = (ws * wp) >> 8

[[noreturn]] void fail(const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, what);
}

void check_range(const char* name, long long value, long long lo, long long hi) {
  if (value < lo || value > hi)
    fail(std::string(name) + " = " + std::to_string(value) + " is outside " +
         std::to_string(lo) + ".." + std::to_string(hi));
}

void check_window_side(const char* name, int side) {
  check_range(name, side, 1, kMaxWindowSide);
  if (side % 2 == 0) fail(std::string(name) + " = " + std::to_string(side) + " must be odd");
}

void check_view(const char* name, ImageView<const std::uint8_t> v, int max_w, int max_h) {
  if (v.data == nullptr) fail(std::string(name) + " image has null data");
  if (v.channels != 1)
    throw Error(ErrorCode::kUnsupportedFormat, std::string(name) + " image has " +
                                                   std::to_string(v.channels) +
                                                   " channels, the matcher takes 1 (gray)");
  if (v.width < 2 || v.width > max_w || v.height < 2 || v.height > max_h)
    fail(std::string(name) + " image is " + std::to_string(v.width) + "x" +
         std::to_string(v.height) + ", allowed 2x2.." + std::to_string(max_w) + "x" +
         std::to_string(max_h));
  if (v.stride_bytes < v.width)
    fail(std::string(name) + " image stride " + std::to_string(v.stride_bytes) +
         " bytes is below its width " + std::to_string(v.width));
}

}  // namespace

void validate_match_params(const StereoParams& p) {
  check_range("num_disp", p.num_disp, 1, kMaxNumDisp);
  if (std::abs(static_cast<long long>(p.d_min)) + p.num_disp > kMaxDispMagnitude)
    fail("|d_min| + num_disp = " + std::to_string(std::abs(static_cast<long long>(p.d_min)) + p.num_disp) +
         " exceeds " + std::to_string(kMaxDispMagnitude) + " (Q4 disparities must fit int16)");
  check_window_side("cost.window_w", p.cost.window_w);
  check_window_side("cost.window_h", p.cost.window_h);
  check_range("cost.truncation", p.cost.truncation, 1, 255);
  if (p.cost.weights != Weights::kBox && p.cost.weights != Weights::kAdaptive)
    fail("cost.weights = " + std::to_string(static_cast<int>(p.cost.weights)) + " is not a Weights value");
  check_range("cost.asw_gamma_color", p.cost.asw_gamma_color, 1, kMaxAswGammaColor);
  check_range("cost.asw_gamma_proximity", p.cost.asw_gamma_proximity, 1, kMaxAswGammaProximity);
  check_range("dp.lambda_q4", p.dp.lambda_q4, 0, kMaxLambdaQ4);
  if (p.dp.gap != GapPolicy::kInvSquare && p.dp.gap != GapPolicy::kInverse &&
      p.dp.gap != GapPolicy::kConstant)
    fail("dp.gap = " + std::to_string(static_cast<int>(p.dp.gap)) + " is not a GapPolicy value");
}

void CostScratch::resize(int num_disp) {
  sum_u16_.assign(static_cast<std::size_t>(num_disp) + kKernelSlack, 0);
  sum_u32_.assign(static_cast<std::size_t>(num_disp) + kKernelSlack, 0);
  constexpr std::size_t kMaxWindowPixels = std::size_t{kMaxWindowSide} * kMaxWindowSide;
  window_right_.assign(kMaxWindowPixels, nullptr);
  window_left_.assign(kMaxWindowPixels, 0);
  window_weight_.assign(kMaxWindowPixels, 0);
}

std::size_t CostScratch::working_memory_bytes() const {
  return capacity_bytes(sum_u16_) + capacity_bytes(sum_u32_) + capacity_bytes(window_right_) +
         capacity_bytes(window_left_) + capacity_bytes(window_weight_);
}

std::size_t MatchContext::working_memory_bytes() const {
  return capacity_bytes(right_rev_) + capacity_bytes(wp_);
}

MatchContext::MatchContext(int max_width, int max_height, const StereoParams& params,
                           const KernelSet& kernels) {
  configure(max_width, max_height, params, kernels);
}

void MatchContext::configure(int max_width, int max_height, const StereoParams& params,
                             const KernelSet& kernels) {
  check_range("max_width", max_width, 2, kMaxImageSide);
  check_range("max_height", max_height, 2, kMaxImageSide);
  validate_match_params(params);
  if (!kernels.accumulate_abs_diff_u16 || !kernels.accumulate_abs_diff_weighted_u32 ||
      !kernels.aggregate_window_box_u16 || !kernels.aggregate_window_weighted_u32 ||
      !kernels.normalize_costs_u16 || !kernels.normalize_costs_u32 || !kernels.dp_step)
    fail(std::string("kernel set '") + (kernels.name ? kernels.name : "?") + "' is incomplete");

  const CostParams& c = params.cost;
  const int rx = c.window_w / 2, ry = c.window_h / 2;
  std::vector<std::uint8_t> wp(static_cast<std::size_t>(rx * rx + ry * ry + 1));
  exp_decay_table_u8(c.asw_gamma_proximity, static_cast<int>(wp.size()), wp.data());
  const int pad = params.num_disp + std::abs(params.d_min);
  const std::size_t stride =
      static_cast<std::size_t>(max_width + 2 * pad + kKernelSlack + 63) / 64 * 64;
  UntouchedVector<std::uint8_t> rev(stride * static_cast<std::size_t>(max_height));

  // Nothing below throws (except bad_alloc above): commit.
  max_width_ = max_width;
  max_height_ = max_height;
  params_ = params;
  kernels_ = &kernels;
  // The u16 lanes hold a box sum of up to w*h differences of at most T_c.
  use_u16_box_ = c.weights == Weights::kBox &&
                 c.window_w * c.window_h * c.truncation <= 65535;
  rev_pad_ = pad;
  rev_stride_ = stride;
  right_rev_ = std::move(rev);
  exp_decay_table_u8(c.asw_gamma_color, 256, ws_);
  wp_ = std::move(wp);
  width_ = height_ = 0;
  left_ = right_ = {};
}

void MatchContext::begin_frame(ImageView<const std::uint8_t> left_gray,
                               ImageView<const std::uint8_t> right_gray) {
  if (!configured()) throw Error(ErrorCode::kNotConfigured, "MatchContext used before configure()");
  check_view("left", left_gray, max_width_, max_height_);
  check_view("right", right_gray, max_width_, max_height_);
  if (left_gray.width != right_gray.width || left_gray.height != right_gray.height)
    throw Error(ErrorCode::kSizeMismatch,
                "left image is " + std::to_string(left_gray.width) + "x" +
                    std::to_string(left_gray.height) + " but right is " +
                    std::to_string(right_gray.width) + "x" + std::to_string(right_gray.height));
  left_ = left_gray;
  right_ = right_gray;
  width_ = left_gray.width;
  height_ = left_gray.height;
}

void MatchContext::prepare_right_rows(int y_begin, int y_end) {
  if (width_ == 0) throw Error(ErrorCode::kNotConfigured, "prepare_right_rows before begin_frame()");
  if (y_begin < 0 || y_end > height_ || y_begin > y_end)
    fail("row band [" + std::to_string(y_begin) + ", " + std::to_string(y_end) +
         ") is not inside [0, " + std::to_string(height_) + ")");
  // Reversed row: rev[i] = R(clamp(W - 1 + pad - i, 0, W - 1)), so rev[offset(x) + k]
  // is R(clamp(x - d_min - k)) with offset(x) = pad + W - 1 - x + d_min.
  const int w = width_;
  const int len = w + 2 * rev_pad_;
  for (int y = y_begin; y < y_end; ++y) {
    const std::uint8_t* src = right_.row(y);
    std::uint8_t* dst = right_rev_.data() + static_cast<std::size_t>(y) * rev_stride_;
    std::fill(dst, dst + rev_pad_, src[w - 1]);
    for (int i = 0; i < w; ++i) dst[rev_pad_ + i] = src[w - 1 - i];
    std::fill(dst + rev_pad_ + w, dst + len, src[0]);
  }
}

void MatchContext::aggregate_sample(int x, int y, std::uint16_t* cost_q4,
                                    CostScratch& scratch) const {
  const CostParams& c = params_.cost;
  const int n = params_.num_disp;
  const int rx = c.window_w / 2, ry = c.window_h / 2;
  const int x0 = std::max(0, x - rx), x1 = std::min(width_ - 1, x + rx);
  const int y0 = std::max(0, y - ry), y1 = std::min(height_ - 1, y + ry);
  const auto trunc = static_cast<std::uint8_t>(c.truncation);
  const KernelSet& ks = *kernels_;
  const std::uint8_t** right = scratch.window_right_.data();
  std::uint8_t* left = scratch.window_left_.data();
  std::uint16_t* weight = scratch.window_weight_.data();

  // The clipped window as a list of pixels: the kernel then walks it with the
  // D sums held in registers. Pixel x0 + j of row py reads its right run at
  // rev(py) + rev_offset(x0) - j (the offset falls by one as x grows).
  // Everything the loops read is copied to locals first: the u8 stores into
  // `left` may alias any object, which would reload the members every pixel.
  const int cols = x1 - x0 + 1;
  const std::ptrdiff_t l_stride = left_.stride_bytes;
  const std::uint8_t* l = left_.row(y0) + x0;
  const auto r_stride = static_cast<std::ptrdiff_t>(rev_stride_);
  const std::uint8_t* r = right_rev_row(y0) + rev_offset(x0);
  std::uint64_t sum_w = 0;
  int count = 0;
  if (c.weights == Weights::kBox) {
    for (int py = y0; py <= y1; ++py, l += l_stride, r += r_stride) {
      for (int j = 0; j < cols; ++j) {
        right[count + j] = r - j;
        left[count + j] = l[j];
      }
      count += cols;
    }
    sum_w = static_cast<std::uint64_t>(count);
  } else {
    const int centre = left_.row(y)[x];
    const std::uint8_t* ws = ws_;
    const std::uint8_t* wp = wp_.data();
    for (int py = y0; py <= y1; ++py, l += l_stride, r += r_stride) {
      const std::uint8_t* wp_row = wp + (py - y) * (py - y);
      for (int j = 0; j < cols; ++j) {
        const int dx = x0 + j - x;
        const auto w = static_cast<std::uint16_t>((ws[std::abs(l[j] - centre)] * wp_row[dx * dx]) >>
                                                  kWeightShift);
        if (w == 0) continue;  // adds nothing to S or W
        sum_w += w;
        right[count] = r - j;
        left[count] = l[j];
        weight[count] = w;
        ++count;
      }
    }
  }
  // sum_w >= 1: the centre's weight is 1 (box) or (255 * 255) >> 8 = 254.
  const std::uint64_t inv_q32 = (std::uint64_t{1} << kInvShift) / sum_w;
  if (use_u16_box_) {
    std::uint16_t* acc = scratch.sum_u16_.data();
    ks.aggregate_window_box_u16(right, left, count, trunc, n, acc);
    ks.normalize_costs_u16(acc, inv_q32, n, cost_q4);
  } else {
    // Adaptive weights, or a box too large for u16 sums (weights all 1).
    if (c.weights == Weights::kBox) std::fill(weight, weight + count, std::uint16_t{1});
    std::uint32_t* acc = scratch.sum_u32_.data();
    ks.aggregate_window_weighted_u32(right, left, weight, count, trunc, n, acc);
    ks.normalize_costs_u32(acc, inv_q32, n, cost_q4);
  }
}

}  // namespace tristereo
