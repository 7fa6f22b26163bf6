#include "src/profile/latency_stats.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "tristereo/status.hpp"

namespace tristereo {

namespace {

constexpr double kNsPerMs = 1e6;

}  // namespace

double percentile_of_sorted(const std::int64_t* sorted_values, std::size_t n, double q) {
  if (sorted_values == nullptr || n == 0) {
    throw Error(ErrorCode::kInvalidArgument, "percentile of an empty series (n = 0, need n >= 1)");
  }
  // The negated test also rejects NaN.
  if (!(q >= 0.0 && q <= 100.0)) {
    throw Error(ErrorCode::kInvalidArgument,
                "percentile q = " + std::to_string(q) + " outside [0, 100]");
  }
  const double h = static_cast<double>(n - 1) * q / 100.0;
  const std::size_t lo = std::min(static_cast<std::size_t>(std::floor(h)), n - 1);
  const std::size_t hi = std::min(lo + 1, n - 1);
  const double frac = h - static_cast<double>(lo);
  const double a = static_cast<double>(sorted_values[lo]);
  // Interpolate on the difference, not a*(1-f)+b*f: equal neighbours then give
  // exactly their value, and large ns values keep their low digits.
  const double step = static_cast<double>(sorted_values[hi] - sorted_values[lo]);
  return a + frac * step;
}

LatencyStats compute_latency_stats(const std::vector<std::int64_t>& durations_ns) {
  if (durations_ns.empty()) {
    throw Error(ErrorCode::kInvalidArgument,
                "latency statistics of an empty series (0 frames, need at least 1)");
  }
  std::vector<std::int64_t> sorted(durations_ns);
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();

  // Sums of offsets from the minimum: the offsets are small next to absolute
  // timestamps-sized values, so the double sums lose nothing for realistic runs.
  const std::int64_t base = sorted.front();
  double sum = 0;
  for (std::int64_t v : sorted) sum += static_cast<double>(v - base);
  const double mean_offset = sum / static_cast<double>(n);
  double sq = 0;
  for (std::int64_t v : sorted) {
    const double d = static_cast<double>(v - base) - mean_offset;
    sq += d * d;
  }

  LatencyStats s;
  s.count = n;
  s.min_ms = static_cast<double>(sorted.front()) / kNsPerMs;
  s.max_ms = static_cast<double>(sorted.back()) / kNsPerMs;
  s.p50_ms = percentile_of_sorted(sorted.data(), n, 50.0) / kNsPerMs;
  s.p90_ms = percentile_of_sorted(sorted.data(), n, 90.0) / kNsPerMs;
  s.p99_ms = percentile_of_sorted(sorted.data(), n, 99.0) / kNsPerMs;
  s.mean_ms = (static_cast<double>(base) + mean_offset) / kNsPerMs;
  s.std_ms = std::sqrt(sq / static_cast<double>(n)) / kNsPerMs;
  return s;
}

const char* profile_stage_name(ProfileStage stage) {
  switch (stage) {
    case ProfileStage::kRectify:
      return "rectify";
    case ProfileStage::kTritree:
      return "tritree";
    case ProfileStage::kCostAggregation:
      return "cost_aggregation";
    case ProfileStage::kDp:
      return "dp";
    case ProfileStage::kPrior:
      return "prior";
    case ProfileStage::kRightPass:
      return "right_pass";
    case ProfileStage::kFill:
      return "fill";
    case ProfileStage::kInterpolation:
      return "interpolation";
    case ProfileStage::kMeshOutput:
      return "mesh_output";
  }
  return "unknown";
}

FrameLog::FrameLog(std::size_t capacity) {
  if (capacity == 0 || capacity > kMaxFrames) {
    throw Error(ErrorCode::kInvalidArgument, "frame log capacity " + std::to_string(capacity) +
                                                 " outside [1, " + std::to_string(kMaxFrames) +
                                                 "]");
  }
  samples_.resize(capacity);
}

bool FrameLog::push(const FrameSample& sample) noexcept {
  if (size_ == samples_.size()) return false;
  samples_[size_++] = sample;
  return true;
}

std::vector<std::int64_t> FrameLog::stage_column(ProfileStage stage) const {
  const auto k = static_cast<std::size_t>(stage);
  std::vector<std::int64_t> col(size_);
  for (std::size_t i = 0; i < size_; ++i) col[i] = samples_[i].stage_ns[k];
  return col;
}

std::vector<std::int64_t> FrameLog::total_column() const {
  std::vector<std::int64_t> col(size_);
  for (std::size_t i = 0; i < size_; ++i) col[i] = samples_[i].total_ns;
  return col;
}

std::vector<std::int64_t> FrameLog::cpu_column() const {
  std::vector<std::int64_t> col(size_);
  for (std::size_t i = 0; i < size_; ++i) col[i] = samples_[i].cpu_ns;
  return col;
}

}  // namespace tristereo
