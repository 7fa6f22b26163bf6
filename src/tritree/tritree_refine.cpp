// Tritree refinement: rounds of criterion evaluation (parallelisable) and
// longest-edge-propagation bisection (serial), docs/model.md section 1.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <thread>
#include <utility>

#include "platform/thread_pool.hpp"

#include "src/tritree/tritree.hpp"
#include "src/tritree/tritree_criterion.hpp"
#include "src/tritree/tritree_geometry.hpp"

namespace tristereo {

namespace {

// Entries a helper takes at a time while the split is producing them: small,
// so helpers follow the producer closely and the tail at the end of a round
// is short. Scheduling cannot change any decision (each depends only on its
// own triangle and the image).
constexpr int kChunk = 64;
// While the split runs, helpers stay this many entries behind the newest one:
// the producer is still writing those cache lines (created_, and the nodes
// the helpers' liveness check reads), and some of those triangles are split
// again within the round, which the lag lets the check catch. At the end of a
// round (drain) they take everything.
constexpr int kLag = 2048;

inline void cpu_relax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__) || defined(__arm__)
  asm volatile("yield" ::: "memory");
#endif
}

}  // namespace

void Tritree::build(ImageView<const std::uint8_t> gray, Mesh& mesh, ThreadPool* pool) {
  begin(gray);
  if (pool != nullptr && pool->size() > 1) {
    run_overlapped(*pool);
    finish_parallel(mesh, *pool);
    return;
  }
  while (pending_count() > 0) {
    evaluate_round(0, pending_count());
    split_round();
  }
  finish(mesh);
}

// One pool run for all rounds. Worker 0 runs the serial part (sort and
// propagation, process_order) and publishes every triangle it creates; the
// other workers evaluate the published triangles meanwhile, so the next
// round's criterion overlaps this round's propagation instead of following
// it, and the pool is woken once per build instead of once per round. A
// triangle that is split again later in the same round is evaluated for
// nothing (or skipped when a helper sees it is gone); the liveness check
// before sorting drops it either way. Before each split, worker 0 helps with
// what is left and waits until every entry has its decision.
void Tritree::run_overlapped(ThreadPool& pool) {
  claimed_.store(0, std::memory_order_relaxed);
  evaluated_.store(0, std::memory_order_relaxed);
  published_.store(created_count_, std::memory_order_release);
  split_done_.store(false, std::memory_order_relaxed);
  drain_.store(true, std::memory_order_relaxed);
  pool.run([&](int worker) {
    if (worker != 0) {
      int idle = 0;
      for (;;) {
        if (claim_and_evaluate(kChunk, /*skip_dead=*/true)) {
          idle = 0;
          continue;
        }
        if (split_done_.load(std::memory_order_acquire)) return;
        // Let the producer's core go when it is shared (busy machines).
        if (++idle < 256) {
          cpu_relax();
        } else {
          std::this_thread::yield();
        }
      }
    }
    // Worker 0: a task that throws must still release the helpers.
    struct Release {
      std::atomic<bool>* flag;
      ~Release() { flag->store(true, std::memory_order_release); }
    } release{&split_done_};
    // Rounds are ranges of created_ here: begin()'s pending list (the two
    // roots, entries 0 and 1) is not used, and no pending list is built.
    round_begin_ = 0;
    for (;;) {
      drain_.store(true, std::memory_order_relaxed);
      while (claim_and_evaluate(kChunk, /*skip_dead=*/true)) {
      }
      // A helper may still be inside its last chunk (or preempted in it).
      for (int spin = 0; evaluated_.load(std::memory_order_acquire) < created_count_; ++spin) {
        if (spin < 256) {
          cpu_relax();
        } else {
          std::this_thread::yield();
        }
      }
      drain_.store(false, std::memory_order_relaxed);
      const std::int32_t b = round_begin_;
      const std::int32_t e = created_count_;
      // A round that created anything leaves its last children alive, so an
      // empty range is exactly split_round()'s empty pending list.
      if (b == e) break;
      round_begin_ = e;
      int count = 0;
      for (std::int32_t i = b; i < e; ++i) {
        // Only the entries that want to split are checked for liveness:
        // cheaper than promote_created() over all of them.
        if (decision_[i] && nodes_[created_[i].slot].birth == created_[i].birth) order_[count++] = key_[i];
      }
      process_order(count);
    }
    pending_count_ = 0;
  });
}

