// Path aggregation on the samples and the winner (docs/model.md sections 3b, 6).
//
// Configured once for the largest frame; per frame:
//
//   pm.compute_costs(ctx, samples, pool);  // C(i, k) at every sample
//   pm.match(samples, left_gray, pool, disp_q4);
//       = aggregate: L_r along each direction, S = sum_r L_r (two passes:
//         the forward directions, then the backward ones)
//       + select: smallest argmin of S, sub-pixel, uniqueness, left-right
//         check from S (lr_source = costs)
//
// The two passes run at the same time, each a wavefront of tiles
// (platform/wavefront.hpp): bands of rows cut into column blocks, sheared so
// that every predecessor of a tile's samples lies in the tile itself, in the
// tiles to its left, or in a band above at most `lead` tiles ahead per band.
// A worker takes a ready tile of its own pass first (even workers forward,
// odd ones backward), else of the other, so a slowed one takes fewer tiles.
// The pass that starts a band first writes its S; the other starts that band
// once the first has done it, adds to S, and decides the band's rows. Every
// sample's L_r is computed from the same predecessors by the same kernel
// whatever the schedule, and integer sums do not depend on the order, so the
// output is the same for any thread count.
// Every buffer is sized at configure for max_width x max_height samples (dense
// mode's worst case) and allocated without being touched, so a sparse frame
// only pays for the pages its samples use. No heap allocation per frame.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "src/memory/large_array.hpp"

#include "platform/thread_pool.hpp"
#include "platform/wavefront.hpp"
#include "platform/work_chunks.hpp"
#include "src/aggregate/predecessor_offers.hpp"
#include "src/aggregate/samples.hpp"
#include "src/cost/match_context.hpp"
#include "src/kernels/kernel_set.hpp"
#include "tristereo/params.hpp"
#include "tristereo/trace.hpp"

namespace tristereo {

class PathMatcher {
 public:
  // Throws Error on sizes outside 2..kMaxImageSide, workers outside 1..256 or
  // parameters validate_params rejects.
  // schedule_workers: cut the passes into tiles as for that many workers
  // (0 = `workers`; a one-worker trace recorded for the scaling model).
  void configure(int max_width, int max_height, const StereoParams& params,
                 const KernelSet& kernels, int workers, int schedule_workers = 0);

  // C(i, k) = ctx.aggregate_sample at sample i (ctx prepared for the frame).
  // Sparse mode: the mesh predecessors too (unless use_predecessors() handed
  // over the mesher's), on one worker while the others start on the rows
  // (serial work that would otherwise leave workers idle).
  // Throws Error (after every worker is done) for a mesh whose edges reach
  // beyond the path rings.
  void compute_costs(const MatchContext& ctx, const SampleLayout& samples, ThreadPool& pool);
  // The predecessor table, for a mesher to fill while it builds the next
  // frame's mesh (Tritree::build); once filled, use_predecessors() hands it
  // back for that mesh, and the next compute_costs() on it skips the scan.
  PredecessorTable predecessor_table() { return PredecessorTable{preds_.get(), directions_, false, 0, {}}; }
  void use_predecessors(const Mesh* mesh, const PredecessorTable& filled);
  // Predecessors along each direction, then the path costs and their sums.
  // left_gray: the frame's reference image (for the intensity-adaptive P2).
  void aggregate(const SampleLayout& samples, ImageView<const std::uint8_t> left_gray,
                 ThreadPool& pool);
  // disp_q4[i] = 16 (d_min + k) + sub-pixel offset for the smallest argmin k
  // of S(i, .), or kInvalidDispQ4 where the uniqueness test or (lr_source =
  // costs) the left-right check fails. Returns how many each rejected.
  // confidence (optional): every sample's measured_confidence() from its
  // best and rival summed costs (src/select/confidence.hpp), rejected or not.
  struct Rejected {
    int uniqueness = 0;
    int left_right = 0;
  };
  Rejected select(const SampleLayout& samples, ThreadPool& pool, std::int16_t* disp_q4,
                  std::uint8_t* confidence = nullptr);
  // aggregate() then select(), with the same result, but each row decided as
  // soon as its S is complete, by the worker that completed it (while the
  // row's sums are still in its cache: a separate select() reads all of S back
  // from memory).
  Rejected match(const SampleLayout& samples, ImageView<const std::uint8_t> left_gray,
                 ThreadPool& pool, std::int16_t* disp_q4, std::uint8_t* confidence = nullptr);

  // Work items and passes go to `trace` (null = none; not owned).
  void set_trace(FrameTrace* trace) { trace_ = trace; }

