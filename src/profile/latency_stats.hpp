// Per-frame latency records and their summary statistics.
//
// The profiler records one FrameSample per measured frame into a FrameLog whose
// storage is allocated once, before the loop (push() never allocates), and
// summarises the columns only after the run.
//
// Definitions (docs/profiling.md repeats them):
//  - percentile q (0..100): linear interpolation between the closest ranks of
//    the sorted sample, numpy's default ("linear"): h = (n - 1) q / 100,
//    value = s[floor(h)] + (h - floor(h)) (s[floor(h) + 1] - s[floor(h)]).
//    p0 = min, p100 = max, p50 of an even count = mean of the two middle values.
//  - std: population standard deviation (divide by n, numpy's np.std default),
//    because the measured frames are the whole population we report on, and
//    it stays defined (0) for a single frame.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tristereo {

// Summary of one series of durations, in milliseconds.
struct LatencyStats {
  std::size_t count = 0;
  double min_ms = 0;
  double p50_ms = 0;
  double p90_ms = 0;
  double p99_ms = 0;
  double max_ms = 0;
  double mean_ms = 0;
  double std_ms = 0;  // population standard deviation
};

// Percentile q (0..100) of an ascending-sorted series, linear interpolation
// between closest ranks, in the series' own unit. Throws Error(kInvalidArgument)
// if n == 0, sorted_values is null or q is outside [0, 100] (or NaN).
double percentile_of_sorted(const std::int64_t* sorted_values, std::size_t n, double q);

// Stats of durations in nanoseconds (any order; the input is not modified).
// Throws Error(kInvalidArgument) on an empty series.
LatencyStats compute_latency_stats(const std::vector<std::int64_t>& durations_ns);

// The timed stages of one profiled frame, in report order.
enum class ProfileStage : int {
  kTritree = 0,
  kCostAggregation,
  kDp,
  kRightPass,  // the right view's pass of a mirrored left-right check (FrameTimings::right_pass_ns)
  kFill,  // validity checks and the fill of invalid samples (FrameTimings::fill_ns)
  kInterpolation,
  kMeshOutput,  // PLY writing of the mesh, only with --mesh-output
  kRectify,     // raw frames only (--rig): both views remapped (FrameTimings::rectify_ns);
                // first in the reports' pipeline order (profile_stage_order)
  kPrior,       // the support prior, only when it is on (FrameTimings::prior_ns)
};
constexpr int kProfileStageCount = 9;

// "tritree", "cost_aggregation", "dp", "right_pass", "fill", "interpolation",
// "mesh_output", "rectify", "prior".
const char* profile_stage_name(ProfileStage stage);
// The stages in pipeline order, as the reports list them (rectify first).
constexpr ProfileStage kProfileStageOrder[kProfileStageCount] = {
    ProfileStage::kRectify, ProfileStage::kTritree,       ProfileStage::kCostAggregation,
    ProfileStage::kDp,      ProfileStage::kPrior,         ProfileStage::kRightPass,
    ProfileStage::kFill,    ProfileStage::kInterpolation, ProfileStage::kMeshOutput};

// One measured frame. total_ns is the wall time of the whole frame (pipeline
// plus mesh output when enabled); cpu_ns is the process CPU time (all threads)
// spent during the frame.
struct FrameSample {
  std::array<std::int64_t, kProfileStageCount> stage_ns{};
  std::int64_t total_ns = 0;
  std::int64_t cpu_ns = 0;
};

// Fixed-capacity log of frame samples: the only allocation is in the
// constructor, so recording inside a real-time loop never touches the heap.
class FrameLog {
 public:
  // Throws Error(kInvalidArgument) if capacity is 0 or above kMaxFrames.
  explicit FrameLog(std::size_t capacity);

  static constexpr std::size_t kMaxFrames = 10000000;  // 10^7 frames = 560 MB of samples

  // Appends a sample. Returns false (and records nothing) when full, so the
  // caller's loop bound, not this class, decides how many frames are run.
  bool push(const FrameSample& sample) noexcept;

  std::size_t size() const noexcept { return size_; }
  std::size_t capacity() const noexcept { return samples_.size(); }
  const FrameSample& operator[](std::size_t i) const { return samples_[i]; }

  // Columns for compute_latency_stats (allocate; call after the run).
  std::vector<std::int64_t> stage_column(ProfileStage stage) const;
  std::vector<std::int64_t> total_column() const;
  std::vector<std::int64_t> cpu_column() const;

 private:
  std::vector<FrameSample> samples_;
  std::size_t size_ = 0;
};

}  // namespace tristereo
