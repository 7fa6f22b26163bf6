// FrameTrace's storage and its Chrome trace-event JSON (include/tristereo/trace.hpp).
#include "tristereo/trace.hpp"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <limits>

#include "src/io/file_util.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

const char* to_string(TraceKind kind) {
  switch (kind) {
    case TraceKind::kFrame: return "frame";
    case TraceKind::kTritree: return "tritree";
    case TraceKind::kCosts: return "costs";
    case TraceKind::kPaths: return "paths";
    case TraceKind::kRowDp: return "row dp";
    case TraceKind::kRightPass: return "right pass";
    case TraceKind::kRectify: return "rectify";
    case TraceKind::kFill: return "fill";
    case TraceKind::kInterpolation: return "interpolation";
    case TraceKind::kRun: return "run";
    case TraceKind::kPathTile: return "path tile";
    case TraceKind::kDecideBand: return "decide band";
    case TraceKind::kCostRows: return "cost rows";
    case TraceKind::kInterpolationTiles: return "interpolation tiles";
    case TraceKind::kTritreeRows: return "tritree rows";
    case TraceKind::kFillChunk: return "fill items";
    case TraceKind::kStretchedLeaves: return "stretched leaves";
    case TraceKind::kEdgeTriangles: return "edge triangles";
    case TraceKind::kVertexSamples: return "vertex samples";
    case TraceKind::kLeftRightRows: return "left-right rows";
    case TraceKind::kSampleStates: return "sample states";
    case TraceKind::kPrior: return "support prior";
    case TraceKind::kPriorSegments: return "prior segments";
    case TraceKind::kPriorSamples: return "prior samples";
    case TraceKind::kPriorSetup: return "prior set-up";
    case TraceKind::kPriorJoins: return "prior joins";
    case TraceKind::kPriorRoots: return "prior roots";
    case TraceKind::kCount: break;
  }
  return "?";
}

void FrameTrace::reserve(int workers, std::size_t spans_per_track) {
  if (workers < 1 || workers > 1024)
    throw Error(ErrorCode::kInvalidArgument, "frame trace: workers = " + std::to_string(workers) + " (1..1024)");
  // Every page of the storage is written here: untouched, each of its first
  // writes in a frame faulted (every 128 spans, 3-20 us on one VM), which
  // the trace then showed as time between work items.
  pipeline_.clear();
  pipeline_.reserve(spans_per_track);
  pipeline_.resize(spans_per_track);
  pipeline_.clear();
  workers_.assign(static_cast<std::size_t>(workers), {});
  for (auto& t : workers_) {
    t.reserve(spans_per_track);
    t.resize(spans_per_track);
    t.clear();
  }
  dropped_.assign(static_cast<std::size_t>(workers) + 1, 0);
}

void FrameTrace::clear() {
  pipeline_.clear();
  for (auto& t : workers_) t.clear();
  std::fill(dropped_.begin(), dropped_.end(), 0);
}

std::size_t FrameTrace::dropped() const {
  std::size_t n = 0;
  for (std::size_t d : dropped_) n += d;
  return n;
}

namespace {
// Microseconds since t0 with nanosecond digits: Chrome's "ts" and "dur" are
// microseconds, and fractions keep the items' order exact.
std::string us(std::int64_t ns) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%" PRId64 ".%03d", ns / 1000, static_cast<int>(ns % 1000));
  return buf;
}
}  // namespace

void write_chrome_trace(const FrameTrace& trace, const std::string& path) {
  std::int64_t t0 = std::numeric_limits<std::int64_t>::max();
  for (int t = FrameTrace::kPipelineTrack; t < trace.workers(); ++t)
    for (const TraceSpan& s : trace.track(t)) t0 = std::min(t0, s.begin_ns);
  if (t0 == std::numeric_limits<std::int64_t>::max()) t0 = 0;
  std::string out = "{\"displayTimeUnit\":\"ms\",\"otherData\":{\"workers\":" + std::to_string(trace.workers()) +
                    ",\"dropped\":" + std::to_string(trace.dropped()) + "},\"traceEvents\":[\n";
  // Track names: tid 0 the pipeline, tid w + 1 worker w.
  out += "{\"ph\":\"M\",\"pid\":1,\"tid\":0,\"name\":\"thread_name\",\"args\":{\"name\":\"pipeline\"}}";
  for (int w = 0; w < trace.workers(); ++w)
    out += ",\n{\"ph\":\"M\",\"pid\":1,\"tid\":" + std::to_string(w + 1) +
           ",\"name\":\"thread_name\",\"args\":{\"name\":\"worker " + std::to_string(w) + "\"}}";
  for (int t = FrameTrace::kPipelineTrack; t < trace.workers(); ++t) {
    for (const TraceSpan& s : trace.track(t)) {
      out += ",\n{\"ph\":\"X\",\"pid\":1,\"tid\":" + std::to_string(t + 1) + ",\"name\":\"" + to_string(s.kind) +
             "\",\"ts\":" + us(s.begin_ns - t0) + ",\"dur\":" + us(s.end_ns - s.begin_ns) +
             ",\"args\":{\"a\":" + std::to_string(s.a) + ",\"b\":" + std::to_string(s.b) +
             ",\"c\":" + std::to_string(s.c) + "}}";
    }
  }
  out += "\n]}\n";
  io_detail::OutputFile f(path);
  f.write(out);
  f.commit();
}

}  // namespace tristereo
