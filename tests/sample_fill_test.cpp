// The background fill (docs/model.md section 6): against a literal
// transcription of its rounds, with and without a pool, on tritree meshes and
// dense grids.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <vector>

#include "platform/thread_pool.hpp"
#include "src/fill/sample_fill.hpp"
#include "src/tritree/tritree.hpp"
#include "support/scenes.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {
namespace {

// Rounds as the model states them: every invalid sample with a neighbour valid
// at the start of the round takes the smallest such disparity.
int fill_by_rounds(const SampleLayout& samples, std::vector<std::int16_t>& d) {
  const int n = samples.count();
  std::vector<std::vector<int>> nb(static_cast<std::size_t>(n));
  if (samples.dense()) {
    for (int i = 0; i < n; ++i)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = i % samples.width + dx, y = i / samples.width + dy;
          if ((dx || dy) && x >= 0 && x < samples.width && y >= 0 && y < samples.height)
            nb[static_cast<std::size_t>(i)].push_back(y * samples.width + x);
        }
  } else {
    for (const Triangle& t : samples.mesh->triangles)
      for (int e = 0; e < 3; ++e)
        nb[static_cast<std::size_t>(t[static_cast<std::size_t>(e)])].push_back(t[static_cast<std::size_t>((e + 1) % 3)]),
            nb[static_cast<std::size_t>(t[static_cast<std::size_t>((e + 1) % 3)])].push_back(t[static_cast<std::size_t>(e)]);
  }
  int filled = 0;
  for (;;) {
    std::vector<std::int16_t> next = d;
    int now = 0;
    for (int i = 0; i < n; ++i) {
      if (d[static_cast<std::size_t>(i)] != kInvalidDispQ4) continue;
      int best = INT_MAX;
      for (int q : nb[static_cast<std::size_t>(i)])
        if (d[static_cast<std::size_t>(q)] != kInvalidDispQ4) best = std::min<int>(best, d[static_cast<std::size_t>(q)]);
      if (best != INT_MAX) next[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(best), ++now;
    }
    d.swap(next);
    filled += now;
    if (now == 0) return filled;
  }
}

TEST(FillThreads, IdenticalForAnyPoolAndToTheRounds) {
  test::Rng rng(99);
  for (int round = 0; round < 6; ++round) {
    const int w = rng.uniform(420, 560), h = rng.uniform(300, 380);
    // Texture everywhere but in one smooth band: a fine mesh with coarse parts.
    ImageU8 img(w, h, 1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        img.at(x, y) = static_cast<std::uint8_t>(y < h / 4 ? x / 4 : rng.uniform(0, 255));
    Tritree tree;
    TritreeParams fine;  // leaves down to 1 px^2: enough triangles for the chunks below
    fine.min_area_px2 = 1;
    tree.configure(w, h, fine);
    Mesh mesh;
    tree.build(img.view(), mesh);
    for (const bool dense : {false, true}) {
      const SampleLayout samples{dense ? nullptr : &mesh, w, h};
      const int n = samples.count();
      // Invalid in blobs and alone, so rounds of several steps occur.
      std::vector<std::int16_t> d(static_cast<std::size_t>(n));
      const int cx = rng.uniform(0, w - 1), cy = rng.uniform(0, h - 1), r = rng.uniform(5, 40);
      for (int i = 0; i < n; ++i) {
        const int x = samples.x_of(i), y = samples.y_of(i);
        const bool blob = (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
        d[static_cast<std::size_t>(i)] = blob || rng.uniform(0, 99) < 45
                                             ? kInvalidDispQ4
                                             : static_cast<std::int16_t>(rng.uniform(0, 16 * 200));
      }
      std::vector<std::int16_t> expected = d;
      const int expected_filled = fill_by_rounds(samples, expected);
      ASSERT_GT(expected_filled, 4096);  // enough for the pool's chunks (SampleFill: 2 x 2048)
      // and triangles for two chunks of the mesh's first walk (2 x 8192)
      if (!dense) {
        ASSERT_GT(mesh.triangles.size(), 16384u);
        // and, for the second round's walk, triangles whose three corners are
        // all invalid (the only ones the first round keeps) for two of its
        // chunks (2 x 4096)
        std::size_t live = 0;
        for (const Triangle& t : mesh.triangles)
          live += (d[static_cast<std::size_t>(t[0])] == kInvalidDispQ4 && d[static_cast<std::size_t>(t[1])] == kInvalidDispQ4 &&
                   d[static_cast<std::size_t>(t[2])] == kInvalidDispQ4) ? 1 : 0;
        ASSERT_GT(live, 8192u);
      }
      for (int workers : {0, 1, 2, 3}) {
        // Configured for the pool's workers, and for fewer (then it fills alone).
        for (const int configured : {std::max(workers, 1), 1}) {
          SampleFill fill;
          fill.configure(w * h, 2 * w * h, configured);
          ThreadPool pool;
          if (workers > 0) pool.start(workers, {}, /*pin=*/false);
          // Twice on one SampleFill: a fill must not depend on the one before.
          for (int again = 0; again < 2; ++again) {
            std::vector<std::int16_t> got = d;
            const int filled = fill.fill(samples, got.data(), workers > 0 ? &pool : nullptr);
            ASSERT_EQ(filled, expected_filled)
                << (dense ? "dense" : "mesh") << " workers " << workers << " configured " << configured;
            ASSERT_EQ(got, expected) << (dense ? "dense" : "mesh") << " workers " << workers << " configured "
                                     << configured;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace tristereo
