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
#include "platform/side_work.hpp"
#include "platform/thread_pool.hpp"
#include "platform/work_chunks.hpp"
#include "src/aggregate/path_matcher.hpp"
#include "src/cost/match_context.hpp"
#include "src/fill/sample_fill.hpp"
#include "src/select/confidence.hpp"
#include "src/select/lr_check.hpp"
#include "src/select/support_prior.hpp"
#include "src/dp/row_matcher.hpp"
#include "src/interp/interpolate_edges.hpp"
#include "src/interp/interpolate_midpoints.hpp"
#include "src/interp/interpolate_planes.hpp"
#include "src/interp/interpolate_state.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/memory/capacity_bytes.hpp"
#include "src/memory/large_array.hpp"
#include "src/memory/untouched_vector.hpp"
#include "src/pipeline/input_check.hpp"
#include "src/rectify/rectify_map.hpp"
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
  Tritree right_tritree;  // the mirrored pass's (left-right check by a second pass)
  MatchContext match;
  PathMatcher paths;
  SampleFill fill;
  SupportPrior prior;  // support_prior_applies(params) only
  ThreadPool pool;
  struct Worker {
    RowMatcher matcher;
    CensusScratch census;
    UntouchedVector<std::int32_t> xs;  // sample x of the row being matched
    std::int64_t cost_ns = 0;
    std::int64_t dp_ns = 0;
    // Interpolation: one row of tiles' grid values, then their confidences.
    std::unique_ptr<std::int32_t[]> tile_values;
  };
  std::vector<Worker> workers;
  WorkChunks rows;       // matching: rows handed out on demand
  WorkChunks triangles;  // interpolation: rows of tiles, triangles or (dense) vertices on demand
  HomeChunks leaf_homes;  // interpolation: the stretched leaves, a home of them per worker
  std::vector<std::int32_t> all_xs;  // 0 .. max_width-1 (dense mode samples)
  ImageU8 left_gray, right_gray;     // used when the input is RGB (reserved, sized per frame)
  ImageU8 rect_left, rect_right;     // the rectified frames (config.rectify only)
  // Left-right check: the right view is matched as the left view of the
  // mirrored pair (mirror(R), mirror(L)). Reserved, sized per frame.
  ImageU8 mirror_left, mirror_right;
  Mesh right_mesh;
  std::vector<std::int16_t> right_vdisp;
  ImageS16 right_disp;
  StereoOutput out;
  FrameTimings timings;
  StageListener* listener = nullptr;
  FrameTrace* trace = nullptr;
  int frame_number = 0;

  // A span on the trace's pipeline track (nothing without a trace).
  void span(TraceKind kind, std::int64_t t0, std::int64_t t1, int a = 0) const {
    if (trace != nullptr) trace->record(FrameTrace::kPipelineTrack, kind, t0, t1, a);
  }
  void mark(PipelineStage s, bool begin) const {
    if (listener) listener->on_stage(s, begin);
  }
  PathMatcher::Rejected match_view(ImageView<const std::uint8_t> lg, ImageView<const std::uint8_t> rg,
                                   const SampleLayout& samples, std::int16_t* sample_disp,
                                   std::uint8_t* sample_conf, std::int64_t* cost_ns, std::int64_t* dp_ns,
                                   SideWork* right_rows = nullptr);
  int settle_states(int n, std::int16_t* disp, std::uint8_t* conf, std::uint8_t* state);
  void interpolate_all(const Tritree& tree, const Mesh& mesh, const std::int16_t* vertex_disp,
                       ImageView<const std::uint8_t> gray, ImageView<std::int16_t> out,
                       const ConfidenceMaps* conf = nullptr);
  // The tritree, and for the path optimizer's sparse frames the mesh's
  // predecessors, offered as the leaves are emitted (no scan of the mesh).
  void build_mesh(Tritree& tree, ImageView<const std::uint8_t> gray, Mesh& mesh, SideWork* side = nullptr) {
    if (config.params.optimizer != Optimizer::kPaths || config.params.dense) {
      tree.build(gray, mesh, &pool, nullptr, side);
      return;
    }
    PredecessorTable preds = paths.predecessor_table();
    tree.build(gray, mesh, &pool, &preds, side);
    paths.use_predecessors(&mesh, preds);
  }
};

Pipeline::Pipeline() : impl_(new Impl) {}
Pipeline::~Pipeline() = default;

bool Pipeline::configured() const { return impl_->configured; }
const PipelineConfig& Pipeline::config() const { return impl_->config; }
const FrameTimings& Pipeline::last_timings() const { return impl_->timings; }
void Pipeline::set_stage_listener(StageListener* listener) { impl_->listener = listener; }
void Pipeline::set_trace(FrameTrace* trace) {
  impl_->trace = trace;
  impl_->pool.set_trace(trace);
  impl_->paths.set_trace(trace);
  impl_->tritree.set_trace(trace);
  impl_->fill.set_trace(trace);
  impl_->right_tritree.set_trace(trace);
}
KernelChoice Pipeline::active_kernels() const { return impl_->active; }
int Pipeline::worker_count() const { return impl_->configured ? impl_->pool.size() : 0; }

