// The production pipeline: tritree -> cost aggregation + DP per row -> interpolation.
//
// Everything size-dependent is allocated in configure(); process() only writes
// into that storage (tests/no_alloc_test.cpp counts allocations). Rows (cost,
// DP) and triangles (interpolation) are handed to the workers in chunks on
// demand; each pixel/sample is computed by exactly one worker from the same
// inputs, whichever it is, so the output is identical for any thread count.
#include "tristereo/pipeline.hpp"

#include <algorithm>
#include <atomic>
#include <string>

#include "platform/clock.hpp"
#include "platform/cpu_features.hpp"
#include "platform/thread_pool.hpp"
#include "platform/work_chunks.hpp"
#include "src/cost/match_context.hpp"
#include "src/dp/row_matcher.hpp"
#include "src/interp/interpolate_planes.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/memory/capacity_bytes.hpp"
#include "src/memory/untouched_vector.hpp"
#include "src/pipeline/input_check.hpp"
#include "src/tritree/tritree.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

struct Pipeline::Impl {
  PipelineConfig config;
  bool configured = false;
  KernelChoice active = KernelChoice::kScalar;
  const KernelSet* kernels = nullptr;

  Tritree tritree;
  MatchContext match;
  ThreadPool pool;
  struct Worker {
    RowMatcher matcher;
    UntouchedVector<std::int32_t> xs;  // sample x of the row being matched
    std::int64_t cost_ns = 0;
    std::int64_t dp_ns = 0;
  };
  std::vector<Worker> workers;
  WorkChunks rows;       // matching: rows handed out on demand
  WorkChunks triangles;  // interpolation: triangles handed out on demand
  std::vector<std::int32_t> all_xs;  // 0 .. max_width-1 (dense mode samples)
  ImageU8 left_gray, right_gray;     // used when the input is RGB (reserved, sized per frame)
  StereoOutput out;
  FrameTimings timings;
  StageListener* listener = nullptr;

  void mark(PipelineStage s, bool begin) const {
    if (listener) listener->on_stage(s, begin);
  }
};

Pipeline::Pipeline() : impl_(new Impl) {}
Pipeline::~Pipeline() = default;

bool Pipeline::configured() const { return impl_->configured; }
const PipelineConfig& Pipeline::config() const { return impl_->config; }
const FrameTimings& Pipeline::last_timings() const { return impl_->timings; }
void Pipeline::set_stage_listener(StageListener* listener) { impl_->listener = listener; }
KernelChoice Pipeline::active_kernels() const { return impl_->active; }
int Pipeline::worker_count() const { return impl_->configured ? impl_->pool.size() : 0; }

std::size_t Pipeline::working_memory_bytes() const {
  const Impl& m = *impl_;
  if (!m.configured) return 0;
  std::size_t bytes = m.tritree.working_memory_bytes() + m.match.working_memory_bytes() +
                      capacity_bytes(m.workers) + capacity_bytes(m.all_xs) +
                      capacity_bytes(m.left_gray.pixels) + capacity_bytes(m.right_gray.pixels) +
                      capacity_bytes(m.out.mesh.vertices) + capacity_bytes(m.out.mesh.triangles) +
                      capacity_bytes(m.out.mesh.row_start) + capacity_bytes(m.out.vertex_disp_q4) +
                      capacity_bytes(m.out.disp_q4.pixels);
  for (const Impl::Worker& w : m.workers) bytes += w.matcher.working_memory_bytes() + capacity_bytes(w.xs);
  return bytes;
}

