// Tritree refinement: rounds of criterion evaluation (parallelisable) and
// longest-edge-propagation bisection (serial), docs/model.md section 1.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <utility>

#include "platform/thread_pool.hpp"

#include "src/tritree/tritree.hpp"
#include "src/tritree/tritree_criterion.hpp"
#include "src/tritree/tritree_geometry.hpp"

namespace tristereo {

namespace {

// Rounds with fewer pending triangles run on the calling thread: waking the
// pool costs more than evaluating them. Any value gives the same mesh.
constexpr int kMinParallelPending = 512;
// Work is handed out in chunks of this many pending triangles (an atomic
// counter balances the uneven cost of triangles; each decision depends only
// on its own triangle, so scheduling cannot change the result).
constexpr int kChunk = 256;

}  // namespace

void Tritree::build(ImageView<const std::uint8_t> gray, Mesh& mesh, ThreadPool* pool) {
  begin(gray);
  const int workers = (pool != nullptr) ? pool->size() : 1;
  while (pending_count() > 0) {
    const int n = pending_count();
    if (workers > 1 && n >= kMinParallelPending) {
      std::atomic<int> next{0};
      pool->run([&](int) {
        for (int b = next.fetch_add(kChunk, std::memory_order_relaxed); b < n;
             b = next.fetch_add(kChunk, std::memory_order_relaxed)) {
          evaluate_round(b, std::min(n, b + kChunk));
        }
      });
    } else {
      evaluate_round(0, n);
    }
    split_round();
  }
  finish(mesh);
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
  pending_count_ = 0;
  const int xr = gray.width - 1;
  const int yb = gray.height - 1;
  // The two roots share the diagonal (0,0)-(W-1,H-1): edge 2 of root 0 is
  // edge 0 of root 1.
  set_node(0, {0, 0}, {xr, 0}, {xr, yb}, -1, -1, 1);
  set_node(1, {0, 0}, {xr, yb}, {0, yb}, 0, -1, -1);
  promote_created();
}

void Tritree::evaluate_round(int begin, int end) {
  for (int i = begin; i < end; ++i) {
    const Node& t = nodes_[pending_[i].slot];
    const int k = t.longest;
    const Vertex a = vertex(t, k), b = vertex(t, (k + 1) % 3), c = vertex(t, (k + 2) % 3);
    // Cheap validity first: a triangle whose own bisection is invalid never splits.
    const bool split = half_bisection_valid(a, b, c, snapped_midpoint(a, b)) &&
                       tritree_wants_split(gray_, a, b, c, params_.max_area_px2, mse_q8_);
    decision_[i] = split ? 1 : 0;
    if (split) {
      // The processing-order key, computed here because this part runs in parallel.
      std::uint32_t key[3];
      for (int j = 0; j < 3; ++j) key[j] = static_cast<std::uint32_t>(vertex_key(vertex(t, j)));
      if (key[0] > key[1]) std::swap(key[0], key[1]);
      if (key[1] > key[2]) std::swap(key[1], key[2]);
      if (key[0] > key[1]) std::swap(key[0], key[1]);
      key_[i] = OrderKey{(std::uint64_t{key[0]} << 32) | key[1], key[2], i};
    }
  }
}

void Tritree::split_round() {
  int count = 0;
  for (int i = 0; i < pending_count_; ++i) {
    if (decision_[i]) order_[count++] = key_[i];
  }
  sort_order(count);
  for (int i = 0; i < count; ++i) {
    const Pending& p = pending_[order_[i].pending_index];
    process(p.slot, p.birth);
  }
  ++rounds_;
  promote_created();
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
  for (int i = 0; i < created_count_; ++i) {
    if (nodes_[created_[i].slot].birth == created_[i].birth) pending_[pending_count_++] = created_[i];
  }
  created_count_ = 0;
}

void Tritree::set_node(std::int32_t slot, const Vertex& a, const Vertex& b, const Vertex& c,
                       std::int32_t nab, std::int32_t nbc, std::int32_t nca) {
  Node& n = nodes_[slot];
  const Vertex v[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    n.x[i] = static_cast<std::int16_t>(v[i].x);
    n.y[i] = static_cast<std::int16_t>(v[i].y);
  }
  n.nb[0] = nab;
  n.nb[1] = nbc;
  n.nb[2] = nca;
  n.birth = next_birth_++;
  n.longest = static_cast<std::uint8_t>(longest_edge_index(v));
  n.blocked = 0;
  created_[created_count_++] = Pending{slot, n.birth};
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
