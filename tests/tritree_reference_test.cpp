// The integer tritree (src/tritree) equals the float reference
// (src/reference/ref_tritree) bit for bit: Middlebury, synthetic scenes, and
// over a thousand random small images with random valid parameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <string>
#include <utility>

#include "src/reference/ref_tritree.hpp"
#include "src/tritree/tritree.hpp"
#include "support/scenes.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

using test::Rng;

Mesh build_integer(const ImageU8& gray, const TritreeParams& params) {
  Tritree tree;
  tree.configure(gray.width, gray.height, params);
  Mesh mesh;
  tree.reserve(mesh);
  const ImageU8& g = gray;
  tree.build(g.view(), mesh);
  return mesh;
}

// First difference, so a failure says where the paths diverge.
std::string describe_difference(const Mesh& a, const Mesh& b) {
  if (a.vertices.size() != b.vertices.size())
    return "vertex count " + std::to_string(a.vertices.size()) + " vs " + std::to_string(b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    if (!(a.vertices[i] == b.vertices[i])) return "vertex " + std::to_string(i);
  }
  if (a.triangles != b.triangles) return "triangles";
  return "split counts " + std::to_string(a.forced_splits) + "/" + std::to_string(a.criterion_splits) +
         " vs " + std::to_string(b.forced_splits) + "/" + std::to_string(b.criterion_splits);
}

void expect_bit_exact(const ImageU8& gray, const TritreeParams& params, const std::string& what) {
  const Mesh integer = build_integer(gray, params);
  const Mesh reference = reference::build_tritree(gray, params);
  EXPECT_TRUE(integer == reference)
      << what << " (psnr_deci_db " << params.psnr_deci_db << ", max_area_px2 " << params.max_area_px2
      << ", min_area_px2 " << params.min_area_px2 << "): " << describe_difference(integer, reference);
}

// A minimum area valid with params.max_area_px2: 1 or 2 most of the time (the
// paper mode's and the default), else any up to the largest allowed.
int random_min_area(Rng& rng, int max_area_px2) {
  const int largest = largest_min_area_px2(max_area_px2);
  const int pick = rng.uniform(0, 3);
  return std::min(largest, pick <= 1 ? 1 + pick : rng.uniform(1, largest));
}

// Random scene families: noise, smooth + noise, steps, and blends of them.
ImageU8 random_scene(Rng& rng, int w, int h) {
  ImageU8 img(w, h);
  const int kind = rng.uniform(0, 4);
  const int gx = rng.uniform(-20, 20), gy = rng.uniform(-20, 20);
  const int noise = rng.uniform(0, 40);
  const int sx = rng.uniform(0, w), sy = rng.uniform(0, h), step = rng.uniform(-200, 200);
  const int base = rng.uniform(0, 255);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      int v = base;
      switch (kind) {
        case 0: v = rng.uniform(0, 255); break;
        case 1: v += gx * x / 4 + gy * y / 4; break;
        case 2: v += (x >= sx ? step : 0) + (y >= sy ? -step / 2 : 0); break;
        case 3: v += ((x * x + 3 * y * y) * gx) / 16; break;
        default: v += gx * x / 4 + (x + y >= sx ? step : 0); break;
      }
      if (kind != 0 && noise > 0) v += rng.uniform(-noise, noise) / 4;
      img.at(x, y) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  }
  return img;
}

TEST(TritreeReference, MiddleburyAtDefaultAndOtherPsnr) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  for (const std::string& name : test::middlebury_names()) {
    const ImageU8 gray = to_gray(test::load_middlebury(name).left);
    for (int psnr_deci_db : {400, 300, 350, 440, 450}) {
      for (int min_area : {1, 2, 8}) {
        TritreeParams params;
        params.psnr_deci_db = psnr_deci_db;
        params.min_area_px2 = min_area;
        expect_bit_exact(gray, params, name);
      }
    }
    // Informative only (never asserted): size of the default mesh and one
    // single-run build time of the integer path.
    const TritreeParams defaults;
    Tritree tree;
    tree.configure(gray.width, gray.height, defaults);
    Mesh mesh;
    tree.reserve(mesh);
    const auto t0 = std::chrono::steady_clock::now();
    tree.build(gray.view(), mesh);
    const auto t1 = std::chrono::steady_clock::now();
    std::cout << "[tritree] " << name << " " << gray.width << "x" << gray.height << ": "
              << mesh.vertices.size() << " vertices ("
              << 100.0 * mesh.vertices.size() / (gray.width * gray.height) << "% of pixels), "
              << mesh.triangles.size() << " triangles, " << mesh.criterion_splits
              << " criterion + " << mesh.forced_splits << " forced splits, "
              << std::chrono::duration<double, std::milli>(t1 - t0).count() << " ms\n";
  }
}