void Pipeline::configure(const PipelineConfig& config) {
  Impl& m = *impl_;
  m.configured = false;
  m.pool.stop();
  if (config.max_width < 2 || config.max_width > kMaxImageSide || config.max_height < 2 ||
      config.max_height > kMaxImageSide)
    throw Error(ErrorCode::kInvalidArgument,
                "configured maximum size " + std::to_string(config.max_width) + "x" +
                    std::to_string(config.max_height) + " is outside 2.." +
                    std::to_string(kMaxImageSide) + " per side");
  validate_params(config.params);
  if (config.threads < 0 || config.threads > 256)
    throw Error(ErrorCode::kInvalidArgument,
                "threads = " + std::to_string(config.threads) + " is outside 0..256 (0 = one per CPU)");
  const KernelChoice active = resolve_kernel_choice(config.kernels);
  const KernelSet& kernels = kernel_set_for(active);

  std::vector<int> cpus = config.cpus.empty() ? ThreadPool::available_cpus() : config.cpus;
  const int threads = config.threads > 0 ? config.threads
                                         : std::max<int>(1, static_cast<int>(cpus.size()));

  m.tritree.configure(config.max_width, config.max_height, config.params.tritree);
  m.match.configure(config.max_width, config.max_height, config.params, kernels);
  m.workers.clear();
  m.workers.resize(static_cast<std::size_t>(threads));
  for (auto& w : m.workers) {
    w.matcher.configure(config.max_width, config.params);
    w.xs.resize(static_cast<std::size_t>(config.max_width));  // untouched until a row fills it
  }
  m.all_xs.resize(static_cast<std::size_t>(config.max_width));
  for (int x = 0; x < config.max_width; ++x) m.all_xs[static_cast<std::size_t>(x)] = x;
  // Reserved, not filled: a fresh block stays untouched address space until a
  // frame writes it, so a frame smaller than the maximum (or gray input, which
  // never needs the gray copies) does not fault in pages it does not use. Each
  // frame sizes them within capacity and writes every pixel it keeps.
  const std::size_t max_px = static_cast<std::size_t>(config.max_width) * config.max_height;
  m.left_gray = ImageU8{};
  m.right_gray = ImageU8{};
  m.left_gray.pixels.reserve(max_px);
  m.right_gray.pixels.reserve(max_px);
  m.out = StereoOutput{};
  m.tritree.reserve(m.out.mesh);
  m.out.vertex_disp_q4.reserve(max_px);
  m.out.disp_q4.channels = 1;
  m.out.disp_q4.pixels.reserve(max_px);

  m.pool.start(threads, cpus, config.pin_threads);
  m.config = config;
  m.config.threads = threads;
  m.active = active;
  m.kernels = &kernels;
  m.configured = true;
}

namespace {
// Chunk sizes of the on-demand hand-out: small enough that the last chunks
// even out the workers, large enough that claiming one (an atomic add) is
// negligible. A row costs tens of microseconds, a triangle tens of nanoseconds.
constexpr int kRowsPerChunk = 4;
constexpr int kTrianglesPerChunk = 4096;

// Gray view of an input: the view itself when it is gray, else `buffer` filled.
ImageView<const std::uint8_t> as_gray(ImageView<const std::uint8_t> in, ImageU8& buffer) {
  if (in.channels == 1) return in;
  buffer.width = in.width;
  buffer.height = in.height;
  buffer.pixels.resize(static_cast<std::size_t>(in.width) * in.height);  // within capacity
  ImageView<std::uint8_t> dst{buffer.pixels.data(), in.width, in.height, 1, in.width};
  rgb_to_gray_bt601(in, dst);
  return {buffer.pixels.data(), in.width, in.height, 1, in.width};
}
}  // namespace

