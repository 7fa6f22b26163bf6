// Cost + aggregation at the samples (docs/model.md section 2).
#include "src/cost/match_context.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "src/memory/capacity_bytes.hpp"
#include "src/memory/large_array.hpp"
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

void CensusScratch::resize(int max_width) {
  max_width_ = max_width;
  const std::size_t row = static_cast<std::size_t>(max_width) + 8 + kKernelSlack;
  rows_.assign(9 * row, 0);
  planes_.assign(8 * (static_cast<std::size_t>(max_width) + kKernelSlack), 0);
}

void CostScratch::resize(int num_disp) {
  census_right_.assign(std::size_t{kMaxWindowSide} * kMaxWindowSide * 8, nullptr);
  census_left_.assign(std::size_t{kMaxWindowSide} * kMaxWindowSide * 8, 0);
  census_q4_.assign(static_cast<std::size_t>(num_disp) + kKernelSlack, 0);
  sum_u16_.assign(static_cast<std::size_t>(num_disp) + kKernelSlack, 0);
  sum_u32_.assign(static_cast<std::size_t>(num_disp) + kKernelSlack, 0);
  constexpr std::size_t kMaxWindowPixels = std::size_t{kMaxWindowSide} * kMaxWindowSide;
  window_right_.assign(kMaxWindowPixels, nullptr);
  window_left_.assign(kMaxWindowPixels, 0);
  window_weight_.assign(kMaxWindowPixels, 0);
}

std::size_t CostScratch::working_memory_bytes() const {
  return capacity_bytes(sum_u16_) + capacity_bytes(sum_u32_) + capacity_bytes(window_right_) +
         capacity_bytes(window_left_) + capacity_bytes(window_weight_) + capacity_bytes(census_right_) +
         capacity_bytes(census_left_) + capacity_bytes(census_q4_);
}

std::size_t MatchContext::working_memory_bytes() const {
  return capacity_bytes(right_rev_) + capacity_bytes(wp_) + capacity_bytes(left_census_) +
         capacity_bytes(right_census_rev_);
}

std::size_t CensusScratch::working_memory_bytes() const {
  return capacity_bytes(rows_) + capacity_bytes(planes_);
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
      !kernels.normalize_costs_u16 || !kernels.normalize_costs_u32 || !kernels.dp_step ||
      !kernels.census_row_u8 || !kernels.census_window_u16 || !kernels.census_costs_row_u16 ||
      !kernels.census_costs_row_u8)
    fail(std::string("kernel set '") + (kernels.name ? kernels.name : "?") + "' is incomplete");

  const CostParams& c = params.cost;
  const int rx = c.window_w / 2, ry = c.window_h / 2;
  std::vector<std::uint8_t> wp(static_cast<std::size_t>(rx * rx + ry * ry + 1));
  exp_decay_table_u8(c.asw_gamma_proximity, static_cast<int>(wp.size()), wp.data());
  const int pad = params.num_disp + std::abs(params.d_min);
  const std::size_t stride =
      static_cast<std::size_t>(max_width + 2 * pad + kKernelSlack + 63) / 64 * 64;
  UntouchedVector<std::uint8_t> rev(stride * static_cast<std::size_t>(max_height));
  const int planes = c.kind == CostKind::kAd ? 0 : (c.census_w * c.census_h - 1 + 7) / 8;
  const std::size_t census_stride = static_cast<std::size_t>(max_width + 63) / 64 * 64;
  UntouchedVector<std::uint8_t> left_census(static_cast<std::size_t>(planes) * max_height * census_stride);
  UntouchedVector<std::uint8_t> right_census(static_cast<std::size_t>(planes) * max_height * stride);
  advise_huge_pages(rev.data(), rev.size());
  advise_huge_pages(left_census.data(), left_census.size());
  advise_huge_pages(right_census.data(), right_census.size());

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
  census_planes_ = planes;
  census_stride_ = census_stride;
  left_census_ = std::move(left_census);
  right_census_rev_ = std::move(right_census);
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