std::size_t Pipeline::working_memory_bytes() const {
  const Impl& m = *impl_;
  if (!m.configured) return 0;
  std::size_t bytes = m.tritree.working_memory_bytes() + m.right_tritree.working_memory_bytes() +
                      m.match.working_memory_bytes() +
                      capacity_bytes(m.workers) + capacity_bytes(m.all_xs) +
                      capacity_bytes(m.left_gray.pixels) + capacity_bytes(m.right_gray.pixels) +
                      capacity_bytes(m.out.mesh.vertices) + capacity_bytes(m.out.mesh.triangles) +
                      capacity_bytes(m.out.mesh.row_start) + capacity_bytes(m.out.vertex_disp_q4) +
                      capacity_bytes(m.out.disp_q4.pixels) + capacity_bytes(m.out.vertex_state) +
                      capacity_bytes(m.out.vertex_confidence) + capacity_bytes(m.out.pixel_state.pixels) +
                      capacity_bytes(m.out.pixel_confidence.pixels) + capacity_bytes(m.rect_left.pixels) +
                      capacity_bytes(m.rect_right.pixels) + (m.config.rectify ? m.config.rectify->memory_bytes() : 0);
  for (const Impl::Worker& w : m.workers)
    bytes += w.matcher.working_memory_bytes() + capacity_bytes(w.xs) + w.census.working_memory_bytes() +
             midpoint_band_values_with_confidence(m.tritree.tile_side(), m.config.max_width) * sizeof(std::int32_t);
  bytes += m.paths.working_memory_bytes() + m.fill.working_memory_bytes() + m.prior.working_memory_bytes() +
           capacity_bytes(m.mirror_left.pixels) + capacity_bytes(m.mirror_right.pixels) +
           capacity_bytes(m.right_mesh.vertices) + capacity_bytes(m.right_mesh.triangles) +
           capacity_bytes(m.right_mesh.row_start) + capacity_bytes(m.right_vdisp) +
           capacity_bytes(m.right_disp.pixels);
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
  if (config.schedule_workers < 0 || config.schedule_workers > 256)
    throw Error(ErrorCode::kInvalidArgument,
                "schedule_workers = " + std::to_string(config.schedule_workers) + " is outside 0..256 (0 = threads)");
  if (config.threads < 0 || config.threads > 256)
    throw Error(ErrorCode::kInvalidArgument,
                "threads = " + std::to_string(config.threads) + " is outside 0..256 (0 = one per CPU)");
  if (config.rectify) {
    const RectifyMaps& r = *config.rectify;
    for (const RectifyMap* map : {&r.left, &r.right})
      if (map->width > config.max_width || map->height > config.max_height || map->raw_width > config.max_width ||
          map->raw_height > config.max_height || map->width != r.left.width || map->height != r.left.height ||
          map->xy.size() != 2 * static_cast<std::size_t>(map->width) * map->height)
        throw Error(ErrorCode::kInvalidArgument,
                    "rectification maps of " + std::to_string(map->raw_width) + "x" + std::to_string(map->raw_height) +
                        " raw to " + std::to_string(map->width) + "x" + std::to_string(map->height) +
                        " rectified pixels do not fit the configured maximum size " + std::to_string(config.max_width) +
                        "x" + std::to_string(config.max_height));
  }
  const KernelChoice active = resolve_kernel_choice(config.kernels);
  const KernelSet& kernels = kernel_set_for(active);

  std::vector<int> cpus = config.cpus.empty() ? ThreadPool::available_cpus() : config.cpus;
  const int threads = config.threads > 0 ? config.threads
                                         : std::max<int>(1, static_cast<int>(cpus.size()));

  m.tritree.configure(config.max_width, config.max_height, config.params.tritree, &kernels);
  m.match.configure(config.max_width, config.max_height, config.params, kernels);
  m.workers.clear();
  m.workers.resize(static_cast<std::size_t>(threads));
  const StereoParams& sp = config.params;
  const bool rows_dp = sp.optimizer == Optimizer::kRowDp;
  for (auto& w : m.workers) {
    if (rows_dp) w.matcher.configure(config.max_width, config.params);
    w.census.resize(config.max_width);
    w.xs.resize(static_cast<std::size_t>(config.max_width));  // untouched until a row fills it
    w.tile_values.reset(
        new std::int32_t[midpoint_band_values_with_confidence(m.tritree.tile_side(), config.max_width)]());
  }
  const int max_px = config.max_width * config.max_height;
  if (!rows_dp) m.paths.configure(config.max_width, config.max_height, sp, kernels, threads, config.schedule_workers);
  else m.paths.release();  // a reconfiguration to the row DP gives the path buffers back
  // A conforming triangulation of n points has fewer than 2n triangles.
  m.fill.configure(max_px, 2 * max_px, threads);
  if (support_prior_applies(sp)) m.prior.configure(max_px, 2 * max_px, sp.num_disp, threads, config.schedule_workers);
  else m.prior.release();
  const bool lr = sp.validity.lr_max_diff_q4 >= 0 && sp.validity.lr_source == LrSource::kMirroredPass;
  const std::size_t lr_px = lr ? static_cast<std::size_t>(max_px) : 0;
  m.mirror_left = ImageU8{};
  m.mirror_right = ImageU8{};
  m.mirror_left.pixels.reserve(lr_px);
  m.mirror_right.pixels.reserve(lr_px);
  m.right_mesh = Mesh{};
  m.right_tritree = Tritree{};
  m.right_tritree.set_trace(m.trace);
  if (lr) {
    m.right_tritree.configure(config.max_width, config.max_height, config.params.tritree, &kernels);
    m.right_tritree.reserve(m.right_mesh);
  }
  m.right_vdisp.clear();
  m.right_vdisp.reserve(lr_px);
  m.right_disp = ImageS16{};
  m.right_disp.channels = 1;
  m.right_disp.pixels.reserve(lr_px);
  m.all_xs.resize(static_cast<std::size_t>(config.max_width));
  for (int x = 0; x < config.max_width; ++x) m.all_xs[static_cast<std::size_t>(x)] = x;
  // Reserved, not filled: a fresh block stays untouched address space until a
  // frame writes it, so a frame smaller than the maximum (or gray input, which
  // never needs the gray copies) does not fault in pages it does not use. Each
  // frame sizes them within capacity and writes every pixel it keeps.
  const std::size_t max_px_size = static_cast<std::size_t>(max_px);
  m.left_gray = ImageU8{};
  m.right_gray = ImageU8{};
  m.left_gray.pixels.reserve(max_px_size);
  m.right_gray.pixels.reserve(max_px_size);
  m.rect_left = ImageU8{};
  m.rect_right = ImageU8{};
  if (config.rectify) {
    // Sized once: every raw frame fills them whole.
    m.rect_left = ImageU8(config.rectify->left.width, config.rectify->left.height, 1);
    m.rect_right = ImageU8(config.rectify->right.width, config.rectify->right.height, 1);
  }
  m.out = StereoOutput{};
  m.tritree.reserve(m.out.mesh);
  m.out.vertex_disp_q4.reserve(max_px_size);
  m.out.disp_q4.channels = 1;
  m.out.disp_q4.pixels.reserve(max_px_size);
  m.out.vertex_state.reserve(max_px_size);
  m.out.vertex_confidence.reserve(max_px_size);
  m.out.pixel_state.channels = 1;
  m.out.pixel_state.pixels.reserve(max_px_size);
  m.out.pixel_confidence.channels = 1;
  m.out.pixel_confidence.pixels.reserve(max_px_size);
  // The large reserved outputs and copies fault in 2 MiB at a time where THP is on.
  advise_huge_pages(m.out.mesh.vertices.data(), m.out.mesh.vertices.capacity() * sizeof(Vertex));
  advise_huge_pages(m.out.mesh.triangles.data(), m.out.mesh.triangles.capacity() * sizeof(Triangle));
  advise_huge_pages(m.out.vertex_disp_q4.data(), m.out.vertex_disp_q4.capacity() * sizeof(std::int16_t));
  advise_huge_pages(m.out.disp_q4.pixels.data(), m.out.disp_q4.pixels.capacity() * sizeof(std::int16_t));
  advise_huge_pages(m.left_gray.pixels.data(), m.left_gray.pixels.capacity());
  advise_huge_pages(m.right_gray.pixels.data(), m.right_gray.pixels.capacity());

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
// The stretched leaves: thin triangles along the moved last column and row,
// about 0.1 us each and a thousand on 640x480 (a hundred chunks or more).
constexpr int kStretchedLeavesPerChunk = 8;
// Dense frames: the map's value at each mesh vertex, tens of nanoseconds each.
constexpr int kVerticesPerChunk = 2048;
// The mirrored pass's check: a row's samples, tens of nanoseconds each.
constexpr int kLeftRightRowsPerChunk = 16;
// Samples per chunk of the states settled after the fill.
constexpr int kSettlePerChunk = 16384;

// Gray view of an input (checked by check_stereo_inputs): the view itself
// when it is gray, else `buffer` filled by the configured set's row kernel.
ImageView<const std::uint8_t> as_gray(ImageView<const std::uint8_t> in, ImageU8& buffer, const KernelSet& ks) {
  if (in.channels == 1) return in;
  buffer.width = in.width;
  buffer.height = in.height;
  buffer.pixels.resize(static_cast<std::size_t>(in.width) * in.height);  // within capacity
  for (int y = 0; y < in.height; ++y)
    ks.rgb_to_gray_row_u8(in.row(y), in.width, buffer.pixels.data() + static_cast<std::size_t>(y) * in.width);
  return {buffer.pixels.data(), in.width, in.height, 1, in.width};
}
}  // namespace

