// Writing what `match` (and `demo`) produce: disparity files, mesh, samples, stats.
#pragma once

#include <ostream>
#include <string>

#include "apps/cli_args.hpp"
#include "tristereo/image.hpp"
#include "tristereo/pipeline.hpp"

namespace tristereo::cli {

struct MatchRun {
  PipelineConfig config;
  StereoOutput output;
  FrameTimings timings;
  std::string implementation;  // "reference" or "integer/<kernels>"
  int threads = 1;
};

// Honors --disp, --disp-color, --mesh (+ --mesh-ascii, --camera), --samples, --stats.
void write_match_outputs(const Args& args, const ImageU8& left, const MatchRun& run);
void write_stats_json(const std::string& path, const MatchRun& run);
void write_samples_csv(const std::string& path, const StereoOutput& out);
void print_match_summary(std::ostream& os, const MatchRun& run);

}  // namespace tristereo::cli
