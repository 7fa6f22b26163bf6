// Options shared by match, verify and demo: the model parameters and the run options.
#pragma once

#include <set>
#include <string>

#include "apps/cli_args.hpp"
#include "tristereo/pipeline.hpp"

namespace tristereo::cli {

// Option names understood by stereo_config_from_args (merged into each command's set).
void add_stereo_options(std::set<std::string>& values, std::set<std::string>& flags);
// Builds and validates the config; `width`/`height` become the configured maximum.
PipelineConfig stereo_config_from_args(const Args& args, int width, int height);
// Help text for those options.
const char* stereo_options_help();

}  // namespace tristereo::cli