// Matching of one view: costs at the samples, the configured optimizer, the
// winner (and, paths only, uniqueness and the left-right check from the summed
// costs). Returns the samples those tests rejected. `right_rows`: the rows'
// preparation begun beside the tritree (begin_frame done), else all of it here.
PathMatcher::Rejected Pipeline::Impl::match_view(ImageView<const std::uint8_t> lg,
                                                 ImageView<const std::uint8_t> rg,
                                                 const SampleLayout& samples, std::int16_t* sample_disp,
                                                 std::uint8_t* sample_conf, std::int64_t* cost_ns,
                                                 std::int64_t* dp_ns, SideWork* right_rows) {
  const std::int64_t t0 = monotonic_ns();
  const int workers = pool.size();
  const int height = lg.height;
  // Right rows (and census descriptors) for the cost kernels.
  if (right_rows != nullptr) {
    pool.run([&](int w) { right_rows->drain(w); });
  } else {
    match.begin_frame(lg, rg);
    pool.run([&](int w) {
      int y0, y1;
      ThreadPool::split_range(0, height, workers, w, &y0, &y1);
      match.prepare_right_rows(y0, y1, &this->workers[static_cast<std::size_t>(w)].census);
    });
  }
  const std::int64_t t_prepared = monotonic_ns();
  if (config.params.optimizer == Optimizer::kPaths) {
    paths.compute_costs(match, samples, pool);
    const std::int64_t t_costs = monotonic_ns();
    span(TraceKind::kCosts, t0, t_costs);
    const PathMatcher::Rejected rejected = paths.match(samples, lg, pool, sample_disp, sample_conf);
    *cost_ns += t_costs - t0;
    *dp_ns += monotonic_ns() - t_costs;
    return rejected;
  }
  // The paper's DP: cost aggregation + DP, row by row. Rows are independent,
  // so workers take chunks of rows on demand (platform/work_chunks.hpp):
  // uneven rows (sparse mode) and a worker slowed from outside both even out.
  rows.reset(0, height, kRowsPerChunk);
  pool.run([&](int w) {
    Worker& wk = this->workers[static_cast<std::size_t>(w)];
    wk.cost_ns = 0;
    wk.dp_ns = 0;
    RowTimes times;
    int y0 = 0, y1 = 0;
    while (rows.next(&y0, &y1)) {
      for (int y = y0; y < y1; ++y) {
        const int v0 = samples.row_begin(y), v1 = samples.row_end(y);
        const std::int32_t* xs = all_xs.data();
        if (!samples.dense()) {
          for (int i = v0; i < v1; ++i) wk.xs[static_cast<std::size_t>(i - v0)] = samples.x_of(i);
          xs = wk.xs.data();
        }
        if (v1 > v0) wk.matcher.match_row(match, y, xs, v1 - v0, sample_disp + v0, &times);
      }
    }
    wk.cost_ns = times.cost_ns;
    wk.dp_ns = times.dp_ns;
  });
  // Cost and DP interleave per row inside each worker; the match phase's wall
  // time is split between them in proportion to the workers' summed stage times.
  std::int64_t cost_sum = 0, dp_sum = 0;
  for (const auto& wk : this->workers) {
    cost_sum += wk.cost_ns;
    dp_sum += wk.dp_ns;
  }
  const std::int64_t t_matched = monotonic_ns();
  span(TraceKind::kCosts, t0, t_prepared);
  span(TraceKind::kRowDp, t_prepared, t_matched);
  const std::int64_t match_wall = t_matched - t_prepared;
  const std::int64_t both = cost_sum + dp_sum;
  const std::int64_t cost_part =
      both > 0 ? static_cast<std::int64_t>(static_cast<double>(match_wall) * cost_sum / both) : match_wall;
  *cost_ns += (t_prepared - t0) + cost_part;
  *dp_ns += match_wall - cost_part;
  if (sample_conf != nullptr)
    std::fill_n(sample_conf, samples.count(), static_cast<std::uint8_t>(kRowDpMeasuredConfidence));
  return {};
}