// Census of row y of img into scratch.planes_: the window's rows with the
// border replicated (clamped coordinates, docs/model.md section 2).
void MatchContext::census_rows(ImageView<const std::uint8_t> img, int y,
                               CensusScratch& scratch) const {
  const CostParams& c = params_.cost;
  const int rx = c.census_w / 2, ry = c.census_h / 2;
  const int w = width_;
  const std::size_t row_len = static_cast<std::size_t>(scratch.max_width_) + 8 + kKernelSlack;
  const std::uint8_t* rows[9];
  for (int j = 0; j < c.census_h; ++j) {
    const std::uint8_t* src = img.row(std::clamp(y - ry + j, 0, height_ - 1));
    std::uint8_t* dst = scratch.rows_.data() + static_cast<std::size_t>(j) * row_len + 4;
    std::fill(dst - rx, dst, src[0]);
    std::copy(src, src + w, dst);
    std::fill(dst + w, dst + w + rx, src[w - 1]);
    rows[j] = dst;
  }
  std::uint8_t* planes[8];
  const std::size_t plane_len = static_cast<std::size_t>(scratch.max_width_) + kKernelSlack;
  for (int p = 0; p < 8; ++p) planes[p] = scratch.planes_.data() + static_cast<std::size_t>(p) * plane_len;
  kernels_->census_row_u8(rows, c.census_w, c.census_h, w, planes);
}

namespace {
// dst[i] = src[n - 1 - i], eight bytes at a time: a byte swap of each 64-bit
// word (one instruction on x86 and ARM, and the same bytes on either
// endianness). Byte by byte, the right image's row and its three census
// planes took about 0.7 ms of a one-worker KITTI frame.
void reverse_bytes(const std::uint8_t* src, int n, std::uint8_t* dst) {
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    std::uint64_t v;
    std::memcpy(&v, src + n - 8 - i, sizeof v);
    v = __builtin_bswap64(v);
    std::memcpy(dst + i, &v, sizeof v);
  }
  for (; i < n; ++i) dst[i] = src[n - 1 - i];
}
}  // namespace

void MatchContext::prepare_right_rows(int y_begin, int y_end, CensusScratch* census) {
  if (width_ == 0) throw Error(ErrorCode::kNotConfigured, "prepare_right_rows before begin_frame()");
  if (y_begin < 0 || y_end > height_ || y_begin > y_end)
    fail("row band [" + std::to_string(y_begin) + ", " + std::to_string(y_end) +
         ") is not inside [0, " + std::to_string(height_) + ")");
  // Reversed row: rev[i] = R(clamp(W - 1 + pad - i, 0, W - 1)), so rev[offset(x) + k]
  // is R(clamp(x - d_min - k)) with offset(x) = pad + W - 1 - x + d_min.
  const int w = width_;
  const int pad = rev_pad_;
  const auto reverse_padded = [w, pad](const std::uint8_t* src, std::uint8_t* dst) {
    std::fill(dst, dst + pad, src[w - 1]);
    reverse_bytes(src, w, dst + pad);
    std::fill(dst + pad + w, dst + w + 2 * pad, src[0]);
  };
  for (int y = y_begin; y < y_end; ++y)
    reverse_padded(right_.row(y), right_rev_.data() + static_cast<std::size_t>(y) * rev_stride_);
  if (census_planes_ == 0) return;
  if (census == nullptr || census->max_width_ < w)
    fail("prepare_right_rows: the census cost needs a CensusScratch sized for the frame width");
  const std::size_t plane_len = static_cast<std::size_t>(census->max_width_) + kKernelSlack;
  for (int y = y_begin; y < y_end; ++y) {
    census_rows(left_, y, *census);
    for (int p = 0; p < census_planes_; ++p) {
      const std::uint8_t* src = census->planes_.data() + static_cast<std::size_t>(p) * plane_len;
      std::copy(src, src + w,
                left_census_.begin() + static_cast<std::ptrdiff_t>(
                                           (static_cast<std::size_t>(p) * max_height_ + y) * census_stride_));
    }
    census_rows(right_, y, *census);
    for (int p = 0; p < census_planes_; ++p) {
      const std::uint8_t* src = census->planes_.data() + static_cast<std::size_t>(p) * plane_len;
      reverse_padded(src, right_census_rev_.data() + (static_cast<std::size_t>(p) * max_height_ + y) * rev_stride_);
    }
  }
}

