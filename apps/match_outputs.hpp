// Writing what `match` (and `demo`) produce: disparity files, mesh, samples, stats.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "apps/cli_args.hpp"
#include "apps/output_paths.hpp"
#include "tristereo/depth.hpp"
#include "tristereo/image.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"

namespace tristereo::cli {

struct MatchRun {
  PipelineConfig config;
  StereoOutput output;                  // the reference's result
  const StereoOutput* result = nullptr;  // or the pipeline's, not copied (it outlives the run)
  const StereoOutput& out() const { return result != nullptr ? *result : output; }
  FrameTimings timings;
  std::string implementation;  // "reference" or "integer/<kernels>"
  int threads = 1;
  std::optional<CameraParams> camera;  // from --calib or --camera: metric outputs
  std::string camera_source;           // the calibration file, or "--camera"
  DepthLimits depth_limits;            // what the metric outputs keep (--min-disparity, --min/max-depth)
  // Where a one-shot run's wall time went before its outputs (--stats
  // "run_ms"; docs/performance.md, "One-shot match"), in ms of steady clock:
  // from the command's start through decoding both inputs, configure(), the
  // frame as the caller sees it, and the wait for the swapped-pair check
  // after it. Negative when not measured.
  struct Phases {
    double read_inputs_ms = -1, configure_ms = -1, frame_ms = -1, checks_ms = -1;
  } phases;
};

// The camera of --calib FILE [--calib-format F] [--calib-unit U] or --camera
// F,B,CX,CY[,DOFFS], checked against the input size, and the output options
// that need one (--depth, --points): everything a user can get wrong about it
// fails here, before any computing (and --disp-format). Warns on stderr about a baseline that is
// probably in the wrong unit.
std::optional<CameraParams> camera_from_args(const Args& args, int width, int height,
                                             std::string* source);

// --min-disparity PX, --min-depth M, --max-depth M (defaults: DepthLimits's),
// checked (UsageError naming the option).
DepthLimits depth_limits_from_args(const Args& args);
// The output options of match, with the extensions each writes (for
// check_output_paths, before computing).
const std::vector<OutputOption>& match_output_options();

// Honors --disp, --disp-color, --mesh (+ --mesh-ascii; metric with a camera;
// measured vertices only without --points-include-filled), --valid, --confidence,
// --depth, --points, --samples, --stats.
void write_match_outputs(const Args& args, const ImageU8& left, const MatchRun& run);
void write_stats_json(const std::string& path, const MatchRun& run);
// write_stats_json's text, and the same object on one line (a sequence's
// --stats FILE.jsonl) with "frame", "left" and "right" first.
std::string stats_json_text(const MatchRun& run);
std::string stats_json_line(const MatchRun& run, int frame, const std::string& left, const std::string& right);
// A JSON string literal (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& s);
// --disp as a 16-bit PNG cannot hold what the range needs (UsageError).
void check_disp_output(const Args& args, const StereoParams& p);
void write_samples_csv(const std::string& path, const StereoOutput& out);
void print_match_summary(std::ostream& os, const MatchRun& run);

}  // namespace tristereo::cli