namespace {
// settle_states' loop over samples [i0, i1); returns how many min_conf made
// invalid. Every load unconditional, & for &&, the state as a sum (the same
// values as state_of_confidence(c), tested), and the arrays as arguments
// rather than a lambda's captures (a byte store may alias a captured
// reference, which then reloaded every sample): the compiler vectorises it.
int settle_samples(int i0, int i1, std::int16_t* disp, std::uint8_t* conf, std::uint8_t* state, int min_conf) {
  static_assert(static_cast<int>(SampleState::kInvalid) == 0 && static_cast<int>(SampleState::kFilled) == 1 &&
                    static_cast<int>(SampleState::kMeasured) == 2,
                "the states' sum below");
  int rejected = 0;
  for (int i = i0; i < i1; ++i) {
    const int d = disp[i], ci = conf[i];
    const int c0 = d == kInvalidDispQ4 ? 0 : ci;
    const bool reject = (c0 != 0) & (c0 < min_conf);
    disp[i] = static_cast<std::int16_t>(reject ? kInvalidDispQ4 : d);
    const int c = reject ? 0 : c0;
    rejected += reject;
    conf[i] = static_cast<std::uint8_t>(c);
    state[i] = static_cast<std::uint8_t>((c != 0) + (c >= kMinMeasuredConfidence));
  }
  return rejected;
}
}  // namespace

