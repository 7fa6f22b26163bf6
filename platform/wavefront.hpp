// A wavefront of tiles handed to the workers on demand (docs/threads.md).
//
// The tiles form `bands` x `cols`; tile (k, c) may run once
//   - tile (k, c - 1) is done (a band's tiles run in order: they carry state
//     from left to right), and
//   - tile (k - 1, min(cols - 1, c + lead)) is done (the band above has gone
//     `lead` tiles past this one), and
//   - every band before k - in_flight is done (so at most in_flight bands are
//     under way, which bounds the rings their work keeps alive).
// Bands therefore complete in order. A raster pass of path costs fits this
// shape: a sample depends on its left neighbour in the row and on samples of
// earlier rows at most `lead` tiles ahead (the matcher shears its tiles so
// that this holds, src/aggregate/path_matcher.cpp).
//
// Any worker takes any ready tile, the lowest band first (the one every later
// tile waits for), so a worker slowed from outside takes fewer tiles instead
// of holding its band back. Each tile's done flag is published with release
// and read with acquire, so a tile sees everything the tiles it waited for
// wrote. No allocation after configure().
//
//   Wavefront wf;
//   wf.configure(max_bands);                  // once
//   wf.reset(bands, cols, lead, in_flight);   // before each run()
//   pool.run([&](int w) {
//     int k, c;
//     while (wf.next(&k, &c)) { ...tile (k, c)...; wf.finish(k, c); }
//   });
#pragma once

#include <algorithm>
#include <atomic>
#include <memory>
#include <thread>

#include "platform/cpu_relax.hpp"

namespace tristereo {

class Wavefront {
 public:
  // Room for up to max_bands bands per run. Not thread-safe.
  void configure(int max_bands) {
    max_bands_ = std::max(1, max_bands);
    bands_state_.reset(new Band[static_cast<std::size_t>(max_bands_)]);
    bands_ = 0;
  }

  // A run of `bands` (<= max_bands) x `cols` tiles (both >= 1; bands 0 = no
  // work). lead >= 0, in_flight >= 1. Not thread-safe: call it before the
  // run() that hands the tiles out.
  void reset(int bands, int cols, int lead, int in_flight) {
    bands_ = std::min(std::max(0, bands), max_bands_);
    cols_ = std::max(1, cols);
    lead_ = std::max(0, lead);
    in_flight_ = std::max(1, in_flight);
    for (int k = 0; k < bands_; ++k) {
      bands_state_[k].done.store(0, std::memory_order_relaxed);
      bands_state_[k].claimed.store(0, std::memory_order_relaxed);
    }
    low_.store(0, std::memory_order_relaxed);
  }

  int bands() const { return bands_; }
  int cols() const { return cols_; }

  // Claims a ready tile: true with (*band, *col), false once every band is
  // done. Waits (spinning, then yielding) while tiles remain but none is
  // ready. The lowest band's tile comes first even for the worker that ran
  // the tile before it: a slowed worker must not keep the band every later
  // one waits for (the band's carried state is a few hundred bytes).
  bool next(int* band, int* col) {
    for (int spins = 0;; ++spins) {
      if (try_next(band, col, [](int) { return true; })) return true;
      if (finished()) return false;
      if (spins < 64) cpu_relax();
      else std::this_thread::yield();
    }
  }

  // Claims a ready tile without waiting: false when none is ready now (or
  // every band is done). `can_start(band)` is asked before a band's first
  // tile is claimed, for a condition of the caller's (it may record that the
  // band was started; the claim may still go to another worker).
  template <class CanStart>
  bool try_next(int* band, int* col, CanStart&& can_start) {
    const int low = low_.load(std::memory_order_acquire);
    const int high = std::min(bands_, low + in_flight_);
    for (int k = low; k < high; ++k)
      if (try_claim(k, col, can_start)) {
        *band = k;
        return true;
      }
    return false;
  }

  // Every band is done.
  bool finished() const { return low_.load(std::memory_order_acquire) >= bands_; }
  // Band k is done (its last tile finished).
  bool band_done(int k) const { return bands_state_[k].done.load(std::memory_order_acquire) >= cols_; }

  // Marks tile (band, col) done; true when it completed its band.
  bool finish(int band, int col) {
    bands_state_[band].done.store(col + 1, std::memory_order_release);
    if (col + 1 < cols_) return false;
    // Bands complete in order, but two completions may publish out of order.
    int low = low_.load(std::memory_order_relaxed);
    while (low < band + 1 && !low_.compare_exchange_weak(low, band + 1, std::memory_order_acq_rel)) {
    }
    return true;
  }

 private:
  template <class CanStart>
  bool try_claim(int k, int* col, CanStart& can_start) {
    Band& b = bands_state_[k];
    int c = b.done.load(std::memory_order_acquire);
    if (c >= cols_ || b.claimed.load(std::memory_order_relaxed) != c) return false;
    if (k > 0 && bands_state_[k - 1].done.load(std::memory_order_acquire) < std::min(cols_, c + lead_ + 1))
      return false;
    if (c == 0 && !can_start(k)) return false;
    if (!b.claimed.compare_exchange_strong(c, c + 1, std::memory_order_acq_rel)) return false;
    *col = c;
    return true;
  }

  // One cache line per band: neighbouring bands are worked on by different
  // workers at the same time.
  struct alignas(64) Band {
    std::atomic<int> done{0};     // tiles 0 .. done - 1 are finished
    std::atomic<int> claimed{0};  // tiles 0 .. claimed - 1 were taken
  };
  std::unique_ptr<Band[]> bands_state_;
  int max_bands_ = 0;
  int bands_ = 0, cols_ = 1, lead_ = 0, in_flight_ = 1;
  alignas(64) std::atomic<int> low_{0};  // every band below is done
};

}  // namespace tristereo
