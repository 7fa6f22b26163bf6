// A program that uses an installed tristereo: one frame on a generated scene
// with exact ground truth, checked. Built by scripts/consumer-test.sh against
// the installed package, through find_package(tristereo) and through pkg-config.
#include <cstdio>

#include "tristereo/eval.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"

int main() {
  try {
    tristereo::SynthParams sp;
    sp.width = 160;
    sp.height = 120;
    sp.num_disp = 24;
    const tristereo::SyntheticScene scene = tristereo::make_synthetic_scene(sp);

    tristereo::PipelineConfig config;
    config.max_width = sp.width;
    config.max_height = sp.height;
    config.params.num_disp = sp.num_disp;
    config.threads = 1;
    tristereo::Pipeline pipeline;
    pipeline.configure(config);
    const tristereo::StereoOutput& out = pipeline.process(scene.left.view(), scene.right.view());

    const tristereo::Image<float> disp = tristereo::disp_q4_to_float(out.disp_q4.view());
    const tristereo::BadPixelStats s =
        tristereo::evaluate_disparity(disp.view(), scene.disp_left.view(), scene.nonocc_mask.view());
    std::printf("consumer: %zu vertices, %zu triangles, bad > 1 px on visible pixels: %.2f %%\n",
                out.mesh.vertices.size(), out.mesh.triangles.size(), s.bad_1);
    // The library's own demo scores this scene far below 10 %; a broken link
    // or ABI mix-up gives garbage far above it.
    if (out.mesh.triangles.empty() || s.evaluated < sp.width * sp.height / 2 || s.bad_1 > 10.0) {
      std::printf("consumer: FAILED\n");
      return 1;
    }
    // Errors cross the library boundary as tristereo::Error.
    try {
      config.params.num_disp = 0;
      pipeline.configure(config);
      std::printf("consumer: FAILED (no error for num_disp = 0)\n");
      return 1;
    } catch (const tristereo::Error& e) {
      std::printf("consumer: bad input answered: %s\n", e.what());
    }
    std::printf("consumer: ok\n");
    return 0;
  } catch (const std::exception& e) {
    std::printf("consumer: FAILED: %s\n", e.what());
    return 1;
  }
}