// After the fill: a sample still invalid gets confidence 0 (the one the
// matcher gave it was its margin before a rejection); then those below the
// minimum confidence become invalid, and every state follows from the
// confidence (src/select/confidence.hpp). Returns how many the minimum made
// invalid. Chunks of samples on demand (a sample reads only itself).
int Pipeline::Impl::settle_states(int n, std::int16_t* disp, std::uint8_t* conf, std::uint8_t* state) {
  const int min_conf = config.params.validity.min_confidence;
  std::atomic<int> rejected{0};
  rows.reset(0, n, kSettlePerChunk);
  pool.run([&](int w) {
    int i0 = 0, i1 = 0, own = 0;
    while (rows.next(&i0, &i1)) {
      const std::int64_t t0 = trace != nullptr ? monotonic_ns() : 0;
      own += settle_samples(i0, i1, disp, conf, state, min_conf);
      if (trace != nullptr) trace->record(w, TraceKind::kSampleStates, t0, monotonic_ns(), i0, i1);
    }
    rejected.fetch_add(own, std::memory_order_relaxed);
  });
  return rejected.load();
}

// Interpolation by midpoint averages over the tritree's tiles (rows of tiles
// on demand), then the stretched border leaves, then, only when a vertex is
// invalid, the triangles that reach one (src/interp/interpolate_midpoints.hpp);
// with `conf`, the pixel confidence and state in the same passes.
void Pipeline::Impl::interpolate_all(const Tritree& tree, const Mesh& mesh, const std::int16_t* vertex_disp,
                                     ImageView<const std::uint8_t> gray, ImageView<std::int16_t> out,
                                     const ConfidenceMaps* conf) {
  const TritreeGrid grid = tree.grid();
  const int n_tri = static_cast<int>(mesh.triangles.size());
  const int edge_spread = config.params.interp.edge_spread_q4;
  if (grid.need == nullptr) {  // a 2-pixel strip: its two triangles
    interpolate_triangles(mesh, vertex_disp, 0, n_tri, out);
    if (conf != nullptr) {
      for (const Triangle& t : mesh.triangles) {
        const auto vertex = [&](int k) { return mesh.vertices[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])]; };
        confidence_triangle(vertex(0), vertex(1), vertex(2), conf->vertex_confidence[t[0]],
                            conf->vertex_confidence[t[1]], conf->vertex_confidence[t[2]],
                            vertex_disp[t[0]] == kInvalidDispQ4 || vertex_disp[t[1]] == kInvalidDispQ4 ||
                                vertex_disp[t[2]] == kInvalidDispQ4,
                            *conf);
      }
    }
    interpolate_edge_triangles(mesh, vertex_disp, gray, edge_spread, 0, n_tri, out, conf);
    return;
  }
  triangles.reset(0, grid.layout.tiles_y, 1);
  std::atomic<bool> any_invalid{false};  // the tiles read every vertex, so they tell
  // Depth edges (docs/model.md section 4) by rows of tiles, each right after
  // its tiles, while their rows are in the cache (after every tile, the
  // maps' lines came from L3: the pass took 0.9 ms of KITTI's frame at one
  // worker). A row of tiles' triangles own pixels of its own rows only: the
  // fill rule gives a line between two rows of tiles to the triangles below
  // it (tests/interp_edges_test.cpp checks it), and those are the pixels
  // that row's tiles write.
  const int tiles_y = grid.layout.tiles_y;
  const bool edges = edge_spread > 0;
  const auto edge_band = [&](int w, int ty) {
    const auto t0 = static_cast<int>(grid.band_start[ty]);
    const int t1 = ty + 1 < tiles_y ? static_cast<int>(grid.band_start[ty + 1]) : n_tri;
    const std::int64_t start = trace != nullptr ? monotonic_ns() : 0;
    interpolate_edge_triangles(mesh, vertex_disp, gray, edge_spread, t0, t1, out, conf);
    if (trace != nullptr) trace->record(w, TraceKind::kEdgeTriangles, start, monotonic_ns(), t0, t1);
  };
  pool.run([&](int w) {
    int r0 = 0, r1 = 0;
    bool invalid = false;
    std::int32_t* values = this->workers[static_cast<std::size_t>(w)].tile_values.get();
    while (triangles.next(&r0, &r1)) {
      const std::int64_t t0 = trace != nullptr ? monotonic_ns() : 0;
      invalid |= interpolate_midpoint_tiles(grid, mesh, vertex_disp, r0, r1, *kernels, values, out, conf);
      if (trace != nullptr) trace->record(w, TraceKind::kInterpolationTiles, t0, monotonic_ns(), r0, r1);
      if (edges)
        for (int ty = r0; ty < r1; ++ty) edge_band(w, ty);
    }
    if (invalid) any_invalid.store(true, std::memory_order_relaxed);
  });
  // The stretched leaves overwrite pixels the tiles wrote on the moved last
  // column and row (their planes do not meet the grid's midpoints), so they
  // come after every tile; each leaf writes only its own pixels, so they go in
  // chunks to every worker (a serial loop was a third of the stage's time at
  // one worker on 640x480). Neighbouring leaves write the same rows' last
  // cache lines, so each worker takes a home of consecutive chunks first:
  // chunks dealt in turn made two workers' leaves twice as slow as one's.
  // A leaf across a depth edge takes the rule again after its plane.
  if (grid.stretched_count > 0) {
    const auto leaves = static_cast<int>(grid.stretched_count);
    leaf_homes.reset((leaves + kStretchedLeavesPerChunk - 1) / kStretchedLeavesPerChunk, pool.size());
    pool.run([&](int w) {
      leaf_homes.for_each(w, [&](int c) {
        const int l0 = c * kStretchedLeavesPerChunk, l1 = std::min(leaves, l0 + kStretchedLeavesPerChunk);
        const std::int64_t t0 = trace != nullptr ? monotonic_ns() : 0;
        interpolate_stretched_leaves(grid, mesh, vertex_disp, static_cast<std::size_t>(l0),
                                     static_cast<std::size_t>(l1), out, conf);
        interpolate_edge_leaves(grid.stretched + l0, static_cast<std::size_t>(l1 - l0), mesh, vertex_disp, gray,
                                edge_spread, out, conf);
        if (trace != nullptr) trace->record(w, TraceKind::kStretchedLeaves, t0, monotonic_ns(), l0, l1);
      });
    });
  }
  // Then, only when a vertex is invalid, the triangles that reach one (the
  // depth edges' rule skips them).
  if (!any_invalid.load(std::memory_order_relaxed)) return;
  triangles.reset(0, n_tri, kTrianglesPerChunk);
  pool.run([&](int) {
    int t0 = 0, t1 = 0;
    while (triangles.next(&t0, &t1)) invalidate_triangles(mesh, vertex_disp, t0, t1, out, conf);
  });
}