void MatchContext::census_pixel_costs(int y, std::uint16_t* out, std::size_t stride) const {
  census_pixel_costs_into(y, out, stride);
}

void MatchContext::census_pixel_costs(int y, std::uint8_t* out, std::size_t stride) const {
  census_pixel_costs_into(y, out, stride);
}

template <class T>
void MatchContext::census_pixel_costs_into(int y, T* out, std::size_t stride) const {
  const std::uint8_t* right[8];
  const std::uint8_t* left[8];
  for (int p = 0; p < census_planes_; ++p) {
    // rev_offset(x) = rev_offset(0) - x: the kernel steps back one per pixel.
    right[p] = right_census_rev_.data() + (static_cast<std::size_t>(p) * max_height_ + y) * rev_stride_ +
               rev_offset(0);
    left[p] = left_census_.data() + (static_cast<std::size_t>(p) * max_height_ + y) * census_stride_;
  }
  if constexpr (sizeof(T) == 1)
    kernels_->census_costs_row_u8(right, left, census_planes_, width_, params_.num_disp, stride, out);
  else
    kernels_->census_costs_row_u16(right, left, census_planes_, width_, params_.num_disp, stride, out);
}

// Mean Hamming distance over the clipped window, in Q4 (0 .. 16 * bits).
void MatchContext::aggregate_census(int x0, int x1, int y0, int y1, std::uint16_t* cost_q4,
                                    CostScratch& scratch) const {
  const int n = params_.num_disp;
  const std::uint8_t** right = scratch.census_right_.data();
  std::uint8_t* left = scratch.census_left_.data();
  int count = 0;
  for (int p = 0; p < census_planes_; ++p)
    for (int py = y0; py <= y1; ++py) {
      const std::uint8_t* rrow = right_census_rev_.data() +
                                  (static_cast<std::size_t>(p) * max_height_ + py) * rev_stride_;
      const std::uint8_t* lrow = left_census_.data() +
                                  (static_cast<std::size_t>(p) * max_height_ + py) * census_stride_;
      for (int px = x0; px <= x1; ++px) {
        right[count] = rrow + rev_offset(px);
        left[count] = lrow[px];
        ++count;
      }
    }
  const auto pixels = static_cast<std::uint64_t>((x1 - x0 + 1) * (y1 - y0 + 1));
  std::uint16_t* acc = scratch.sum_u16_.data();
  kernels_->census_window_u16(right, left, count, n, acc);
  kernels_->normalize_costs_u16(acc, (std::uint64_t{1} << kInvShift) / pixels, n, cost_q4);
}

void MatchContext::aggregate_sample(int x, int y, std::uint16_t* cost_q4,
                                    CostScratch& scratch) const {
  const CostParams& c = params_.cost;
  const int n = params_.num_disp;
  const int rx = c.window_w / 2, ry = c.window_h / 2;
  const int x0 = std::max(0, x - rx), x1 = std::min(width_ - 1, x + rx);
  const int y0 = std::max(0, y - ry), y1 = std::min(height_ - 1, y + ry);
  if (c.kind == CostKind::kCensus) return aggregate_census(x0, x1, y0, y1, cost_q4, scratch);
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
  if (c.kind == CostKind::kAdCensus) {
    // cost = min(4080, census + (ad_weight * ad + 8) >> 4), both in Q4.
    std::uint16_t* census = scratch.census_q4_.data();
    aggregate_census(x0, x1, y0, y1, census, scratch);
    const std::uint32_t wq4 = static_cast<std::uint32_t>(c.ad_weight_q4);
    for (int k = 0; k < n; ++k) {
      const std::uint32_t v = census[k] + ((wq4 * cost_q4[k] + 8) >> 4);
      cost_q4[k] = static_cast<std::uint16_t>(v < std::uint32_t{kMaxCostQ4} ? v : std::uint32_t{kMaxCostQ4});
    }
  }
}

}  // namespace tristereo
