// The production (integer) pipeline: configure once, then process frames.
//
//   Pipeline p;
//   p.configure(config);                 // allocates every buffer, starts workers
//   const StereoOutput& out = p.process(left, right);   // no heap allocation
//
// process() accepts gray (1 channel) or RGB (3 channel) 8-bit views of equal
// size, no larger than the configured maximum, any stride. The returned
// reference stays valid until the next process()/configure() call.
#pragma once

#include "tristereo/export.hpp"

#include <cstdint>
#include <memory>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"
#include "tristereo/rectify.hpp"
#include "tristereo/trace.hpp"

namespace tristereo {

struct PipelineConfig {
  int max_width = 640;
  int max_height = 480;
  StereoParams params;
  KernelChoice kernels = KernelChoice::kAuto;
  int threads = 0;           // worker count; 0 = one per CPU in the allowed set (default)
  std::vector<int> cpus;     // CPUs to pin workers to (empty = allowed set, in order)
  bool pin_threads = true;   // pin worker i to cpus[i % cpus.size()]
  // Cut the path passes into work items as for this many workers (0 = threads).
  // Only for traces that the scaling model replays (docs/threads.md): the
  // output is the same, a one-worker frame cut for many is a little slower.
  int schedule_workers = 0;
  // Raw cameras in (include/tristereo/rectify.hpp): when set, process() takes
  // the raw frames of the maps' raw size and rectifies them first (a stage of
  // its own: FrameTimings::rectify_ns), into buffers allocated here. The
  // maps' rectified size must fit max_width x max_height. Shared, not copied:
  // the same maps can serve several pipelines.
  std::shared_ptr<const RectifyMaps> rectify;
};

// Wall-clock nanoseconds of one frame's stages (filled by every process()).
// tritree .. interpolation are the left (reference) view's; the right view's
// pass of the left-right check is right_pass_ns in one piece.
struct FrameTimings {
  std::int64_t rectify_ns = 0;       // raw frames only: both views remapped (in total_ns too)
  std::int64_t tritree_ns = 0;
  std::int64_t cost_aggregation_ns = 0;
  std::int64_t dp_ns = 0;
  std::int64_t prior_ns = 0;         // the support prior (0 when it is off)
  std::int64_t interpolation_ns = 0;
  std::int64_t right_pass_ns = 0;    // left-right check: the whole right-view pass
  std::int64_t fill_ns = 0;          // validity checks and the fill of invalid samples
  std::int64_t total_ns = 0;
};

// Stage boundaries, reported to a StageListener from the thread that calls
// process() (e.g. to drive GPIO lines for an oscilloscope). Cost aggregation
// and DP interleave row by row, so they form one interval, kMatching.
enum class PipelineStage { kTritree = 0, kMatching = 1, kInterpolation = 2 };

class TRISTEREO_API StageListener {
 public:
  virtual ~StageListener() = default;
  // Must be cheap and must not throw or allocate: it runs inside the frame.
  virtual void on_stage(PipelineStage stage, bool begin) noexcept = 0;
};

class TRISTEREO_API Pipeline {
 public:
  Pipeline();
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Validates and allocates. Throws Error; on error the pipeline is unconfigured.
  void configure(const PipelineConfig& config);
  bool configured() const;
  const PipelineConfig& config() const;

  // Throws Error on bad input (sizes, channels, null data, stride; with
  // config.rectify, frames not of the maps' raw size).
  const StereoOutput& process(ImageView<const std::uint8_t> left,
                              ImageView<const std::uint8_t> right);

  const FrameTimings& last_timings() const;

  // nullptr (the default) = no listener. Not owned; must outlive its use.
  void set_stage_listener(StageListener* listener);
  // Records each frame's stages and every worker's runs and work items into
  // `trace` (reserved beforehand for worker_count() workers; spans beyond its
  // room are dropped and counted). nullptr (the default) = no trace. Not
  // owned; must outlive its use. No allocation per frame either way.
  void set_trace(FrameTrace* trace);
  KernelChoice active_kernels() const;
  int worker_count() const;

  // Working memory in bytes: the capacities of every buffer configure()
  // allocated for the configured maximum size, D and worker count (tritree,
  // matching tables, per-worker DP rows, output mesh and maps, gray copies);
  // not the thread stacks, the code or the caller's images. 0 when
  // unconfigured. Divided by max_width * max_height it is the working memory
  // per configured pixel of docs/performance.md and `tristereo info`.
  // configure() allocates without touching the pages (src/memory/untouched_vector.hpp):
  // a frame smaller than the maximum never faults in the rest.
  std::size_t working_memory_bytes() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace tristereo