const StereoOutput& Pipeline::process(ImageView<const std::uint8_t> left,
                                      ImageView<const std::uint8_t> right) {
  Impl& m = *impl_;
  if (!m.configured)
    throw Error(ErrorCode::kNotConfigured, "Pipeline::process called before configure()");
  check_stereo_inputs(left, right, m.config.max_width, m.config.max_height);

  const std::int64_t t_start = monotonic_ns();
  m.pool.trace_new_frame();
  ImageView<const std::uint8_t> lg = as_gray(left, m.left_gray, *m.kernels);
  ImageView<const std::uint8_t> rg = as_gray(right, m.right_gray, *m.kernels);
  if (m.config.rectify) {
    // Raw frames: both rectified first, rows of both views handed out
    // together (each row is one worker's, whichever: the same output).
    const RectifyMaps& maps = *m.config.rectify;
    for (const auto& in : {std::make_pair(left, &maps.left), std::make_pair(right, &maps.right)})
      if (in.first.width != in.second->raw_width || in.first.height != in.second->raw_height)
        throw Error(ErrorCode::kSizeMismatch, "raw frame of " + std::to_string(in.first.width) + "x" +
                                                  std::to_string(in.first.height) + " for a rig calibrated at " +
                                                  std::to_string(in.second->raw_width) + "x" +
                                                  std::to_string(in.second->raw_height));
    const int h = maps.left.height;
    m.rows.reset(0, 2 * h, kRowsPerChunk);
    const ImageView<const std::uint8_t> raw_l = lg, raw_r = rg;
    m.pool.run([&](int) {
      int r0 = 0, r1 = 0;
      while (m.rows.next(&r0, &r1)) {
        for (int r = r0; r < r1;) {
          const bool right_view = r >= h;
          const int v0 = right_view ? r - h : r;
          const int v1 = std::min(r1 - (right_view ? h : 0), h);
          remap_rows(right_view ? maps.right : maps.left, right_view ? raw_r : raw_l,
                     right_view ? m.rect_right.view() : m.rect_left.view(), v0, v1, *m.kernels);
          r += v1 - v0;
        }
      }
    });
    lg = m.rect_left.view();
    rg = m.rect_right.view();
  }
  const std::int64_t t_rectified = monotonic_ns();
  const int width = lg.width, height = lg.height;
  const StereoParams& params = m.config.params;

  // 1. Tritree on the left image; while it runs a serial step, the other
  // workers prepare the right image's rows for the matching (SideWork).
  Mesh& mesh = m.out.mesh;
  m.mark(PipelineStage::kTritree, true);
  m.match.begin_frame(lg, rg);
  const auto prepare_rows = [&m](int w, int y0, int y1) {
    m.match.prepare_right_rows(y0, y1, &m.workers[static_cast<std::size_t>(w)].census);
  };
  SideWork right_rows(0, height, kRowsPerChunk, m.pool.size(), prepare_rows);
  m.build_mesh(m.tritree, lg, mesh, &right_rows);
  const std::int64_t t_tritree = monotonic_ns();
  m.mark(PipelineStage::kTritree, false);
  m.mark(PipelineStage::kMatching, true);

  ImageS16& dense = m.out.disp_q4;
  dense.width = width;
  dense.height = height;
  dense.pixels.resize(static_cast<std::size_t>(width) * height);  // within capacity
  std::vector<std::int16_t>& vdisp = m.out.vertex_disp_q4;
  vdisp.resize(mesh.vertices.size());  // within capacity
  m.out.vertex_state.resize(mesh.vertices.size());       // within capacity
  m.out.vertex_confidence.resize(mesh.vertices.size());  // within capacity
  for (ImageU8* map : {&m.out.pixel_state, &m.out.pixel_confidence}) {
    map->width = width;
    map->height = height;
    map->pixels.resize(static_cast<std::size_t>(width) * height);  // within capacity
  }
  SampleValidity& validity = m.out.validity;
  validity = SampleValidity{};
  const SampleLayout samples{params.dense ? nullptr : &mesh, width, height};
  std::int16_t* sample_disp = params.dense ? dense.pixels.data() : vdisp.data();
  std::uint8_t* sample_conf = params.dense ? m.out.pixel_confidence.pixels.data() : m.out.vertex_confidence.data();
  std::uint8_t* sample_state = params.dense ? m.out.pixel_state.pixels.data() : m.out.vertex_state.data();
  validity.samples = samples.count();

  std::int64_t cost_ns = 0, dp_ns = 0;
  const PathMatcher::Rejected rejected =
      m.match_view(lg, rg, samples, sample_disp, sample_conf, &cost_ns, &dp_ns, &right_rows);
  validity.uniqueness_rejected = rejected.uniqueness;
  validity.lr_rejected = rejected.left_right;
  // Support prior (docs/model.md section 6b): weak samples chosen again.
  const std::int64_t t_prior = monotonic_ns();
  const bool prior_on = support_prior_applies(params);
  if (prior_on) {
    const SupportPriorCounts pc =
        m.prior.apply(params, samples, m.paths, lg, sample_disp, sample_conf, *m.kernels, &m.pool, m.trace);
    validity.prior_redecided = pc.redecided;
    validity.prior_rejected = pc.rejected;
    validity.prior_recovered = pc.recovered;
    validity.prior_lost = pc.lost;
  }
  const std::int64_t t_matched = monotonic_ns();
  m.mark(PipelineStage::kMatching, false);

  // Left-right check by a second pass: the right view's own tritree, matching,
  // fill and dense map (lr_source = costs did it in match_view).
  if (params.validity.lr_max_diff_q4 >= 0 && params.validity.lr_source == LrSource::kMirroredPass) {
    size_mirror(rg, m.mirror_left);
    size_mirror(lg, m.mirror_right);
    m.rows.reset(0, height, kRowsPerChunk);
    m.pool.run([&](int w) {
      int y0 = 0, y1 = 0;
      while (m.rows.next(&y0, &y1)) {
        const std::int64_t t0 = m.trace != nullptr ? monotonic_ns() : 0;
        mirror_gray_rows(rg, m.mirror_left, y0, y1);
        mirror_gray_rows(lg, m.mirror_right, y0, y1);
        if (m.trace != nullptr) m.trace->record(w, TraceKind::kLeftRightRows, t0, monotonic_ns(), y0, y1, 0);
      }
    });
    const ImageView<const std::uint8_t> ml{m.mirror_left.pixels.data(), width, height, 1, width};
    const ImageView<const std::uint8_t> mr{m.mirror_right.pixels.data(), width, height, 1, width};
    ImageS16& rd = m.right_disp;
    rd.width = width;
    rd.height = height;
    rd.pixels.resize(static_cast<std::size_t>(width) * height);  // within capacity
    std::int16_t* right_samples = rd.pixels.data();
    if (!params.dense) {
      m.build_mesh(m.right_tritree, ml, m.right_mesh);
      m.right_vdisp.resize(m.right_mesh.vertices.size());  // within capacity
      right_samples = m.right_vdisp.data();
    }
    const SampleLayout rs{params.dense ? nullptr : &m.right_mesh, width, height};
    std::int64_t unused_cost = 0, unused_dp = 0;
    m.match_view(ml, mr, rs, right_samples, nullptr, &unused_cost, &unused_dp);
    if (params.validity.fill != FillMode::kNone) m.fill.fill(rs, right_samples, &m.pool);
    if (!params.dense) m.interpolate_all(m.right_tritree, m.right_mesh, right_samples, ml, rd.view());
    // Each sample reads the right map and writes only itself: rows on demand.
    std::atomic<int> lr_rejected{0};
    m.rows.reset(0, height, kLeftRightRowsPerChunk);
    m.pool.run([&](int w) {
      int y0 = 0, y1 = 0, own = 0;
      while (m.rows.next(&y0, &y1)) {
        const std::int64_t t0 = m.trace != nullptr ? monotonic_ns() : 0;
        own += lr_check(samples, rd.view(), params.validity.lr_max_diff_q4, sample_disp, y0, y1);
        if (m.trace != nullptr) m.trace->record(w, TraceKind::kLeftRightRows, t0, monotonic_ns(), y0, y1, 1);
      }
      lr_rejected.fetch_add(own, std::memory_order_relaxed);
    });
    validity.lr_rejected = lr_rejected.load();
  }
  const std::int64_t t_right = monotonic_ns();
  if (params.validity.fill != FillMode::kNone)
    validity.filled = m.fill.fill(samples, sample_disp, &m.pool, sample_conf);
  validity.min_confidence_rejected = m.settle_states(samples.count(), sample_disp, sample_conf, sample_state);
  const std::int64_t t_filled = monotonic_ns();
  m.mark(PipelineStage::kInterpolation, true);

  // 4. Dense map from the mesh (sparse mode) or sample disparities from the map (dense mode).
  if (params.dense) {
    // Each vertex reads its own pixel: chunks of vertices on demand.
    m.triangles.reset(0, static_cast<int>(mesh.vertices.size()), kVerticesPerChunk);
    m.pool.run([&](int w) {
      int i0 = 0, i1 = 0;
      while (m.triangles.next(&i0, &i1)) {
        const std::int64_t t0 = m.trace != nullptr ? monotonic_ns() : 0;
        for (int i = i0; i < i1; ++i) {
          const auto v = static_cast<std::size_t>(i);
          const int x = mesh.vertices[v].x, y = mesh.vertices[v].y;
          vdisp[v] = dense.at(x, y);
          m.out.vertex_state[v] = m.out.pixel_state.at(x, y);
          m.out.vertex_confidence[v] = m.out.pixel_confidence.at(x, y);
        }
        if (m.trace != nullptr) m.trace->record(w, TraceKind::kVertexSamples, t0, monotonic_ns(), i0, i1);
      }
    });
  } else {
    const ConfidenceMaps conf{m.out.vertex_confidence.data(), m.out.pixel_confidence.view(),
                              m.out.pixel_state.view()};
    m.interpolate_all(m.tritree, mesh, vdisp.data(), lg, dense.view(), &conf);
  }
  const std::int64_t t_end = monotonic_ns();
  m.mark(PipelineStage::kInterpolation, false);

  if (m.config.rectify) m.span(TraceKind::kRectify, t_start, t_rectified);
  m.span(TraceKind::kTritree, t_rectified, t_tritree);
  if (prior_on) m.span(TraceKind::kPrior, t_prior, t_matched);
  if (params.validity.lr_max_diff_q4 >= 0 && params.validity.lr_source == LrSource::kMirroredPass)
    m.span(TraceKind::kRightPass, t_matched, t_right);
  m.span(TraceKind::kFill, t_right, t_filled);
  m.span(TraceKind::kInterpolation, t_filled, t_end);
  if (m.trace != nullptr)
    m.trace->record(FrameTrace::kPipelineTrack, TraceKind::kFrame, t_start, t_end, m.frame_number++,
                    m.config.schedule_workers > 0 ? m.config.schedule_workers : m.config.threads);
  m.timings.rectify_ns = t_rectified - t_start;
  m.timings.tritree_ns = t_tritree - t_rectified;
  m.timings.cost_aggregation_ns = cost_ns;
  m.timings.dp_ns = dp_ns;
  m.timings.prior_ns = t_matched - t_prior;
  m.timings.right_pass_ns = t_right - t_matched;
  m.timings.fill_ns = t_filled - t_right;
  m.timings.interpolation_ns = t_end - t_filled;
  m.timings.total_ns = t_end - t_start;
  return m.out;
}

}  // namespace tristereo
