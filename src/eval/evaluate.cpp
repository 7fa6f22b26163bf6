// Bad-pixel statistics: Middlebury's bad > t px and KITTI's D1.
#include "tristereo/eval.hpp"

#include <cmath>
#include <string>

#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

template <typename T>
void check_plane(const ImageView<T>& v, const char* what) {
  if (v.data == nullptr || v.width < 1 || v.height < 1) {
    throw Error(ErrorCode::kInvalidArgument,
                std::string(what) + ": empty image (" + std::to_string(v.width) + " x " +
                    std::to_string(v.height) + ")");
  }
  if (v.channels != 1) {
    throw Error(ErrorCode::kUnsupportedFormat, std::string(what) + ": " +
                                                   std::to_string(v.channels) +
                                                   " channels, expected 1");
  }
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(v.width) * sizeof(T);
  if (v.stride_bytes < row) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + ": stride_bytes " +
                                                 std::to_string(v.stride_bytes) +
                                                 " is shorter than a row (" +
                                                 std::to_string(row) + ")");
  }
}

template <typename A, typename B>
void check_same_size(const ImageView<A>& a, const ImageView<B>& b, const char* what) {
  if (a.width != b.width || a.height != b.height) {
    throw Error(ErrorCode::kSizeMismatch, std::string(what) + " is " + std::to_string(b.width) +
                                              " x " + std::to_string(b.height) + ", expected " +
                                              std::to_string(a.width) + " x " +
                                              std::to_string(a.height));
  }
}

bool known_gt(float g) { return std::isfinite(g) && g != 0.f; }

// Accumulates one evaluated pixel; `d` non-finite = no disparity.
struct Accumulator {
  std::int64_t evaluated = 0, invalid = 0, bad05 = 0, bad1 = 0, bad2 = 0, bad3 = 0, d1 = 0,
               valid = 0;
  double sq = 0, abs_sum = 0;

  void add(double d, double gt) {
    ++evaluated;
    if (!std::isfinite(d)) {
      ++invalid;
      ++bad05;
      ++bad1;
      ++bad2;
      ++bad3;
      ++d1;
      return;
    }
    const double e = std::fabs(d - gt);
    bad05 += e > 0.5;
    bad1 += e > 1.0;
    bad2 += e > 2.0;
    bad3 += e > 3.0;
    // KITTI's devkit: outlier when the error exceeds both 3 px and 5 % of gt.
    d1 += e > 3.0 && e > 0.05 * std::fabs(gt);
    ++valid;
    sq += e * e;
    abs_sum += e;
  }
  BadPixelStats stats() const {
    BadPixelStats s;
    s.evaluated = evaluated;
    s.invalid = invalid;
    if (evaluated > 0) {
      s.bad_0_5 = 100.0 * static_cast<double>(bad05) / static_cast<double>(evaluated);
      s.bad_1 = 100.0 * static_cast<double>(bad1) / static_cast<double>(evaluated);
      s.bad_2 = 100.0 * static_cast<double>(bad2) / static_cast<double>(evaluated);
      s.bad_3 = 100.0 * static_cast<double>(bad3) / static_cast<double>(evaluated);
      s.d1 = 100.0 * static_cast<double>(d1) / static_cast<double>(evaluated);
    }
    if (valid > 0) {
      s.rms = std::sqrt(sq / static_cast<double>(valid));
      s.epe = abs_sum / static_cast<double>(valid);
    }
    return s;
  }
};

}  // namespace

BadPixelStats evaluate_disparity(ImageView<const float> disp, ImageView<const float> gt,
                                 ImageView<const std::uint8_t> mask) {
  check_plane(gt, "evaluate_disparity ground truth");
  check_plane(disp, "evaluate_disparity disparity");
  check_same_size(gt, disp, "evaluate_disparity disparity");
  const bool use_mask = mask.data != nullptr;
  if (use_mask) {
    check_plane(mask, "evaluate_disparity mask");
    check_same_size(gt, mask, "evaluate_disparity mask");
  }
  Accumulator acc;
  for (int y = 0; y < gt.height; ++y) {
    const float* g = gt.row(y);
    const float* d = disp.row(y);
    const std::uint8_t* m = use_mask ? mask.row(y) : nullptr;
    for (int x = 0; x < gt.width; ++x) {
      if (!known_gt(g[x]) || (m && m[x] != 255)) continue;
      acc.add(d[x], g[x]);
    }
  }
  return acc.stats();
}

BadPixelStats evaluate_at_points(ImageView<const float> gt, const std::vector<Vertex>& pts,
                                 const std::vector<std::int16_t>& disp_q4,
                                 ImageView<const std::uint8_t> mask) {
  check_plane(gt, "evaluate_at_points ground truth");
  if (pts.size() != disp_q4.size()) {
    throw Error(ErrorCode::kSizeMismatch, "evaluate_at_points: " + std::to_string(disp_q4.size()) +
                                              " disparities for " + std::to_string(pts.size()) +
                                              " points");
  }
  const bool use_mask = mask.data != nullptr;
  if (use_mask) {
    check_plane(mask, "evaluate_at_points mask");
    check_same_size(gt, mask, "evaluate_at_points mask");
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (pts[i].x < 0 || pts[i].x >= gt.width || pts[i].y < 0 || pts[i].y >= gt.height) {
      throw Error(ErrorCode::kInvalidArgument,
                  "evaluate_at_points: point " + std::to_string(i) + " at (" +
                      std::to_string(pts[i].x) + ", " + std::to_string(pts[i].y) +
                      ") lies outside the " + std::to_string(gt.width) + " x " +
                      std::to_string(gt.height) + " ground truth");
    }
  }
  Accumulator acc;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const float g = gt.row(pts[i].y)[pts[i].x];
    if (!known_gt(g) || (use_mask && mask.row(pts[i].y)[pts[i].x] != 255)) continue;
    const double d = disp_q4[i] == kInvalidDispQ4
                         ? HUGE_VAL
                         : static_cast<double>(disp_q4[i]) / kDispOne;
    acc.add(d, g);
  }
  return acc.stats();
}

}  // namespace tristereo