TEST(TritreeReference, SyntheticScenes) {
  Rng rng(31);
  for (int it = 0; it < 24; ++it) {
    const int w = rng.uniform(60, 200), h = rng.uniform(40, 150);
    const ImageU8 img = random_scene(rng, w, h);
    TritreeParams params;
    params.psnr_deci_db = rng.uniform(250, 500);
    params.max_area_px2 = rng.uniform(16, 400);
    params.min_area_px2 = random_min_area(rng, params.max_area_px2);
    expect_bit_exact(img, params, "synthetic scene " + std::to_string(it));
  }
}

TEST(TritreeReference, RandomSmallImagesAndParameters) {
  Rng rng(4242);
  for (int it = 0; it < 1200; ++it) {
    const int w = rng.uniform(2, 40);
    const int h = rng.uniform(2, 40);
    const ImageU8 img = random_scene(rng, w, h);
    TritreeParams params;
    params.psnr_deci_db = rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb);
    params.max_area_px2 = rng.uniform(1, kMaxAreaLimitPx2);
    params.min_area_px2 = random_min_area(rng, params.max_area_px2);
    expect_bit_exact(img, params, "random image " + std::to_string(it) + " " +
                                      std::to_string(w) + "x" + std::to_string(h));
    if (HasFailure()) return;  // one report is enough
  }
}

TEST(TritreeReference, SpecialSizes) {
  // 2 x 2, 3 x N, primes, partial tiles, stretched last row/column, 4096 wide.
  const std::pair<int, int> sizes[] = {{2, 2},   {2, 9},   {3, 3},   {3, 40},  {40, 3},
                                       {5, 5},   {17, 19}, {31, 37}, {61, 59}, {64, 64},
                                       {65, 65}, {66, 67}, {4096, 3}, {4096, 6}, {3, 4096}};
  Rng rng(99);
  for (const auto& size : sizes) {
    for (int area : {1, 5, 100, kMaxAreaLimitPx2}) {
      for (int min_area : {1, largest_min_area_px2(area)}) {
        const ImageU8 img = random_scene(rng, size.first, size.second);
        TritreeParams params;
        params.max_area_px2 = area;
        params.min_area_px2 = min_area;
        params.psnr_deci_db = rng.uniform(300, 500);
        expect_bit_exact(img, params, std::to_string(size.first) + "x" + std::to_string(size.second));
      }
    }
  }
}

TEST(TritreeReference, ExtremeParameters) {
  Rng rng(5);
  for (int it = 0; it < 20; ++it) {
    const ImageU8 img = random_scene(rng, rng.uniform(2, 60), rng.uniform(2, 60));
    for (int psnr : {kMinPsnrDeciDb, kMaxPsnrDeciDb}) {
      for (int area : {1, kMaxAreaLimitPx2}) {
        for (int min_area : {1, largest_min_area_px2(area)}) {
          TritreeParams params;
          params.psnr_deci_db = psnr;
          params.max_area_px2 = area;
          params.min_area_px2 = min_area;
          expect_bit_exact(img, params, "extreme " + std::to_string(it));
        }
      }
    }
  }
}

TEST(TritreeReference, RejectsBadInput) {
  const TritreeParams ok;
  EXPECT_THROW(reference::build_tritree(ImageU8(1, 5), ok), Error);
  EXPECT_THROW(reference::build_tritree(ImageU8(5, 1), ok), Error);
  EXPECT_THROW(reference::build_tritree(ImageU8(5, 5, 3), ok), Error);
  ImageU8 truncated(5, 5);
  truncated.pixels.resize(7);
  EXPECT_THROW(reference::build_tritree(truncated, ok), Error);
  TritreeParams bad;
  bad.max_area_px2 = 0;
  EXPECT_THROW(reference::build_tritree(ImageU8(5, 5), bad), Error);
  bad = ok;
  bad.psnr_deci_db = 99;
  EXPECT_THROW(reference::build_tritree(ImageU8(5, 5), bad), Error);
  bad = ok;
  bad.min_area_px2 = 0;
  EXPECT_THROW(reference::build_tritree(ImageU8(5, 5), bad), Error);
  bad.min_area_px2 = largest_min_area_px2(bad.max_area_px2) + 1;  // 33 with A_max 100
  EXPECT_THROW(reference::build_tritree(ImageU8(5, 5), bad), Error);
  bad.max_area_px2 = 3;  // the default minimum area 2 needs A_max >= 4
  bad.min_area_px2 = 2;
  EXPECT_THROW(reference::build_tritree(ImageU8(5, 5), bad), Error);
}

}  // namespace
}  // namespace tristereo
