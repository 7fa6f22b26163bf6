// README's C++ example, compiled and run by the test command against the
// installed package (scripts/consumer-test.sh): one rectified pair in, the
// dense disparity out.
//   match_pair LEFT.png RIGHT.png NDISP OUT.pfm
#include <cstdio>
#include <cstdlib>

#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: match_pair LEFT.png RIGHT.png NDISP OUT.pfm\n");
    return 2;
  }
  try {
    const tristereo::ImageU8 left = tristereo::read_image_u8(argv[1]);  // gray or RGB
    const tristereo::ImageU8 right = tristereo::read_image_u8(argv[2]);

    tristereo::PipelineConfig config;
    config.max_width = left.width;  // frames up to this size, no larger
    config.max_height = left.height;
    config.params.num_disp = std::atoi(argv[3]);  // other parameters: docs/tuning.md
    config.threads = 0;                           // one pinned worker per allowed CPU
    tristereo::Pipeline pipeline;
    pipeline.configure(config);  // validates, allocates, starts the workers

    // Every later frame of this size: no allocation, the same buffers.
    const tristereo::StereoOutput& out = pipeline.process(left.view(), right.view());
    // out.mesh (vertices, triangles), out.vertex_disp_q4 (one per vertex) and
    // out.disp_q4 (dense, int16 in 1/16 px, kInvalidDispQ4 = no value)
    tristereo::write_disparity(argv[4], out.disp_q4.view());  // PFM: float px, +inf = invalid
    std::printf("%zu vertices, %zu triangles, %.2f ms\n", out.mesh.vertices.size(),
                out.mesh.triangles.size(), pipeline.last_timings().total_ns / 1e6);
    return 0;
  } catch (const tristereo::Error& e) {  // bad input: the message names the value and the limit
    std::fprintf(stderr, "match_pair: %s\n", e.what());
    return 1;
  }
}