const StereoOutput& Pipeline::process(ImageView<const std::uint8_t> left,
                                      ImageView<const std::uint8_t> right) {
  Impl& m = *impl_;
  if (!m.configured)
    throw Error(ErrorCode::kNotConfigured, "Pipeline::process called before configure()");
  check_stereo_inputs(left, right, m.config.max_width, m.config.max_height);

  const std::int64_t t_start = monotonic_ns();
  const ImageView<const std::uint8_t> lg = as_gray(left, m.left_gray);
  const ImageView<const std::uint8_t> rg = as_gray(right, m.right_gray);
  const int width = lg.width, height = lg.height;
  const StereoParams& params = m.config.params;
  const int workers = m.pool.size();

  // 1. Tritree on the left image.
  Mesh& mesh = m.out.mesh;
  m.mark(PipelineStage::kTritree, true);
  m.tritree.build(lg, mesh, &m.pool);
  const std::int64_t t_tritree = monotonic_ns();
  m.mark(PipelineStage::kTritree, false);
  m.mark(PipelineStage::kMatching, true);

  // 2. Right rows for the cost kernels (part of cost aggregation).
  m.match.begin_frame(lg, rg);
  m.pool.run([&](int w) {
    int y0, y1;
    ThreadPool::split_range(0, height, workers, w, &y0, &y1);
    m.match.prepare_right_rows(y0, y1);
  });
  const std::int64_t t_prepared = monotonic_ns();

  // 3. Cost aggregation + DP, row by row. Rows are independent, so workers
  // take chunks of rows on demand (platform/work_chunks.hpp): uneven rows
  // (sparse mode) and a worker slowed from outside both even out.
  ImageS16& dense = m.out.disp_q4;
  dense.width = width;
  dense.height = height;
  dense.pixels.resize(static_cast<std::size_t>(width) * height);  // within capacity
  std::vector<std::int16_t>& vdisp = m.out.vertex_disp_q4;
  vdisp.resize(mesh.vertices.size());  // within capacity
  m.rows.reset(0, height, kRowsPerChunk);
  m.pool.run([&](int w) {
    Impl::Worker& wk = m.workers[static_cast<std::size_t>(w)];
    wk.cost_ns = 0;
    wk.dp_ns = 0;
    RowTimes times;
    int y0 = 0, y1 = 0;
    while (m.rows.next(&y0, &y1)) {
      for (int y = y0; y < y1; ++y) {
        if (params.dense) {
          wk.matcher.match_row(m.match, y, m.all_xs.data(), width, dense.row(y), &times);
          continue;
        }
        const int v0 = mesh.row_start[static_cast<std::size_t>(y)];
        const int v1 = mesh.row_start[static_cast<std::size_t>(y) + 1];
        for (int i = v0; i < v1; ++i) wk.xs[static_cast<std::size_t>(i - v0)] = mesh.vertices[static_cast<std::size_t>(i)].x;
        if (v1 > v0) wk.matcher.match_row(m.match, y, wk.xs.data(), v1 - v0, vdisp.data() + v0, &times);
      }
    }
    wk.cost_ns = times.cost_ns;
    wk.dp_ns = times.dp_ns;
  });
  const std::int64_t t_matched = monotonic_ns();
  m.mark(PipelineStage::kMatching, false);
  m.mark(PipelineStage::kInterpolation, true);

  // 4. Dense map from the mesh (sparse mode) or sample disparities from the map (dense mode).
  if (params.dense) {
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      vdisp[i] = dense.at(mesh.vertices[i].x, mesh.vertices[i].y);
  } else {
    ImageView<std::int16_t> dv = dense.view();
    m.triangles.reset(0, static_cast<int>(mesh.triangles.size()), kTrianglesPerChunk);
    m.pool.run([&](int) {
      int t0 = 0, t1 = 0;
      while (m.triangles.next(&t0, &t1)) interpolate_triangles(mesh, vdisp.data(), t0, t1, dv);
    });
  }
  const std::int64_t t_end = monotonic_ns();
  m.mark(PipelineStage::kInterpolation, false);

  // Cost and DP interleave per row inside each worker; the match phase's wall
  // time is split between them in proportion to the workers' summed stage times.
  std::int64_t cost_sum = 0, dp_sum = 0;
  for (const auto& wk : m.workers) {
    cost_sum += wk.cost_ns;
    dp_sum += wk.dp_ns;
  }
  const std::int64_t match_wall = t_matched - t_prepared;
  const std::int64_t both = cost_sum + dp_sum;
  const std::int64_t cost_part =
      both > 0 ? static_cast<std::int64_t>(static_cast<double>(match_wall) * cost_sum / both) : match_wall;
  m.timings.tritree_ns = t_tritree - t_start;
  m.timings.cost_aggregation_ns = (t_prepared - t_tritree) + cost_part;
  m.timings.dp_ns = match_wall - cost_part;
  m.timings.interpolation_ns = t_end - t_matched;
  m.timings.total_ns = t_end - t_start;
  return m.out;
}

}  // namespace tristereo
