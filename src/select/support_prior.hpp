// The support prior in the winner selection (docs/model.md section 6b).
//
// After the matcher (winner, uniqueness, left-right check from the summed
// costs), before the fill:
//  1. support: samples measured with a confidence >= support_conf;
//  2. planes: on each of two segment levels (mesh edges with |dI| <=
//     seg_fine, then seg_coarse), a robust integer least-squares plane
//     through the support of each segment; where it is well supported, it
//     gives every other sample of the segment not yet covered its prior;
//  3. pass 2: each non-support sample with a prior takes the smallest argmin
//     of S'(k) = S(k) + lambda min(|k - k_prior|, trunc), subject to a
//     uniqueness test on S' (rejected: invalid, for the fill).
// The segments' planes and pass 2 are shared by the pool's workers (each
// segment and each sample writes only its own values: the result is the
// same for any pool); the rest runs on the calling thread. Every buffer is
// sized at configure().
#pragma once

#include <cstdint>
#include <vector>

#include "src/aggregate/path_matcher.hpp"
#include "src/aggregate/samples.hpp"
#include "src/select/plane_fit.hpp"
#include "platform/work_chunks.hpp"
#include "src/memory/large_array.hpp"
#include "tristereo/image.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

class ThreadPool;
class FrameTrace;
enum class TraceKind : std::uint8_t;
struct KernelSet;

struct SupportPriorCounts {
  int support = 0;     // support samples
  int redecided = 0;   // non-support samples whose winner was chosen again
  int rejected = 0;    // of those, rejected by the uniqueness test on S' (invalid)
  int planes = 0;      // segments given a plane
  int recovered = 0;   // of the re-decided, invalid before and valid after
  int lost = 0;        // of the re-decided, valid before and invalid after
};

class SupportPrior {
 public:
  // For up to `workers` workers of a pool; schedule_workers (0: workers)
  // is the count the work is cut for (a one-worker trace cut for N).
  void configure(int max_samples, int max_triangles, int max_disp, int workers = 1, int schedule_workers = 0);
  // Gives every buffer back (a pipeline reconfigured without the prior).
  void release();
  // disp_q4 / confidence: the matcher's outputs, changed in place.
  // pool (optional; called from its owner thread): shares the work.
  SupportPriorCounts apply(const StereoParams& params, const SampleLayout& samples, const PathMatcher& pm,
                           ImageView<const std::uint8_t> left, std::int16_t* disp_q4, std::uint8_t* confidence,
                           const KernelSet& kernels, ThreadPool* pool = nullptr, FrameTrace* trace = nullptr);
  std::size_t working_memory_bytes() const { return bytes_; }

 private:
  int find(int a);
  void unite(int a, int b, bool shared);
  // One segment level with threshold tau: planes for its well-supported
  // segments. joined >= 0: parent_ already holds the segments of threshold
  // joined <= tau (the previous level's), and the triangles' edge bits in
  // next_ say which of their edges the level joins. next >= tau: a next
  // level of threshold next follows; this one writes those bits for it.
  void planes(const StereoParams& params, const SampleLayout& samples, const std::int16_t* disp, int tau, int joined,
              int next, ThreadPool* pool, FrameTrace* trace);
  // body(worker, j0, j1) over [0, n) in chunks, on the pool's workers (up to
  // the configured count) from two chunks up, else chunk by chunk here; each
  // call recorded in the trace as `kind` (a = j0, b = j1, c = tag).
  template <class Body>
  void for_chunks(ThreadPool* pool, FrameTrace* trace, TraceKind kind, int tag, int n, int chunk, Body body);

  // A sample's pixel (< 4096), disparity (Q4) and flags (1 support, 2
  // covered by a plane), together: a segment's members are far apart.
  struct Member {
    std::int16_t x, y, d;
    std::uint8_t flags;
  };
  struct FitPoint {
    std::int16_t x, y, d;  // a support sample's pixel (< 4096) and disparity (Q4)
  };

  struct Census {  // of a segment's members
    int support = 0;
    bool other = false;  // a member neither support nor covered
  };
  struct Residuals {  // of a segment's support points from its last plane
    std::int64_t inliers = 0, sq = 0;
  };
  std::size_t bytes_ = 0;
  int n_ = 0;
  LargeArray<std::int16_t> prior_;  // Q4, within the disparity range
  LargeArray<std::int32_t> parent_, count_, order_;
  LargeArray<std::uint8_t> inten_;
  LargeArray<Member> members_;
  LargeArray<std::uint8_t> next_;           // per triangle: bit e, its edge e joins at the next level
  LargeArray<FitPoint> fit_;                // a segment's support points
  std::vector<std::uint16_t> s2_;                    // S' of one sample (saturated), per worker
  std::vector<std::uint16_t> penalty_;               // lambda min(|j|, T) saturated, j = 1 - D .. D - 1
  std::vector<SupportPriorCounts> worker_counts_;   // per worker
  WorkChunks chunks_;
  // The segments of at least kBigSegment samples (roots), fitted apart.
  std::vector<std::int32_t> big_;
  int n_big_ = 0;
  std::vector<int> big_points_;            // support points per chunk of members
  std::vector<Census> big_census_;         // per worker
  std::vector<PlaneSums> big_sums_;        // per worker
  std::vector<Residuals> big_residuals_;   // per worker
  int max_disp_ = 0;
  // From kSharedSortWorkers (scheduled) workers on, the members' counting
  // sort and the list of samples decided again are shared too.
  bool shared_sort_ = false;
  std::vector<std::int32_t> redo_at_;  // per chunk of samples: its first slot in the list
};

}  // namespace tristereo