// Takes up to `chunk` published entries and evaluates them. False when
// nothing published is left to take.
bool Tritree::claim_and_evaluate(int chunk, bool skip_dead) {
  std::int32_t b = claimed_.load(std::memory_order_relaxed);
  for (;;) {
    const std::int32_t published = published_.load(std::memory_order_acquire);
    const std::int32_t limit =
        drain_.load(std::memory_order_relaxed) ? published : published - kLag;
    if (b >= limit) return false;
    const std::int32_t e = std::min(limit, b + chunk);
    if (claimed_.compare_exchange_weak(b, e, std::memory_order_relaxed)) {
      for (std::int32_t i = b; i < e; ++i) {
        // Births are unique, so a slot that shows another birth means the
        // triangle is gone for good; one that still shows it may die later,
        // which only wastes this evaluation.
        const Created& c = created_[i];
        if (skip_dead && __atomic_load_n(&nodes_[c.slot].birth, __ATOMIC_RELAXED) != c.birth) {
          decision_[i] = 0;
        } else {
          evaluate_created(i);
        }
      }
      evaluated_.fetch_add(e - b, std::memory_order_release);
      return true;
    }
  }
}

void Tritree::begin(ImageView<const std::uint8_t> gray) {
  validate_image(gray);
  gray_ = gray;
  rounds_ = 0;
  next_birth_ = 0;
  forced_splits_ = 0;
  criterion_splits_ = 0;
  node_count_ = 2;
  created_count_ = 0;
  round_begin_ = 0;
  pending_count_ = 0;
  const int xr = gray.width - 1;
  const int yb = gray.height - 1;
  // The two roots share the diagonal (0,0)-(W-1,H-1): edge 2 of root 0 is
  // edge 0 of root 1.
  set_node(0, {0, 0}, {xr, 0}, {xr, yb}, -1, -1, 1);
  set_node(1, {0, 0}, {xr, yb}, {0, yb}, 0, -1, -1);
  promote_created();
}

// The decision of one created triangle; reads only the entry and the image.
void Tritree::evaluate_created(int index) {
  const Created& t = created_[index];
  const int k = t.longest;
  const int k1 = k == 2 ? 0 : k + 1;
  const int k2 = k == 0 ? 2 : k - 1;
  const Vertex a{t.x[k], t.y[k]}, b{t.x[k1], t.y[k1]}, c{t.x[k2], t.y[k2]};
  // Cheap validity first: a triangle whose own bisection is invalid never splits.
  const bool split = half_bisection_valid(a, b, c, snapped_midpoint(a, b)) &&
                     tritree_wants_split(gray_, a, b, c, params_.max_area_px2, mse_q8_);
  decision_[index] = split ? 1 : 0;
  if (split) {
    // The processing-order key, computed here because this part runs in parallel.
    std::uint32_t key[3];
    for (int j = 0; j < 3; ++j) key[j] = static_cast<std::uint32_t>(vertex_key(Vertex{t.x[j], t.y[j]}));
    if (key[0] > key[1]) std::swap(key[0], key[1]);
    if (key[1] > key[2]) std::swap(key[1], key[2]);
    if (key[0] > key[1]) std::swap(key[0], key[1]);
    key_[index] = OrderKey{(std::uint64_t{key[0]} << 32) | key[1], key[2], index};
  }
}

void Tritree::evaluate_round(int begin, int end) {
  for (int i = begin; i < end; ++i) evaluate_created(pending_[i]);
}

