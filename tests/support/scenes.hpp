// Test inputs: the Middlebury scenes of ../shared/data and small random images.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "src/tritree/tritree.hpp"
#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/params.hpp"
#include "tristereo/synth.hpp"
#include "support/data.hpp"

namespace tristereo::test {

struct MiddleburyPair {
  std::string name;
  int ndisp = 0;
  int gt_scale = 1;
  ImageU8 left, right;      // as stored (RGB)
  Image<float> gt;          // disparity in px, 0 = unknown
  ImageU8 nonocc, all;      // 255 = evaluated
};

// Root of ../shared/data/middlebury. Tests that need it start with
// TRISTEREO_REQUIRE_MIDDLEBURY() (support/data.hpp: the rule for missing data).
std::string middlebury_dir();
bool middlebury_available();
std::vector<std::string> middlebury_names();  // tsukuba venus teddy cones
MiddleburyPair load_middlebury(const std::string& name);

// Deterministic small PRNG (identical sequence on every platform).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(seed * 0x9E3779B97F4A7C15ULL + 1) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  int uniform(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }

 private:
  std::uint64_t s_;
};

// A random gray image mixing smooth gradients, noise and steps (so the tritree
// both splits and stops), and its right view shifted by `shift` with noise.
ImageU8 random_image(Rng& rng, int w, int h);
ImageU8 shifted_view(Rng& rng, const ImageU8& left, int shift, int noise);
// The synthetic scene (make_synthetic_scene, seed 1) of width x height
// with disparities below num_disp.
SyntheticScene synthetic_scene(int width, int height, int num_disp);
// The mesh of a random_image(rng, w, h) under random_tritree_params(rng),
// built by `tree` (configured here; it keeps the build's grid); the
// parameters go to *params when given.
Mesh random_mesh(Rng& rng, int w, int h, Tritree& tree, TritreeParams* params = nullptr);
// Any valid tritree parameters: A_max from 1 to 1024 px^2 (a few typical
// values), any threshold and any minimum area A_max allows.
TritreeParams random_tritree_params(Rng& rng);
// The mesh of `gray` with A_max = max_area_px2 (default threshold), from
// `tree`, which is configured for the image and keeps the build's grid.
Mesh tritree_mesh(Tritree& tree, const ImageU8& gray, int max_area_px2);
// A pipeline configuration for a width x height frame with `threads`
// unpinned workers (tests share the machine's CPUs).
PipelineConfig unpinned_config(int width, int height, const StereoParams& params, int threads,
                               KernelChoice kernels = KernelChoice::kAuto);
// Random valid parameters (every field inside validate_params' ranges).
StereoParams random_params(Rng& rng, int max_ndisp);

}  // namespace tristereo::test
