// `tristereo profile`: per-frame latency of the pipeline on a stream of frames
// (stage timings, percentiles, fps, CPU time, peak memory), with optional
// real-time scheduling, CPU pinning and GPIO frame markers. docs/profiling.md.
#pragma once

namespace tristereo::cli {

// argv[0] == "profile". Returns the exit code (0 = success); throws
// cli::UsageError for bad options and tristereo::Error for failures
// (unreadable input, GPIO or real-time refused), which main() prints.
int cmd_profile(int argc, char** argv);

}  // namespace tristereo::cli
