// --rig FILE [--rig-right FILE2]: a raw rig's calibration for match and rectify.
// Two options rather than --rig given twice: an option given twice is a usage
// error everywhere else in the program, and the pair's order matters.
#pragma once

#include <memory>
#include <set>
#include <string>

#include "apps/cli_args.hpp"
#include "tristereo/rectify.hpp"
#include "tristereo/rig.hpp"

namespace tristereo::cli {

struct LoadedRig {
  StereoRig rig;
  Rectification rect;
  std::shared_ptr<RectifyMaps> maps;
};

void add_rig_options(std::set<std::string>& values);
const char* rig_options_help();
// Reads --rig (and --rig-right), the rectification (the file's or computed)
// and builds the maps; checks that the raw images are of the rig's size.
// Throws tristereo::Error (exit 1) on bad files.
LoadedRig load_rig(const Args& args, int raw_width, int raw_height);

}  // namespace tristereo::cli
