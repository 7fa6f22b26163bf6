// Reports of a latency profiling run (`tristereo profile`): the per-frame CSV,
// the summary JSON and the human-readable table.
//
// Units are in the field names: *_ms milliseconds, *_mb mebibytes (2^20 bytes).
// docs/profiling.md describes every field.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "src/profile/latency_stats.hpp"
#include "src/profile/rss_trace.hpp"

namespace tristereo {

// What was run: echoed verbatim in the JSON "config" object.
struct ProfileRunConfig {
  std::string source;  // "synthetic", "pair" or "folder"
  int width = 0;       // frame size actually processed
  int height = 0;
  int num_disp = 0;
  int d_min = 0;
  bool dense = false;
  std::string weights;  // "box" | "adaptive"
  int window_w = 0;
  int window_h = 0;
  double psnr_db = 0;
  int max_area_px2 = 0;
  int min_area_px2 = 0;
  int threads = 0;        // workers actually running
  std::string kernels;    // kernel set actually active
  std::vector<int> cpus;  // requested pinning (empty = allowed set)
  bool realtime = false;  // SCHED_FIFO granted
  int realtime_priority = 0;
  std::string gpio;          // GPIO spec ("" = no markers)
  bool mesh_output = false;  // PLY writing timed as a stage
  // The left-right check ran a right-view pass (lr_source mirror): timed as a
  // stage, which the other modes do not have.
  bool right_pass = false;
  // The support prior ran (docs/model.md section 6b): a stage of its own.
  bool prior = false;
  // Raw frames rectified by the pipeline's stage (--rig): timed as a stage.
  bool rectify = false;
  int warmup_frames = 0;
  int frames = 0;  // measured frames
  // Pipeline::working_memory_bytes() of the pipeline, configured for frames of
  // width x height (0 = not known).
  std::int64_t working_memory_bytes = 0;
};

// The machine the run was measured on (from platform/cpu_features.hpp).
struct ProfileMachine {
  std::string cpu_model;
  int online_cpus = 0;
};

// Digests (verify.hpp's digest_hex) of the first and last measured frames'
// outputs, and which input each processed (the index in the source's ring of
// prepared pairs): on the same input they must be equal.
struct ProfileOutputCheck {
  bool has = false;
  std::int64_t first_frame = 0;  // measured frame numbers, from 0
  std::int64_t last_frame = 0;
  std::int64_t first_input = 0;
  std::int64_t last_input = 0;
  std::string first_digest;
  std::string last_digest;
  bool same_input() const { return first_input == last_input; }
  bool identical() const { return first_digest == last_digest; }
};
struct ProfileStageSummary {
  std::string name;  // profile_stage_name() of the stage
  LatencyStats stats;
};

struct ProfileReport {
  ProfileRunConfig config;
  std::vector<ProfileStageSummary> stages;  // in pipeline order
  LatencyStats total;                       // whole frame, wall clock
  LatencyStats cpu;                         // process CPU time per frame (all threads)
  double fps_from_mean = 0;                 // 1000 / total.mean_ms
  double wall_fps = 0;                      // measured frames / wall time of the loop
  double wall_s = 0;                        // wall time of the measured loop
  double peak_rss_mb = 0;                   // peak resident set size of the process
  ProfileMachine machine;
  // Resident memory sampled over the measured loop (when a trace was given):
  // the first sample is taken after warm-up, before the first measured frame.
  bool has_rss = false;
  RssSummary rss;                        // bytes
  std::int64_t rss_every_frames = 0;     // sampling interval
  std::vector<RssSample> rss_samples;    // the whole trace
  // Drift: total latency of the first and of the last drift_window_frames
  // measured frames (min(kDriftWindowFrames, frames / 2); 0 below 2 frames).
  std::size_t drift_window_frames = 0;
  LatencyStats first_window;
  LatencyStats last_window;
  double p50_change_pct = 0;  // 100 * (last p50 - first p50) / first p50
  double p99_change_pct = 0;  // the same for p99
  // The same windows of the process CPU time per frame: on a shared machine the
  // wall clock follows the other jobs, the CPU time only tristereo's work.
  LatencyStats first_window_cpu;
  LatencyStats last_window_cpu;
  // The outputs of the first and the last measured frame (a soak asks that the
  // last frame of a long run equals the first on the same input).
  ProfileOutputCheck outputs;
};

constexpr std::size_t kDriftWindowFrames = 1000;

// Summarises a finished log: the pipeline stages (right_pass only when
// config.right_pass), plus mesh_output when config.mesh_output, the total and the CPU time; fps from the mean and from
// wall_ns (the measured loop's wall time). Pure: queries nothing itself.
// Throws Error(kInvalidArgument) if the log is empty or wall_ns <= 0.
// rss: the resident-memory trace of the loop, or nullptr (no "rss" section).
ProfileReport make_profile_report(const ProfileRunConfig& config, const FrameLog& log,
                                  std::int64_t wall_ns, std::int64_t peak_rss_bytes,
                                  const ProfileMachine& machine, const RssTrace* rss = nullptr,
                                  const ProfileOutputCheck* outputs = nullptr);

// Column names of the per-frame CSV, in order: frame, <stage>_ms...,
// total_ms, cpu_ms (right_pass_ms and mesh_output_ms only when the config has
// them).
std::vector<std::string> frames_csv_columns(const ProfileRunConfig& config);

// One header line then one row per frame; ms printed exactly from integer ns
// (6 decimals), so the file round-trips to the nanosecond.
void write_frames_csv(std::ostream& os, const FrameLog& log, const ProfileRunConfig& config);

// The summary as one JSON object (UTF-8, strings escaped).
void write_profile_json(std::ostream& os, const ProfileReport& report);

// The summary as an aligned text table for a terminal.
void write_profile_table(std::ostream& os, const ProfileReport& report);

// JSON string literal of s, with quotes and escapes.
std::string json_quote(const std::string& s);

}  // namespace tristereo