  // Gives every buffer back (working_memory_bytes() becomes 0).
  void release();
  // Heap bytes the configured matcher holds (docs/performance.md, working memory).
  std::size_t working_memory_bytes() const;

  // Inspection (tests): C, and the summed path costs of the last select().
  // C(i, 0 .. D) of the last compute_costs() in Q4, into out.
  void cost_q4(const SampleLayout& samples, int i, std::uint16_t* out) const;
  // S(i, k) of the last aggregate().
  void summed_costs(int i, std::uint16_t* out) const;
  // S(i, 0 .. D) of the last aggregate(), in place.
  const std::uint16_t* summed_costs_row(int i) const { return sum_.get() + row(i, cost_stride_); }
  // Predecessor of sample i along direction r in the last aggregate(), -1 = none.
  int predecessor(const SampleLayout& samples, int r, int i) const;

 private:
  static std::size_t row(int i, std::size_t stride) { return static_cast<std::size_t>(i) * stride; }
  struct Worker;
  // The workers' rejection counts, added up as each one finishes.
  struct RejectedSum {
    std::atomic<int> uniqueness{0}, left_right{0};
    void add(const Rejected& r) {
      uniqueness.fetch_add(r.uniqueness, std::memory_order_relaxed);
      left_right.fetch_add(r.left_right, std::memory_order_relaxed);
    }
    Rejected total() const {
      Rejected r;
      r.uniqueness = uniqueness.load();
      r.left_right = left_right.load();
      return r;
    }
  };
  // The winner of each sample of a row, uniqueness, and the left-right check
  // from the summed costs once the row is complete (docs/model.md section 6).
  // Samples are offered left to right between begin_row and end_row.
  class RowDecider {
   public:
    RowDecider(const PathMatcher& pm, const SampleLayout& samples, Worker& wk, std::int16_t* disp_q4,
               std::uint8_t* confidence);
    // Every sample of image row y from its complete S.
    void row(int y);
    void begin_row(int y);
    void sample(int i, const std::uint16_t* total);  // S(i, .)
    void end_row();
    Rejected rejected;

   private:
    static constexpr std::uint16_t kNoWinner = 0xFFFF;  // row_k of a sample uniqueness rejected
    const PathMatcher& pm_;
    const SampleLayout& samples_;
    Worker& wk_;
    std::int16_t* disp_q4_;
    std::uint8_t* confidence_;
    bool lr_;
    int v0_ = 0, v1_ = 0;
  };
  // Returns the largest id distance of a mesh edge between two rows.
  int find_predecessors(const SampleLayout& samples);
  void check_reach(int reach) const;
  // How a pass is cut into tiles this frame (plan_pass()).
  struct PassPlan {
    bool forward = true;
    int rows_per_band = 1;  // R
    int block = 32;         // B: tile width in pixels along the pass
    int shear = 0;          // pixels the tile borders move back per row of a band
    int bands = 0, cols = 0, lead = 0, in_flight = 1;
    int ring_n = 1;         // ring slots this frame: sample i is slot i mod ring_n
  };
  // The predecessors' extent this frame (predecessor_offers.hpp): a dense
  // frame's by rule, a mesh's by a scan of preds_.
  PredecessorBounds predecessor_bounds(const SampleLayout& samples) const;
  PassPlan plan_pass(const SampleLayout& samples, bool forward, int workers) const;
  // The image rows [*y0, *y1) of a pass's band (bands are the same rows in
  // both passes: band j = rows [j R, j R + R), the backward pass's k-th band
  // is j = bands - 1 - k).
  static void band_rows(const PassPlan& plan, int band, int height, int* y0, int* y1);
  // Tile (band, col) of a pass; `add`: S holds the other pass's sums.
  void run_tile(const SampleLayout& samples, ImageView<const std::uint8_t> left_gray, const PassPlan& plan,
                int band, int col, int worker, int add);
  // aggregate(), deciding the rows on the way when disp_q4 is given.
  Rejected aggregate_rows(const SampleLayout& samples, ImageView<const std::uint8_t> left_gray,
                          ThreadPool& pool, std::int16_t* disp_q4, std::uint8_t* confidence);