void Tritree::split_round() {
  int count = 0;
  for (int i = 0; i < pending_count_; ++i) {
    const std::int32_t c = pending_[i];
    if (decision_[c]) order_[count++] = key_[c];
  }
  process_order(count);
  promote_created();
}

// Sorts order_[0, count) and refines each triangle in that order.
void Tritree::process_order(int count) {
  sort_order(count);
  for (int i = 0; i < count; ++i) {
    const Created& p = created_[order_[i].created];
    process(p.slot, p.birth);
    // Hand the triangles created so far to the helpers (if any are running).
    published_.store(created_count_, std::memory_order_release);
  }
  ++rounds_;
}

// Sorts order_[0, count) by order_less. Distinct leaves have distinct vertex
// sets, so the order is strict and any correct sort gives the same sequence.
// LSD counting sort on the smallest vertex key (x, then y: both < max side),
// then an insertion sort of the short runs sharing that vertex; this replaced
// a comparison sort that cost about as much as all the bisections.
void Tritree::sort_order(int count) {
  if (count < 64) {
    std::sort(order_.begin(), order_.begin() + count, order_less);
    return;
  }
  const int w = gray_.width;
  const int h = gray_.height;
  std::int32_t* cnt = radix_count_.data();
  OrderKey* src = order_.data();
  OrderKey* tmp = order_tmp_.data();
  // Smallest vertex key = k01 >> 32 = (y << 16) | x.
  std::fill(cnt, cnt + w + 1, 0);
  for (int i = 0; i < count; ++i) ++cnt[((src[i].k01 >> 32) & 0xFFFF) + 1];
  for (int x = 0; x < w; ++x) cnt[x + 1] += cnt[x];
  for (int i = 0; i < count; ++i) tmp[cnt[(src[i].k01 >> 32) & 0xFFFF]++] = src[i];
  std::fill(cnt, cnt + h + 1, 0);
  for (int i = 0; i < count; ++i) ++cnt[(tmp[i].k01 >> 48) + 1];
  for (int y = 0; y < h; ++y) cnt[y + 1] += cnt[y];
  for (int i = 0; i < count; ++i) src[cnt[tmp[i].k01 >> 48]++] = tmp[i];
  // Runs with the same smallest vertex: a vertex's fan, a handful of triangles.
  int run = 0;
  for (int i = 1; i <= count; ++i) {
    if (i < count && (src[i].k01 >> 32) == (src[run].k01 >> 32)) continue;
    for (int j = run + 1; j < i; ++j) {
      const OrderKey key = src[j];
      int k = j;
      for (; k > run && order_less(key, src[k - 1]); --k) src[k] = src[k - 1];
      src[k] = key;
    }
    run = i;
  }
}

// Next round's pending list: the triangles created since the last call that
// still exist (a child may already have been split again in the same round).
void Tritree::promote_created() {
  pending_count_ = 0;
  for (std::int32_t i = round_begin_; i < created_count_; ++i) {
    if (nodes_[created_[i].slot].birth == created_[i].birth) pending_[pending_count_++] = i;
  }
  round_begin_ = created_count_;
}

void Tritree::set_node(std::int32_t slot, const Vertex& a, const Vertex& b, const Vertex& c,
                       std::int32_t nab, std::int32_t nbc, std::int32_t nca) {
  Node& n = nodes_[slot];
  Created& e = created_[created_count_++];
  const Vertex v[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    n.x[i] = e.x[i] = static_cast<std::int16_t>(v[i].x);
    n.y[i] = e.y[i] = static_cast<std::int16_t>(v[i].y);
  }
  n.nb[0] = nab;
  n.nb[1] = nbc;
  n.nb[2] = nca;
  const std::uint32_t birth = next_birth_++;
  // Helpers read births concurrently (run_overlapped); a relaxed atomic store
  // is a plain store on every target.
  __atomic_store_n(&n.birth, birth, __ATOMIC_RELAXED);
  n.longest = e.longest = static_cast<std::uint8_t>(longest_edge_index(v));
  n.blocked = 0;
  e.slot = slot;
  e.birth = birth;
}

