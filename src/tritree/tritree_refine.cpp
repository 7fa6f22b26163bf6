// Tritree refinement: rounds of criterion evaluation and longest-edge
// propagation, run per spatial region (docs/model.md section 1, docs/tritree.md).
//
// Why regions give the reference's mesh: a triangle's children, its longest
// edge and its split decision depend only on the triangle (and the image), and
// processing a triangle performs a fixed sequence of bisections (its
// propagation path, cut short where a bisection is invalid). The mesh after a
// round is therefore the union of those sequences whatever the order, and
// workers may process their regions concurrently as long as none writes a node
// it does not own. A propagation that would read or relink another region's
// node is stopped (bisections already done stay; they belong to the sequence
// anyway) and finished by the serial pass at the end of the round.
#include <algorithm>
#include <cassert>

#include "platform/clock.hpp"
#include "platform/thread_pool.hpp"

#include "src/tritree/tritree.hpp"
#include "src/tritree/tritree_criterion.hpp"
#include "src/tritree/tritree_geometry.hpp"

namespace tristereo {

namespace {

// Regions are cut once the mesh has this many leaves per region: the first
// rounds (area-forced splits of a few large triangles) are cheap, and enough
// leaves make regions of nearly equal area.
constexpr std::int32_t kLeavesPerRegion = 64;

// Rounds with fewer new triangles than this run on the calling thread: waking
// the pool costs more. Neither constant changes the mesh.
constexpr std::int32_t kMinParallelCreated = 1024;
// How many list entries ahead the node of an entry is prefetched.
constexpr std::int32_t kPrefetchAhead = 8;

}  // namespace

void Tritree::build(ImageView<const std::uint8_t> gray, Mesh& mesh, ThreadPool* pool) {
  const std::int64_t t_begin = monotonic_ns();
  validate_image(gray);
  times_ = BuildTimes{};
  fell_back_ = false;
  const int workers = (pool != nullptr) ? pool->size() : 1;
  const int want_regions = workers > 1 ? std::min(kRegionsPerWorker * workers, kMaxRegions) : 1;
  if (!refine(gray, pool, want_regions)) {
    // A region ran out of node slots (see partition()); nothing was written
    // outside the tree's own arrays. One region cannot run out, and the mesh
    // does not depend on the regions, so the result is the same, only slower.
    fell_back_ = true;
    refine(gray, nullptr, 1);
  }
  const std::int64_t t_output = monotonic_ns();
  finish(mesh, pool);
  times_.rounds_ns = t_output - t_begin;
  times_.output_ns = monotonic_ns() - t_output;
}

// The refinement rounds; false when a region ran out of node slots (the tree
// is then unusable and must be rebuilt).
bool Tritree::refine(ImageView<const std::uint8_t> gray, ThreadPool* pool, int want_regions) {
  begin(gray);
  const int workers = (pool != nullptr) ? pool->size() : 1;
  for (;;) {
    std::int32_t created = 0;
    for (int g = 0; g < region_count_; ++g) created += regions_[g].created_count;
    if (created == 0) break;
    if (region_count_ == 1 && want_regions > 1 &&
        regions_[0].next_slot >= kLeavesPerRegion * want_regions) {
      partition(want_regions);
    }
    if (region_count_ > 1 && created >= kMinParallelCreated) {
      // Each worker has a home: a contiguous run of regions, the same every
      // round, so a region's nodes stay in the caches of the core that
      // refined it last round. It takes its home regions largest first (by
      // entries to evaluate), then helps the other homes with what is left
      // there, so a slow worker or a heavy home delays the round by about
      // one region.
      region_homes_.reset(region_count_, workers);
      std::int8_t order[kMaxRegions];
      for (int g = 0; g < region_count_; ++g) order[g] = static_cast<std::int8_t>(g);
      for (int h = 0; h < region_homes_.homes(); ++h) {
        int b = 0, e = 0;
        region_homes_.home_range(h, &b, &e);
        std::sort(order + b, order + e, [this](int p, int q) {
          return regions_[p].created_count != regions_[q].created_count
                     ? regions_[p].created_count > regions_[q].created_count
                     : p < q;
        });
      }
      std::atomic<std::int64_t> busy_ns{0};
      const std::int64_t t_round = monotonic_ns();
      pool->run([this, &order, &busy_ns](int worker) {
        const std::int64_t t_worker = monotonic_ns();
        region_homes_.for_each(worker, [this, &order](int i) {
          refine_region(order[i], /*local=*/true);
          merge_deferred(order[i]);
        });
        busy_ns.fetch_add(monotonic_ns() - t_worker, std::memory_order_relaxed);
      });
      times_.round_idle_ns += (monotonic_ns() - t_round) * workers - busy_ns.load(std::memory_order_relaxed);
    } else {
      // Local even here: a region must not split another's triangles before
      // that region has evaluated them (the split counts would differ).
      for (int g = 0; g < region_count_; ++g) refine_region(g, /*local=*/region_count_ > 1);
      process_deferred(0, region_count_);
    }
    if (out_of_slots_.load(std::memory_order_relaxed)) return false;
    ++rounds_;
  }
  return true;
}

std::int64_t Tritree::deferred_propagations() const {
  std::int64_t sum = 0;
  for (int g = 0; g < region_count_; ++g) sum += regions_[g].deferred;
  return sum;
}

void Tritree::begin(ImageView<const std::uint8_t> gray) {
  gray_ = gray;
  out_of_slots_.store(false, std::memory_order_relaxed);
  rounds_ = 0;
  criterion_splits_ = 0;
  forced_splits_ = 0;
  initial_slots_ = 0;
  initial_vertices_ = 0;
  region_count_ = 1;
  Region& r = regions_[0];
  r = Region{};
  r.slot_end = static_cast<std::int32_t>(nodes_.size());
  r.list_capacity = static_cast<std::int32_t>(created_.size());
  const int xr = gray.width - 1;
  const int yb = gray.height - 1;
  // The two roots share the diagonal (0,0)-(W-1,H-1): edge 2 of root 0 is
  // edge 0 of root 1.
  r.next_slot = 2;
  nodes_[0].region = nodes_[1].region = 0;
  set_node(0, {0, 0}, {xr, 0}, {xr, yb}, -1, -1, 1);
  set_node(1, {0, 0}, {xr, yb}, {0, yb}, 0, -1, -1);
}

// One round of one region: promote the triangles created last round, decide
// each, then process those that split. With `local`, propagations that would
// touch another region are left in the pending list (deferred).
void Tritree::refine_region(int g, bool local) {
  Region& r = regions_[g];
  Pending* pending = pending_.data() + r.list_begin;
  const Pending* created = created_.data() + r.list_begin;
  const std::int32_t created_count = r.created_count;
  r.created_count = 0;

  // One pass: drop entries whose triangle was split again in the round that
  // created it, decide the others. The lists visit slots in creation order,
  // scattered over the node array, so nodes are prefetched a few entries ahead
  // (the node loads were half of this loop's time).
  std::int32_t splitting = 0;
  for (std::int32_t i = 0; i < created_count; ++i) {
    if (i + kPrefetchAhead < created_count) prefetch_node(created[i + kPrefetchAhead].slot);
    Node& t = nodes_[created[i].slot];
    if (t.birth != created[i].birth) continue;
    const int k = t.longest;
    const Vertex a = vertex(t, k), b = vertex(t, (k + 1) % 3), c = vertex(t, (k + 2) % 3);
    // Cheap validity first: a triangle whose own bisection is invalid never splits.
    if (half_bisection_valid(a, b, c, snapped_midpoint(a, b)) &&
        tritree_wants_split(gray_, a, b, c, params_.max_area_px2, mse_q8_)) {
      t.wants = 1;
      pending[splitting++] = created[i];
    }
  }

  std::int32_t deferred = 0;
  for (std::int32_t i = 0; i < splitting; ++i) {
    // Two stages: the node, then (its line having arrived) the neighbour
    // across its longest edge, where the propagation goes first.
    if (i + 2 * kPrefetchAhead < splitting) prefetch_node(pending[i + 2 * kPrefetchAhead].slot);
    if (i + kPrefetchAhead < splitting) {
      const Node& ahead = nodes_[pending[i + kPrefetchAhead].slot];
      const std::int32_t nb = ahead.nb[ahead.longest];
      if (nb >= 0) prefetch_node(nb);
    }
    const int lo = local ? g : 0, hi = local ? g + 1 : region_count_;
    if (!process(pending[i].slot, pending[i].birth, lo, hi)) pending[deferred++] = pending[i];
  }
  r.pending_count = deferred;
  r.deferred += deferred;
}

// Called by the worker that refined region g this round. Walks up the merge
// tree: at each level, the first of a group's two halves to finish stops
// there; the second finishes the group's deferred propagations, now free to
// touch the whole group. Why this is safe: a group's regions are done with
// the round (their evaluations included, so split counts are unaffected) and
// no other worker touches them until the round ends; disjoint groups run
// concurrently. The top group is every region, so the round ends with nothing
// deferred.
void Tritree::merge_deferred(int g) {
  for (int level = 1; level < kMergeLevels; ++level) {
    const int lo = (g >> level) << level;
    const int mid = lo + (1 << (level - 1));
    const int hi = std::min(lo + (1 << level), region_count_);
    if (mid >= hi) continue;  // one half only: nothing new to merge
    std::atomic<int>& arrivals = merge_arrivals_[level][g >> level];
    if (arrivals.fetch_add(1, std::memory_order_acq_rel) == 0) return;
    arrivals.store(0, std::memory_order_relaxed);  // for the next round (run() orders it)
    process_deferred(lo, hi);
  }
}

// Processes the deferred propagations of regions [lo, hi) within that
// territory, keeping those that still cross its border.
void Tritree::process_deferred(int lo, int hi) {
  for (int g = lo; g < hi; ++g) {
    Region& r = regions_[g];
    Pending* pending = pending_.data() + r.list_begin;
    std::int32_t kept = 0;
    for (std::int32_t i = 0; i < r.pending_count; ++i) {
      if (!process(pending[i].slot, pending[i].birth, lo, hi)) pending[kept++] = pending[i];
    }
    r.pending_count = kept;
  }
}

// Cuts the current leaves (slots [0, next_slot) of region 0) into stripes
// across the longer image side, of nearly equal area, and gives each region
// node slots and list space for its stripe's refinement: area2 / 2 leaves
// (each leaf has area2 >= 2) plus an equal share of the spare slots. The area
// bound alone is not enough: the floored midpoint snap moves a sliver of area
// across the edge it splits, so when the two triangles of a pair belong to two
// regions, one region's leaves can outgrow its stripe's area. The spare
// covers that in practice; if a region still runs out, build() redoes the
// build on one region (Tritree.RegionOutOfSlotsFallsBackToOneRegion).
void Tritree::partition(int region_count) {
  Region& r0 = regions_[0];
  const std::int32_t n0 = r0.next_slot;
  initial_vertices_ = r0.vertex_count;  // at new_vertices_[0 ..), below slot n0
  criterion_splits_ += r0.criterion_splits;
  forced_splits_ += r0.forced_splits;
  const bool by_x = gray_.width >= gray_.height;
  std::int32_t* order = vertex_id_.data();  // scratch: W x H >= n0 entries each
  std::int32_t* centre3 = bucket_.data();
  std::int64_t total_area2 = 0;
  for (std::int32_t s = 0; s < n0; ++s) {
    const Node& t = nodes_[s];
    centre3[s] = by_x ? t.x[0] + t.x[1] + t.x[2] : t.y[0] + t.y[1] + t.y[2];
    order[s] = s;
    total_area2 += area2_of(vertex(t, 0), vertex(t, 1), vertex(t, 2));
  }
  std::sort(order, order + n0, [centre3](std::int32_t p, std::int32_t q) {
    return centre3[p] != centre3[q] ? centre3[p] < centre3[q] : p < q;
  });
  std::int64_t area2_of_region[kMaxRegions] = {};
  std::int32_t leaves_of_region[kMaxRegions] = {};
  std::int64_t before = 0;
  for (std::int32_t i = 0; i < n0; ++i) {
    const Node& t = nodes_[order[i]];
    const std::int64_t a2 = area2_of(vertex(t, 0), vertex(t, 1), vertex(t, 2));
    const int g = static_cast<int>(
        std::min<std::int64_t>(region_count - 1, (2 * before + a2) * region_count / (2 * total_area2)));
    nodes_[order[i]].region = static_cast<std::uint8_t>(g);
    area2_of_region[g] += a2;
    ++leaves_of_region[g];
    before += a2;
  }

  // The created list of the last round moves to the regions' lists (through
  // the pending list, which is empty between rounds).
  const std::int32_t moved = r0.created_count;
  std::copy(created_.begin(), created_.begin() + moved, pending_.begin());

  std::int64_t area_capacity[kMaxRegions];
  std::int64_t spare = static_cast<std::int64_t>(nodes_.size()) - n0;
  for (int g = 0; g < region_count; ++g) {
    area_capacity[g] = std::max<std::int64_t>(0, area2_of_region[g] / 2 - leaves_of_region[g]);
    spare -= area_capacity[g];
  }
  spare = std::min<std::int64_t>(spare, static_cast<std::int64_t>(spare_limit_));
  std::int32_t slot = n0;
  std::int32_t list = 0;
  for (int g = 0; g < region_count; ++g) {
    const std::int32_t capacity = static_cast<std::int32_t>(area_capacity[g] + spare / region_count);
    Region& r = regions_[g];
    r = Region{};
    r.slot_begin = r.next_slot = slot;
    r.slot_end = slot + capacity;
    r.list_begin = list;
    // Each bisection of a region triangle adds one of its slots and creates two entries.
    r.list_capacity = 2 * capacity + leaves_of_region[g];
    slot += capacity;
    list += r.list_capacity;
  }
  assert(static_cast<std::size_t>(slot) <= nodes_.size());
  assert(static_cast<std::size_t>(list) <= created_.size());
  initial_slots_ = n0;
  region_count_ = region_count;
  for (auto& level : merge_arrivals_) {
    for (auto& arrivals : level) arrivals.store(0, std::memory_order_relaxed);
  }
  for (std::int32_t i = 0; i < moved; ++i) {
    const Pending p = pending_[i];
    if (nodes_[p.slot].birth != p.birth) continue;
    Region& r = regions_[region_of(p.slot)];
    created_[r.list_begin + r.created_count++] = p;
  }
}

// A free slot of the parent's region, or -1 (and out_of_slots_ set) when the
// region has none left.
std::int32_t Tritree::new_slot(std::int32_t parent) {
  const std::uint8_t g = nodes_[parent].region;
  Region& r = regions_[g];
  if (r.next_slot >= r.slot_end) {
    out_of_slots_.store(true, std::memory_order_relaxed);
    return -1;
  }
  const std::int32_t slot = r.next_slot++;
  nodes_[slot].region = g;
  return slot;
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
  ++n.birth;  // per slot: no counter shared between workers
  n.longest = static_cast<std::uint8_t>(longest_edge_index(v));
  n.blocked = 0;
  n.wants = 0;
  Region& r = regions_[region_of(slot)];
  assert(r.created_count < r.list_capacity);
  created_[r.list_begin + r.created_count++] = Pending{slot, n.birth};
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

// A bisected triangle's split is a criterion split when the triangle itself
// was evaluated and wants to split, else a forced (conformity) split.
void Tritree::count_split(std::int32_t slot) {
  Region& r = regions_[region_of(slot)];
  if (nodes_[slot].wants) {
    ++r.criterion_splits;
  } else {
    ++r.forced_splits;
  }
}

// Bisects leaf t on its longest edge AB together with n (the neighbour across
// AB, whose longest edge is AB too), or alone when AB is on the border (n < 0).
// Changes no node when any child would have area2 < 2 (kInvalid) or a region
// has no free slot (kNoSlot).
Tritree::Bisect Tritree::bisect_pair(std::int32_t t, std::int32_t n) {
  const Node& nt = nodes_[t];
  const int k = nt.longest;
  const Vertex a = vertex(nt, k), b = vertex(nt, (k + 1) % 3), c = vertex(nt, (k + 2) % 3);
  const std::int32_t n_bc = nt.nb[(k + 1) % 3];
  const std::int32_t n_ca = nt.nb[(k + 2) % 3];
  const Vertex m = snapped_midpoint(a, b);
  if (!half_bisection_valid(a, b, c, m)) return Bisect::kInvalid;

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
    if (!half_bisection_valid(b, a, d, m)) return Bisect::kInvalid;
  }

  const std::int32_t t2 = new_slot(t);
  const std::int32_t n1 = (n >= 0) ? new_slot(n) : -1;
  if (t2 < 0 || (n >= 0 && n1 < 0)) return Bisect::kNoSlot;
  count_split(t);
  if (n >= 0) count_split(n);
  Region& owner = regions_[region_of(t)];
  new_vertices_[static_cast<std::size_t>(owner.slot_begin + owner.vertex_count++)] = m;
  set_node(t, a, m, c, n, t2, n_ca);    // (A, M, C) keeps t's slot
  set_node(t2, m, b, c, n1, n_bc, t);   // (M, B, C)
  replace_link(n_bc, t, t2);
  if (n >= 0) {
    set_node(n, m, a, d, t, n_ad, n1);  // (M, A, D) keeps n's slot
    set_node(n1, b, m, d, t2, n, n_db); // (B, M, D)
    replace_link(n_db, n, n1);
  }
  return Bisect::kDone;
}

// Longest-edge propagation from `slot` until the triangle (identified by its
// birth) has been bisected or a terminal bisection turns out invalid (then it
// is blocked). Returns false as soon as the next bisection would read or
// relink a node outside regions [lo, hi).
bool Tritree::process(std::int32_t slot, std::uint32_t birth, int lo, int hi) {
  const bool everywhere = lo == 0 && hi >= region_count_;
  const auto outside = [&](std::int32_t s) {
    return static_cast<unsigned>(region_of(s) - lo) >= static_cast<unsigned>(hi - lo);
  };
  while (nodes_[slot].birth == birth) {
    std::int32_t x = slot;
    std::int32_t n = nodes_[x].nb[nodes_[x].longest];
    // Each step goes to a strictly longer edge (model's edge order): terminates.
    while (n >= 0) {
      if (!everywhere && outside(n)) return false;
      if (nodes_[n].nb[nodes_[n].longest] == x) break;
      x = n;
      n = nodes_[x].nb[nodes_[x].longest];
    }
    if (!everywhere) {
      // The bisection relinks the neighbours across x's edge BC and n's edge DB.
      const Node& nx = nodes_[x];
      const std::int32_t n_bc = nx.nb[(nx.longest + 1) % 3];
      if (n_bc >= 0 && outside(n_bc)) return false;
      if (n >= 0) {
        const Node& nn = nodes_[n];
        const std::int32_t n_db = nn.nb[(nn.longest + 2) % 3];
        if (n_db >= 0 && outside(n_db)) return false;
      }
    }
    const Bisect result = bisect_pair(x, n);
    if (result == Bisect::kInvalid) {
      nodes_[slot].blocked = 1;
      return true;
    }
    if (result == Bisect::kNoSlot) return true;  // build() starts over on one region
  }
  return true;
}

std::vector<std::array<Vertex, 3>> Tritree::blocked_leaves() const {
  std::vector<std::array<Vertex, 3>> out;
  for_each_slot([&](std::int32_t i) {
    const Node& n = nodes_[i];
    if (n.blocked) out.push_back({vertex(n, 0), vertex(n, 1), vertex(n, 2)});
  });
  return out;
}

}  // namespace tristereo
