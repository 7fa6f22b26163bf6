// A frame trace: where each worker's time goes, span by span.
//
//   FrameTrace trace;
//   trace.reserve(pipeline.worker_count(), 1 << 16);   // allocates, once
//   pipeline.set_trace(&trace);
//   pipeline.process(left, right);                      // records, no allocation
//   write_chrome_trace(trace, "frame.json");            // Perfetto, chrome://tracing
//
// Tracks: kPipelineTrack holds the frames and their stages (recorded by the
// thread that calls process()); track w >= 0 holds worker w's spans: each
// ThreadPool run it took part in and, inside them, the work items it took
// (path tiles, bands decided, rows of costs, rows of interpolation tiles).
// Spans go into storage reserved beforehand; a span that finds its track full
// is dropped and counted (dropped()), never allocated. A pipeline without a
// trace, or with a disabled one, records nothing.
#pragma once

#include "tristereo/export.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tristereo {

enum class TraceKind : std::uint8_t {
  // Pipeline track.
  kFrame = 0,       // a = frame number, b = the workers the path tiles were cut for
  kTritree,
  kCosts,           // the right image's rows and the costs at the samples
  kPaths,           // both path passes (at once): a = tiles per band, b = the forward
                    // pass's lead + 256 x the backward one's, c = rows per band
  kRowDp,           // the paper's model: costs and DP row by row
  kRightPass,       // left-right check by the mirrored pass
  kFill,
  kInterpolation,
  // Worker tracks.
  kRun,             // one ThreadPool::run on this worker; a = the frame's run number
  kPathTile,        // a = pass (0 forward, 1 backward), b = band in the pass's order, c = tile
  kDecideBand,      // a = band of image rows (by the pass that came second)
  kCostRows,        // a = first row, b = end row
  kInterpolationTiles,  // a = first row of tiles, b = end
  kTritreeRows,     // a = phase (0 the split criterion, 1 numbering and emission, 2 the carry
                    // across tile borders, 3 counting the vertices), b = row of tiles
  kFillChunk,       // a fill round over items a .. b - 1 (mesh triangles, or a grid's invalid
                    // samples), handed out in chunks of c
  kRectify,         // pipeline track: both raw frames remapped (after the other kinds, so
                    // that their numbers stay those of older traces)
  kStretchedLeaves,  // the tritree's stretched leaves a .. b - 1 interpolated by their planes
  kVertexSamples,    // dense frames: the map's values at the mesh's vertices a .. b - 1
  kLeftRightRows,    // the mirrored pass's left-right check: image rows a .. b - 1; c = 0 the
                     // images mirrored, 1 the samples checked
  kSampleStates,     // samples a .. b - 1: confidence and state settled after the fill
  kPrior,            // pipeline track: the support prior (docs/model.md section 6b)
  kPriorSegments,    // the prior's segments a .. b - 1 (roots) fitted; c = the level's threshold
  kPriorSamples,     // the prior's covered samples a .. b - 1 (in list order) decided again
  kPriorSetup,       // the prior's samples a .. b - 1: c = 0 intensity and support; c = 1 (from
                     // 4 workers) those to decide again counted, then listed
  kPriorJoins,       // the prior's chunks a .. b - 1 of triangles (the last: the frame's border)
                     // whose mesh edges were joined; c = the level's threshold
  kPriorRoots,       // the prior's samples a .. b - 1 pointed at their segment's root (from 4
                     // workers: counted per segment, then a second item placed by segment);
                     // c = threshold
  kEdgeTriangles,    // interpolation: triangles a .. b - 1 checked for an invalid vertex and
                     // for a depth edge (docs/model.md section 4), those written again
  kCount
};

// Its name in the trace file ("frame", "tritree", "path tile", ...).
TRISTEREO_API const char* to_string(TraceKind kind);

struct TraceSpan {
  std::int64_t begin_ns = 0;  // monotonic clock (CLOCK_MONOTONIC)
  std::int64_t end_ns = 0;
  TraceKind kind = TraceKind::kFrame;
  std::int32_t a = 0, b = 0, c = 0;  // what the kind says
};

class TRISTEREO_API FrameTrace {
 public:
  static constexpr int kPipelineTrack = -1;

  // Room for spans_per_track spans on the pipeline track and on each of
  // `workers` worker tracks; clears. Allocates, and writes every page of the
  // storage (no page faults while recording): call it before the frames.
  void reserve(int workers, std::size_t spans_per_track);
  // Forgets every span (keeps the storage).
  void clear();
  // Disabled, record() does nothing (a trace starts enabled).
  void set_enabled(bool on) { enabled_ = on; }
  bool enabled() const { return enabled_; }

  // Called by the pipeline: the span on `track` (kPipelineTrack or a worker
  // below workers()); a track is written by one thread only.
  // Inline: the thread pool records its runs without linking the library.
  void record(int track, TraceKind kind, std::int64_t begin_ns, std::int64_t end_ns, std::int32_t a = 0,
              std::int32_t b = 0, std::int32_t c = 0) noexcept {
    if (!enabled_) return;
    const bool pipe = track == kPipelineTrack;
    if (!pipe && (track < 0 || track >= workers())) return;
    std::vector<TraceSpan>& t = pipe ? pipeline_ : workers_[static_cast<std::size_t>(track)];
    if (t.size() == t.capacity()) {  // full: push_back would allocate
      ++dropped_[pipe ? workers_.size() : static_cast<std::size_t>(track)];
      return;
    }
    t.push_back(TraceSpan{begin_ns, end_ns, kind, a, b, c});
  }

  int workers() const { return static_cast<int>(workers_.size()); }
  const std::vector<TraceSpan>& track(int t) const { return t == kPipelineTrack ? pipeline_ : workers_[static_cast<std::size_t>(t)]; }
  // Spans that found their track full.
  std::size_t dropped() const;

 private:
  bool enabled_ = true;
  std::vector<TraceSpan> pipeline_;
  std::vector<std::vector<TraceSpan>> workers_;
  std::vector<std::size_t> dropped_;  // per track, the pipeline's last
};

// The trace as Chrome trace-event JSON (complete "X" events in microseconds
// from the first span, one thread per track, named), which Perfetto and
// chrome://tracing open. Throws Error when the file cannot be written.
TRISTEREO_API void write_chrome_trace(const FrameTrace& trace, const std::string& path);

}  // namespace tristereo