  StereoParams params_;
  const KernelSet* kernels_ = nullptr;
  int max_samples_ = 0;
  int num_disp_ = 0;
  int directions_ = 0;
  std::size_t cost_stride_ = 0;   // C and S rows
  std::size_t path_stride_ = 0;   // L rows: guard, D values, guard
  std::vector<std::uint32_t> p1_by_gap_, p2_by_gap_;
  // When P1 and P2 do not depend on the gap (gap policy const): P2 after the
  // edge rule for each |I(p) - I(q)|, so a step needs no division.
  bool penalties_by_gap_ = true;
  std::uint16_t p2_by_diff_[256] = {};
  std::size_t costs_len_ = 0, preds_len_ = 0;
  int max_width_ = 0;
  std::size_t ring_len_ = 0;  // per worker: window_h x max_width x cost_stride_ (census only)
  // The census box sums in bytes: descriptor bits x window pixels <= 255, so
  // no per-pixel cost nor window sum exceeds a byte (census only).
  bool byte_costs_ = false;
  // C holds those byte sums, not their Q4 means (configure: when every box
  // size has a 15-bit reciprocal that gives the means, src/cost/byte_means.hpp;
  // inv_pixels_q15_ by box pixel count); the path kernels take the means.
  bool c_sums_u8_ = false;
  std::size_t box_pixels(const SampleLayout& samples, int x, int y) const;
  std::vector<std::uint16_t> inv_pixels_q15_;
  LargeArray<std::uint16_t> costs_;
  LargeArray<std::int32_t> preds_;  // 6 diagonal/vertical directions x samples
  std::vector<std::uint16_t> zero_path_;   // a path start: zeros between 0xFFFF guards
  // The directions run in two passes, forward (raster order: the even
  // directions) and backward (the odd ones), at the same time; a pass steps
  // every direction at each sample while its costs and sums are in cache. L_r
  // of a vertical or diagonal direction is kept until no later sample can need
  // it, in each pass's rings: path_rings_[pass][j] (direction 2 (j + 1) +
  // pass) and path_mins_ (the minimum of each L_r) hold ring_capacity_
  // samples, of which a frame uses plan.ring_n (sample i is slot i mod
  // ring_n): enough for the rows of the bands under way plus the rows their
  // predecessors reach up.
  std::vector<LargeArray<std::uint16_t>> path_rings_[2], path_mins_[2];
  int ring_capacity_ = 0;
  int reach_ = 0;                    // find_predecessors' reach for preds_for_
  const Mesh* preds_for_ = nullptr;  // the mesh whose predecessors preds_ holds (this frame)
  const Mesh* supplied_for_ = nullptr;  // use_predecessors(): filled by the mesher, for this mesh
  int supplied_reach_ = 0;
  PredecessorBounds supplied_bounds_;
  PredecessorBounds bounds_;          // of preds_for_ (compute_costs)
  std::atomic<int> side_next_{0};
  // The horizontal path where a row leaves one tile for the next: per band
  // under way (band mod in_flight) and row of the band, the last L_0/L_1 (with
  // guards), its minimum, the next sample and the last sample's x and I.
  struct RowCarry {
    int next = 0;
    int hq_x = -1, hq_i = 0;
    std::uint16_t min = 0;
  };
  static constexpr int kMaxRowsPerBand = 2;  // plan_pass: bands of 2 rows from 3 workers on
  int max_rows_per_band_ = 1;  // what configure() sized for
  int max_in_flight_ = 1;
  int schedule_workers_ = 1;  // plan_pass's worker count
  std::vector<RowCarry> carry_[2];
  std::vector<std::uint16_t> carry_paths_[2];
  Wavefront wavefront_[2];
  // Per band of image rows: the pass that started it first (-1: none yet);
  // the other pass starts it once the first has done it, and adds to S.
  std::unique_ptr<std::atomic<int>[]> band_first_;
  FrameTrace* trace_ = nullptr;
  // S: in each band, the pass that comes first writes it, the other adds to it.
  LargeArray<std::uint16_t> sum_;
  struct Worker {
    // L_r of the horizontal direction: the previous sample's and this one's.
    std::unique_ptr<std::uint16_t[]> row_path;
    CostScratch scratch;
    std::vector<std::uint16_t> total;
    // Census costs by rows (compute_costs): window_h rows of per-pixel costs,
    // their column sums, and which image row each ring slot holds.
    // u16 elements, or bytes (byte_costs_) in the first half.
    LargeArray<std::uint16_t> pixel_rows;
    LargeArray<std::uint16_t> column_sums;
    std::vector<int> slot_row;
    // Left-right check from S (select): the right view's running winner per
    // right pixel of the row (index W - 1 - xr + ... see select), and each
    // sample's k.
    std::vector<std::uint16_t> lr_cost, lr_k, row_k;
  };
  std::vector<Worker> workers_;
  template <class T>
  void census_costs_by_rows(const MatchContext& ctx, const SampleLayout& samples, Worker& wk, int y0, int y1);
  WorkChunks rows_;
  HomeChunks row_homes_;  // census costs by rows: chunks of 16 rows
};

}  // namespace tristereo