void Tritree::replace_link(std::int32_t slot, std::int32_t old_nb, std::int32_t new_nb) {
  if (slot < 0) return;
  Node& n = nodes_[slot];
  for (int i = 0; i < 3; ++i) {
    if (n.nb[i] == old_nb) {
      n.nb[i] = new_nb;
      return;
    }
  }
  assert(false && "neighbour links out of sync");
}

// Bisects leaf t on its longest edge AB together with n (the neighbour across
// AB, whose longest edge is AB too), or alone when AB is on the border (n < 0).
// Returns false, changing nothing, when any child would have area2 < 2.
bool Tritree::bisect_pair(std::int32_t t, std::int32_t n) {
  const Node& nt = nodes_[t];
  const int k = nt.longest;
  const Vertex a = vertex(nt, k), b = vertex(nt, (k + 1) % 3), c = vertex(nt, (k + 2) % 3);
  const std::int32_t n_bc = nt.nb[(k + 1) % 3];
  const std::int32_t n_ca = nt.nb[(k + 2) % 3];
  const Vertex m = snapped_midpoint(a, b);
  if (!half_bisection_valid(a, b, c, m)) return false;

  Vertex d{};
  std::int32_t n_ad = -1, n_db = -1;
  if (n >= 0) {
    // n = (B, A, D) rotated so that its edge 0 is BA; the shared edge is n's longest.
    const Node& nn = nodes_[n];
    const int j = nn.longest;
    assert(nn.nb[j] == t);
    d = vertex(nn, (j + 2) % 3);
    n_ad = nn.nb[(j + 1) % 3];
    n_db = nn.nb[(j + 2) % 3];
    if (!half_bisection_valid(b, a, d, m)) return false;
  }

  const std::int32_t t2 = node_count_++;
  const std::int32_t n1 = (n >= 0) ? node_count_++ : -1;
  assert(static_cast<std::size_t>(node_count_) <= nodes_.size());
  set_node(t, a, m, c, n, t2, n_ca);    // (A, M, C) keeps t's slot
  set_node(t2, m, b, c, n1, n_bc, t);   // (M, B, C)
  replace_link(n_bc, t, t2);
  if (n >= 0) {
    set_node(n, m, a, d, t, n_ad, n1);  // (M, A, D) keeps n's slot
    set_node(n1, b, m, d, t2, n, n_db); // (B, M, D)
    replace_link(n_db, n, n1);
  }
  return true;
}

// Longest-edge propagation from `slot` until the triangle (identified by its
// birth) has been bisected or a terminal bisection turns out invalid.
void Tritree::process(std::int32_t slot, std::uint32_t birth) {
  while (nodes_[slot].birth == birth) {
    std::int32_t x = slot;
    std::int32_t n = nodes_[x].nb[nodes_[x].longest];
    // Each step goes to a strictly longer edge (model's edge order): terminates.
    while (n >= 0 && nodes_[n].nb[nodes_[n].longest] != x) {
      x = n;
      n = nodes_[x].nb[nodes_[x].longest];
    }
    if (!bisect_pair(x, n)) {
      nodes_[slot].blocked = 1;
      return;
    }
    // The processed triangle's own split is a criterion split; every other
    // split only keeps the mesh conforming.
    const int pair_size = (n >= 0) ? 2 : 1;
    if (x == slot) {
      criterion_splits_ += 1;
      forced_splits_ += pair_size - 1;
    } else {
      forced_splits_ += pair_size;
    }
  }
}

std::vector<std::array<Vertex, 3>> Tritree::blocked_leaves() const {
  std::vector<std::array<Vertex, 3>> out;
  for (std::int32_t i = 0; i < node_count_; ++i) {
    const Node& n = nodes_[i];
    if (n.blocked) out.push_back({vertex(n, 0), vertex(n, 1), vertex(n, 2)});
  }
  return out;
}

}  // namespace tristereo
