// Kernel micro-benchmarks: the cost and DP entries of KernelSet x every kernel
// set this CPU can run x D in {16, 64, 128, 256}, named kernel/set/D (e.g.
// dp_step/avx2/64); the tritree's side4_tests_u8 and side8_tests_s32 per set and number of squares,
// and the interpolation's midpoints_row_q4 (and midpoints_row_conf_q4) per set, row kind and width.
// items_per_second counts disparity evaluations (one element of the kernel's n).
//
//   bench_kernels --benchmark_filter='accumulate.*/64$'
//
// For a scalar baseline without the compiler's auto-vectoriser, configure with
// -DTRISTEREO_SCALAR_NO_AUTOVEC=ON (simd/README.md).
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "tristereo/kernels.hpp"
#include "bench_context.hpp"

namespace tristereo {
namespace {

constexpr int kRows = 16;  // distinct inputs per iteration, like 16 window pixels

struct Inputs {
  std::vector<std::uint8_t> right;   // kRows rows of D (+ slack for misalignment)
  std::vector<std::uint8_t> left;    // kRows
  std::vector<std::uint16_t> sum16;  // D
  std::vector<std::uint32_t> sum32;  // D
  std::vector<std::uint16_t> cost;   // D
  std::vector<std::uint32_t> prev;   // D
  explicit Inputs(int d) : right(kRows * (d + 1)), left(kRows), sum16(d), sum32(d), cost(d), prev(d) {
    std::mt19937 rng(42);
    for (auto& v : right) v = static_cast<std::uint8_t>(rng());
    for (auto& v : left) v = static_cast<std::uint8_t>(rng());
    for (auto& v : sum16) v = static_cast<std::uint16_t>(rng() % (25 * 255));
    for (auto& v : sum32) v = rng() % (961 * 255 * 255);
    for (auto& v : cost) v = static_cast<std::uint16_t>(rng() % 4081);
    for (auto& v : prev) v = rng() % (4080 + 255 * 400);
  }
  // Row r starts at an odd offset so loads are misaligned, as in a real row.
  const std::uint8_t* row(int r, int d) const { return right.data() + r * (d + 1) + 1; }
};

void bench_accumulate_u16(benchmark::State& state, const KernelSet* ks, int d) {
  Inputs in(d);
  std::vector<std::uint16_t> acc(d);
  for (auto _ : state) {
    for (int r = 0; r < kRows; ++r) ks->accumulate_abs_diff_u16(in.row(r, d), in.left[r], 40, d, acc.data());
    benchmark::DoNotOptimize(acc.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kRows * d);
}

void bench_accumulate_weighted_u32(benchmark::State& state, const KernelSet* ks, int d) {
  Inputs in(d);
  std::vector<std::uint32_t> acc(d);
  for (auto _ : state) {
    for (int r = 0; r < kRows; ++r)
      ks->accumulate_abs_diff_weighted_u32(in.row(r, d), in.left[r], static_cast<std::uint16_t>(100 + r), 255, d, acc.data());
    benchmark::DoNotOptimize(acc.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kRows * d);
}

// The fused window kernels over a 5x5 window (the default), laid out like
// MatchContext's: 5 reversed rows, pixel j of a row one byte before pixel j - 1.
// items_per_second counts window pixels x disparities, like the per-pixel
// kernels above, so the two can be compared directly.
constexpr int kWindowSide = 5;
constexpr int kWindowPixels = kWindowSide * kWindowSide;

struct Window {
  std::vector<std::uint8_t> rows;  // kWindowSide rows of D + kWindowSide + 1
  std::vector<const std::uint8_t*> right;
  std::vector<std::uint8_t> left;
  std::vector<std::uint16_t> weight;
  explicit Window(int d) : rows(kWindowSide * (d + kWindowSide + 1)) {
    std::mt19937 rng(7);
    for (auto& v : rows) v = static_cast<std::uint8_t>(rng());
    for (int i = 0; i < kWindowSide; ++i) {
      const std::uint8_t* r = rows.data() + i * (d + kWindowSide + 1) + kWindowSide;
      for (int j = 0; j < kWindowSide; ++j) {
        right.push_back(r - j);
        left.push_back(static_cast<std::uint8_t>(rng()));
        weight.push_back(static_cast<std::uint16_t>(rng() % 255));
      }
    }
  }
};

void bench_window_box_u16(benchmark::State& state, const KernelSet* ks, int d) {
  Window win(d);
  std::vector<std::uint16_t> sum(d);
  for (auto _ : state) {
    ks->aggregate_window_box_u16(win.right.data(), win.left.data(), kWindowPixels, 30, d, sum.data());
    benchmark::DoNotOptimize(sum.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kWindowPixels * d);
}

void bench_window_weighted_u32(benchmark::State& state, const KernelSet* ks, int d) {
  Window win(d);
  std::vector<std::uint32_t> sum(d);
  for (auto _ : state) {
    ks->aggregate_window_weighted_u32(win.right.data(), win.left.data(), win.weight.data(),
                                      kWindowPixels, 255, d, sum.data());
    benchmark::DoNotOptimize(sum.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kWindowPixels * d);
}

void bench_normalize_u16(benchmark::State& state, const KernelSet* ks, int d) {
  Inputs in(d);
  std::vector<std::uint16_t> out(d);
  const std::uint64_t inv = (std::uint64_t{1} << 32) / 25;
  for (auto _ : state) {
    ks->normalize_costs_u16(in.sum16.data(), inv, d, out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * d);
}

void bench_normalize_u32(benchmark::State& state, const KernelSet* ks, int d) {
  Inputs in(d);
  std::vector<std::uint16_t> out(d);
  const std::uint64_t inv = (std::uint64_t{1} << 32) / (961 * 255);
  for (auto _ : state) {
    ks->normalize_costs_u32(in.sum32.data(), inv, d, out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * d);
}

void bench_dp_step(benchmark::State& state, const KernelSet* ks, int d) {
  Inputs in(d);
  std::vector<std::uint32_t> prev = in.prev, out(d);
  std::vector<std::uint8_t> ptr(d);
  for (auto _ : state) {
    // Chained like a row: out (<= 4080 + 255 * 400) becomes the next prev.
    ks->dp_step(in.cost.data(), prev.data(), 400, d, out.data(), ptr.data());
    prev.swap(out);
    benchmark::DoNotOptimize(ptr.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * d);
}

// The u16 DP (lambda_q4 <= kMaxDpPenaltyU16): chained like a row, penalty 40
// (the default lambda), so values stay <= 4080 + 255 * 40.
void bench_dp_step_u16(benchmark::State& state, const KernelSet* ks, int d) {
  Inputs in(d);
  std::vector<std::uint16_t> prev(d), out(d);
  for (int k = 0; k < d; ++k) prev[k] = static_cast<std::uint16_t>(in.prev[k] % (4080 + 255 * 40));
  for (auto _ : state) {
    ks->dp_step_u16(in.cost.data(), prev.data(), 40, d, out.data());
    prev.swap(out);
    benchmark::DoNotOptimize(prev.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * d);
}

// One back-pointer search per call (a backtracking step), k walking the range.
void bench_dp_pointer_u16(benchmark::State& state, const KernelSet* ks, int d) {
  Inputs in(d);
  std::vector<std::uint16_t> prev(d);
  for (int k = 0; k < d; ++k) prev[k] = static_cast<std::uint16_t>(in.prev[k] % (4080 + 255 * 40));
  int k = 0;
  for (auto _ : state) {
    k = (ks->dp_pointer_u16(prev.data(), 40, d, k) + 7) % d;
    benchmark::DoNotOptimize(k);
  }
  state.SetItemsProcessed(state.iterations() * d);
}

void register_all() {
  using Fn = void (*)(benchmark::State&, const KernelSet*, int);
  const std::pair<const char*, Fn> kernels[] = {
      {"accumulate_abs_diff_u16", bench_accumulate_u16},
      {"accumulate_abs_diff_weighted_u32", bench_accumulate_weighted_u32},
      {"aggregate_window_box_u16", bench_window_box_u16},
      {"aggregate_window_weighted_u32", bench_window_weighted_u32},
      {"normalize_costs_u16", bench_normalize_u16},
      {"normalize_costs_u32", bench_normalize_u32},
      {"dp_step", bench_dp_step},
      {"dp_step_u16", bench_dp_step_u16},
      {"dp_pointer_u16", bench_dp_pointer_u16},
  };
  for (const auto& [kernel, fn] : kernels) {
    for (KernelChoice set : available_kernel_sets()) {
      const KernelSet* ks = &kernel_set_for(set);
      for (int d : {16, 64, 128, 256}) {
        const std::string name = std::string(kernel) + "/" + to_string(set) + "/" + std::to_string(d);
        benchmark::RegisterBenchmark(name.c_str(), fn, ks, d);
      }
    }
  }
}

// The tritree's side-4 level: n 4 x 4 squares along a row (5 pixel rows of
// 4 n + 1), limits that make about half the triangles fail. items_per_second
// counts pixels (16 per square).
void bench_side4_tests(benchmark::State& state, const KernelSet* ks, int n) {
  std::mt19937 rng(7);
  std::vector<std::vector<std::uint8_t>> px(5, std::vector<std::uint8_t>(static_cast<std::size_t>(4 * n + 1)));
  for (std::size_t r = 0; r < px.size(); ++r)
    for (std::size_t x = 0; x < px[r].size(); ++x) px[r][x] = static_cast<std::uint8_t>(2 * x + 3 * r + rng() % 24);
  const std::uint8_t* rows[5] = {px[0].data(), px[1].data(), px[2].data(), px[3].data(), px[4].data()};
  const std::int32_t limit[8] = {4000, 4000, 4000, 4000, 12000, 12000, 12000, 12000};
  std::vector<std::uint32_t> wants(static_cast<std::size_t>(n));
  std::vector<std::int32_t> sums(static_cast<std::size_t>(8 * n));
  for (auto _ : state) {
    ks->side4_tests_u8(rows, n, 1, limit, wants.data(), sums.data(), static_cast<std::size_t>(n));
    benchmark::DoNotOptimize(wants.data());
    benchmark::DoNotOptimize(sums.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * 16 * n);
}

// The side-8 level: n 8 x 8 squares along a row (9 pixel rows of 8 n + 1),
// fed with the scalar side-4 kernel's sums of those rows (made once);
// items_per_second counts pixels (64 per square).
void bench_side8_tests(benchmark::State& state, const KernelSet* ks, int n) {
  std::mt19937 rng(7);
  std::vector<std::vector<std::uint8_t>> px(9, std::vector<std::uint8_t>(static_cast<std::size_t>(8 * n + 1)));
  for (std::size_t r = 0; r < px.size(); ++r)
    for (std::size_t x = 0; x < px[r].size(); ++x) px[r][x] = static_cast<std::uint8_t>(2 * x + 3 * r + rng() % 24);
  const std::size_t stride4 = static_cast<std::size_t>(2 * n);
  std::vector<std::int32_t> quad[2] = {std::vector<std::int32_t>(8 * stride4), std::vector<std::int32_t>(8 * stride4)};
  std::vector<std::uint32_t> wants4(stride4);
  const std::int32_t never4[8] = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};
  for (int dy = 0; dy < 2; ++dy) {
    const std::uint8_t* rows4[5];
    for (int r = 0; r < 5; ++r) rows4[r] = px[static_cast<std::size_t>(4 * dy + r)].data();
    scalar_kernel_set().side4_tests_u8(rows4, 2 * n, dy == 0, never4, wants4.data(), quad[dy].data(), stride4);
  }
  const std::int32_t* quad_sums[2] = {quad[0].data(), quad[1].data()};
  const std::uint8_t* rows[3] = {px[0].data(), px[4].data(), px[8].data()};
  const std::int64_t limit[8] = {60000, 60000, 60000, 60000, 200000, 200000, 200000, 200000};
  std::vector<std::uint32_t> wants(static_cast<std::size_t>(n));
  std::vector<std::int32_t> sums(static_cast<std::size_t>(8 * n));
  for (auto _ : state) {
    ks->side8_tests_s32(quad_sums, stride4, rows, n, 1, limit, wants.data(), sums.data(), static_cast<std::size_t>(n));
    benchmark::DoNotOptimize(wants.data());
    benchmark::DoNotOptimize(sums.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * 64 * n);
}

// The interpolation's side-2 level on one grid row of n points (odd rows:
// three rows read), half of the points unknown; items_per_second counts points.
void bench_midpoints_row(benchmark::State& state, const KernelSet* ks, int n, bool odd) {
  std::mt19937 rng(9);
  std::vector<std::vector<std::int32_t>> rows(3, std::vector<std::int32_t>(static_cast<std::size_t>(n) + 2));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t i = 0; i < rows[r].size(); ++i) {
      const bool even_row = r != 1 || !odd, even_x = (i & 1) != 0;  // i = x + 1
      rows[r][i] = !(even_row && even_x) && rng() % 2 ? kMidpointUnknown : static_cast<std::int32_t>(rng() % (1u << 20));
    }
  std::vector<std::int16_t> out(static_cast<std::size_t>(n));
  const std::int32_t* above = odd ? rows[0].data() + 1 : nullptr;
  const std::int32_t* below = odd ? rows[2].data() + 1 : nullptr;
  for (auto _ : state) {
    ks->midpoints_row_q4(above, rows[1].data() + 1, below, n, 1, 7, out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// The same rows with their confidences (a byte per point), through
// midpoints_row_conf_q4: disparity, confidence and state.
void bench_midpoints_row_conf(benchmark::State& state, const KernelSet* ks, int n, bool odd) {
  std::mt19937 rng(9);
  const std::size_t len = static_cast<std::size_t>(n) + 2;
  std::vector<std::vector<std::int32_t>> rows(3, std::vector<std::int32_t>(len));
  std::vector<std::vector<std::uint8_t>> conf_rows(3, std::vector<std::uint8_t>(len));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t i = 0; i < len; ++i) {
      const bool even_row = r != 1 || !odd, even_x = (i & 1) != 0;  // i = x + 1
      rows[r][i] = !(even_row && even_x) && rng() % 2 ? kMidpointUnknown : static_cast<std::int32_t>(rng() % (1u << 20));
      conf_rows[r][i] = static_cast<std::uint8_t>(rng() % 256);
    }
  std::vector<std::int16_t> out(static_cast<std::size_t>(n));
  std::vector<std::uint8_t> conf(static_cast<std::size_t>(n)), st(static_cast<std::size_t>(n));
  const std::int32_t* above = odd ? rows[0].data() + 1 : nullptr;
  const std::int32_t* below = odd ? rows[2].data() + 1 : nullptr;
  const std::uint8_t* conf_above = odd ? conf_rows[0].data() + 1 : nullptr;
  const std::uint8_t* conf_below = odd ? conf_rows[2].data() + 1 : nullptr;
  for (auto _ : state) {
    ks->midpoints_row_conf_q4(above, rows[1].data() + 1, below, conf_above, conf_rows[1].data() + 1, conf_below, n,
                              1, 7, out.data(), conf.data(), st.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::DoNotOptimize(conf.data());
    benchmark::DoNotOptimize(st.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

void register_tritree_kernels() {
  for (KernelChoice set : available_kernel_sets()) {
    const KernelSet* ks = &kernel_set_for(set);
    for (int n : {4, 108, 310}) {  // a tile of side 16; Teddy's and KITTI's runs of plain tiles
      const std::string name = std::string("side4_tests_u8/") + to_string(set) + "/" + std::to_string(n);
      benchmark::RegisterBenchmark(name.c_str(), bench_side4_tests, ks, n);
    }
    for (int n : {2, 54, 155}) {  // the same runs in 8 x 8 squares
      const std::string name = std::string("side8_tests_s32/") + to_string(set) + "/" + std::to_string(n);
      benchmark::RegisterBenchmark(name.c_str(), bench_side8_tests, ks, n);
    }
    for (int n : {448, 1240}) {  // Teddy's and KITTI's grid rows
      for (bool odd : {false, true}) {
        const std::string name = std::string("midpoints_row_q4/") + to_string(set) + (odd ? "/odd/" : "/even/") +
                                 std::to_string(n);
        benchmark::RegisterBenchmark(name.c_str(), bench_midpoints_row, ks, n, odd);
        const std::string conf_name = std::string("midpoints_row_conf_q4/") + to_string(set) +
                                      (odd ? "/odd/" : "/even/") + std::to_string(n);
        benchmark::RegisterBenchmark(conf_name.c_str(), bench_midpoints_row_conf, ks, n, odd);
      }
    }
  }
}

}  // namespace
}  // namespace tristereo

int main(int argc, char** argv) {
  tristereo::register_all();
  tristereo::register_tritree_kernels();
  tristereo::add_binary_context();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
