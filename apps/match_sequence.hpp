// `tristereo match --folder DIR` / `--list FILE`: a recorded run in one
// process (docs/profiling.md, "Sequences in one run").
#pragma once

#include <set>
#include <string>

#include "apps/cli_args.hpp"

namespace tristereo::cli {

// The options only a sequence takes (match adds them to its own).
void add_sequence_options(std::set<std::string>& values, std::set<std::string>& flags);
// match's --help paragraph about them.
const char* sequence_help();

// Runs the sequence `args` names (--folder or --list; every other option as
// for one pair, the output options being patterns with one %d field).
// Returns 0 when every frame was done, 1 when any failed (each reported on
// stderr, the others done); throws UsageError / tristereo::Error for what
// stops the run before its first frame.
int match_sequence(const Args& args);

}  // namespace tristereo::cli
