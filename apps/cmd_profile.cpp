// tristereo profile: per-frame latency distribution of the pipeline.
//
// Frames are prepared before the clock starts (a ring of synthetic frames, a
// pair, or a folder sequence, converted to gray), the pipeline is configured
// once, then W warm-up frames and N measured frames run back to back. Each
// measured frame stores one FrameSample into a preallocated FrameLog; all
// statistics are computed after the loop, so the loop itself allocates only
// what the pipeline and (with --mesh-output) the PLY writer allocate.
#include "apps/cmd_profile.hpp"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "apps/cli_args.hpp"
#include "apps/frame_sequence.hpp"
#include "apps/option_errors.hpp"
#include "apps/output_paths.hpp"
#include "apps/output_set.hpp"
#include "apps/rig_options.hpp"
#include "apps/stereo_options.hpp"
#include "platform/clock.hpp"
#include "platform/cpu_features.hpp"
#include "platform/frame_marker_driver.hpp"
#include "platform/gpio.hpp"
#include "platform/realtime.hpp"
#include "src/profile/latency_stats.hpp"
#include "src/profile/profile_report.hpp"
#include "src/profile/rss_trace.hpp"
#include "tristereo/verify.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/trace.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"

namespace tristereo::cli {

namespace {

// GPIO stage lines, counted from the first line after the frame line: the
// slots docs/profiling.md documents (kept when the report gained stages).
constexpr int kLineTritree = 0, kLineMatching = 1, kLineInterpolation = 3, kLineMeshOutput = 4;

const char* kProfileHelp = R"(usage: tristereo profile [options]

Runs the pipeline on a stream of frames and reports the per-frame latency of each
stage (min, p50, p90, p99, max, mean, std in ms), fps, CPU time per frame and peak
memory. Frames are prepared before timing starts. See docs/profiling.md.

Frames:
  --frames N           measured frames (default 100)
  --warmup W           frames run first and not measured (default 5)
  --source synthetic|pair|folder   (default: pair if --left, folder if --folder,
                       else synthetic)
  --width W --height H synthetic frame size, 16..4096 (default 640x480)
  --left L --right R   one rectified pair, processed again every frame
  --folder DIR         a sequence DIR/left_0000.png, DIR/right_0000.png, ... (numbering
                       from 0 or 1, cycled if shorter than warm-up + frames)
  --left-pattern P     file name pattern with one %d-style field (default left_%04d.png)
  --right-pattern P    (default right_%04d.png)
Real time and markers:
  --realtime [PRIO]    SCHED_FIFO at PRIO (1..99, default 80) for the frame loop and the
                       workers, and mlockall; needs root or CAP_SYS_NICE + CAP_IPC_LOCK
  --gpio CHIP:LINE[,CHIP:LINE...]   frame line high during each frame; further lines
                       high during tritree, matching, (dp: low), interpolation,
                       mesh output
  --mesh-output        time writing the mesh as binary PLY (to a temp file) as a stage
Reports:
  --csv FILE.csv       one row per measured frame (ms)
  --json FILE.json     the summary (config, per-stage stats, fps, memory, machine)
  --trace FILE.json    the last measured frames as a Chrome trace: one track per
                       worker with its runs and work items, the frames and their
                       stages on a pipeline track; open it in Perfetto
                       (ui.perfetto.dev) or chrome://tracing (docs/profiling.md)
  --trace-frames N     how many frames the trace keeps, 1..100 (default 3)
  --schedule-workers N cut the path passes into work items as for N workers (with
                       --trace, for scripts/scaling_model.py; docs/threads.md)
                       The reports are checked before the run (never an input, a
                       frame of --folder or each other) and written together, all
                       or nothing.
  --quiet              no progress line and no table on stdout
Memory: resident memory is sampled (outside the timed frames) before the first
measured frame, every frames/100 frames and after the last; the JSON's "rss"
has start, end, max and the trace, "drift" the first and last 1000 frames.
)";

constexpr int kDefaultNumDisp = 64;
constexpr std::int64_t kRssSamples = 100;  // resident-memory samples per run (about)

// The model options' help, with --ndisp's "(required)" (true for match and
// verify) replaced by the profiler's default.
std::string profile_model_help() {
  std::string text = stereo_options_help();
  const std::size_t line = text.find("--ndisp");
  const std::size_t required = text.find("(required)", line);
  const std::size_t eol = text.find('\n', line);
  if (line != std::string::npos && required != std::string::npos && required < eol)
    text.replace(required, 10, "(default " + std::to_string(kDefaultNumDisp) + ")");
  return text;
}
constexpr int kDefaultRealtimePriority = 80;
constexpr int kMaxWarmup = 100000;
// Synthetic frames are generated into a ring this long, then cycled: enough
// for the mesh to change every frame without the frames dominating memory.
constexpr int kSyntheticRing = 8;
// Folder frames are preloaded up to this many bytes, then cycled.
constexpr std::size_t kFolderBudgetBytes = std::size_t{256} << 20;

bool is_unsigned_number(const char* s) {
  if (!s || !*s) return false;
  for (; *s; ++s)
    if (*s < '0' || *s > '9') return false;
  return true;
}

// Adapts argv to cli::Args: "--realtime [PRIO]" has an optional value, which
// Args does not model, so it becomes the flag plus --realtime-priority=PRIO;
// and --ndisp gets the profiler's default (match and verify require it).
std::vector<std::string> normalize_args(int argc, char** argv) {
  std::vector<std::string> out;
  bool has_ndisp = false, ended = false;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    ended = ended || a == "--";  // after it, nothing is an option (cli::Args)
    if (ended) {
      out.push_back(a);
      continue;
    }
    if (a == "--ndisp" || a.rfind("--ndisp=", 0) == 0) has_ndisp = true;
    if (a == "--realtime") {
      out.push_back(a);
      if (i + 1 < argc && is_unsigned_number(argv[i + 1]))
        out.push_back(std::string("--realtime-priority=") + argv[++i]);
    } else if (a.rfind("--realtime=", 0) == 0) {
      out.push_back("--realtime");
      out.push_back("--realtime-priority=" + a.substr(11));
    } else {
      out.push_back(a);
    }
  }
  if (!has_ndisp) {  // right after the command's name: before any "--"
    const std::string d[] = {"--ndisp", std::to_string(kDefaultNumDisp)};
    out.insert(out.begin() + 1, d, d + 2);
  }
  return out;
}

int bounded_int(const Args& a, const char* name, int fallback, int lo, int hi) {
  const int v = a.get_int(name, fallback);
  if (v < lo || v > hi)
    throw UsageError(std::string("--") + name + " " + std::to_string(v) + " is outside " +
                     std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

// The frames of the run, already gray and of one size; frame i of the run
// (warm-up included) uses slot i % size().
struct FrameRing {
  std::vector<ImageU8> left, right;
  std::vector<std::string> files;  // the frames read from --folder: no output may name one
  int width = 0, height = 0;
  std::size_t size() const { return left.size(); }
};

void add_pair(FrameRing& ring, const ImageU8& l, const ImageU8& r, const std::string& what) {
  if (l.width != r.width || l.height != r.height)
    throw Error(ErrorCode::kSizeMismatch,
                what + ": left is " + std::to_string(l.width) + "x" + std::to_string(l.height) +
                    " but right is " + std::to_string(r.width) + "x" + std::to_string(r.height));
  if (ring.size() == 0) {
    ring.width = l.width;
    ring.height = l.height;
  } else if (l.width != ring.width || l.height != ring.height) {
    throw Error(ErrorCode::kSizeMismatch,
                what + " is " + std::to_string(l.width) + "x" + std::to_string(l.height) +
                    " but the first frame is " + std::to_string(ring.width) + "x" +
                    std::to_string(ring.height));
  }
  ring.left.push_back(to_gray(l));
  ring.right.push_back(to_gray(r));
}

FrameRing synthetic_frames(int width, int height, int num_disp, int count) {
  FrameRing ring;
  for (int f = 0; f < count; ++f) {
    SynthParams sp;
    sp.width = width;
    sp.height = height;
    sp.num_disp = num_disp;
    sp.frame = f;
    const SyntheticScene scene = make_synthetic_scene(sp);
    add_pair(ring, scene.left, scene.right, "synthetic frame " + std::to_string(f));
  }
  return ring;
}

FrameRing folder_frames(const std::string& dir, const std::string& left_pattern,
                        const std::string& right_pattern, int wanted) {
  FrameRing ring;
  std::size_t bytes = 0;
  for (const SequenceFrame& f : folder_sequence(dir, left_pattern, right_pattern, wanted)) {
    const ImageU8 l = read_image_u8(f.left);
    const ImageU8 r = read_image_u8(f.right);
    add_pair(ring, l, r, "frame '" + f.left + "'");
    ring.files.push_back(f.left);
    ring.files.push_back(f.right);
    bytes += 2 * ring.left.back().pixels.size();
    if (bytes >= kFolderBudgetBytes) break;
  }
  return ring;
}

// A PLY target for --mesh-output: a fresh temp file, removed at the end.
class TempFile {
 public:
  TempFile() {
    const char* tmp = std::getenv("TMPDIR");
    std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/tristereo_profile_XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    const int fd = mkstemp(buf.data());
    if (fd < 0)
      throw Error(ErrorCode::kIoError,
                  "cannot create a temp file '" + templ + "': " + std::strerror(errno));
    close(fd);
    path_ = buf.data();
  }
  ~TempFile() { unlink(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The reports, as text files written all or nothing (output_set.hpp).
void add_report(OutputSet& outputs, const char* option, const std::string& path,
                const std::function<void(std::ostream&)>& write) {
  if (path.empty()) return;
  outputs.add(option, path, [write](const std::string& to) {
    std::ostringstream text;
    write(text);
    write_text_file(to, text.str());
  });
}

}  // namespace

int cmd_profile(int argc, char** argv) {
  const std::vector<std::string> normalized = normalize_args(argc, argv);
  std::vector<char*> nargv;
  for (const std::string& s : normalized) nargv.push_back(const_cast<char*>(s.c_str()));

  std::set<std::string> values = {
      "frames",        "warmup", "source", "left", "right", "folder", "left-pattern",
      "right-pattern", "width",  "height", "gpio", "json",  "csv",    "realtime-priority",
      "trace",         "trace-frames", "schedule-workers"};
  std::set<std::string> flags = {"realtime", "mesh-output", "quiet", "help"};
  add_stereo_options(values, flags);
  add_rig_options(values);
  const Args args(static_cast<int>(nargv.size()), nargv.data(), values, flags);
  if (args.flag("help")) {
    std::cout << kProfileHelp << profile_model_help() << "\n" << rig_options_help() << "\n";
    return 0;
  }
  if (!args.positional().empty())
    throw UsageError("profile takes no positional arguments, got '" + args.positional()[0] + "'");
  // Options that act only beside another (cli_args.hpp, OptionNeed).
  static const std::vector<OptionNeed> kNeeds = {
      {"left-pattern", {"folder"}, nullptr, "it names the left frames in that folder"},
      {"right-pattern", {"folder"}, nullptr, "it names the right frames in that folder"},
      {"trace-frames", {"trace"}, nullptr, "it says how many frames the trace keeps"},
      {"schedule-workers", {"trace"}, nullptr, "it cuts the work for the scaling model's traces"},
      {"rig-right", {"rig"}, nullptr, "it is the right camera's file of a --rig pair"},
  };
  check_option_needs(args, kNeeds);

  // ---- options (all checked before anything is loaded or opened)
  const int frames = bounded_int(args, "frames", 100, 1, static_cast<int>(FrameLog::kMaxFrames));
  const int warmup = bounded_int(args, "warmup", 5, 0, kMaxWarmup);
  const std::string source = args.get("source", args.has("folder") ? "folder"
                                                : args.has("left") ? "pair"
                                                                   : "synthetic");
  if (source != "synthetic" && source != "pair" && source != "folder")
    throw UsageError("--source '" + source + "' is not one of synthetic, pair, folder");
  if (source != "synthetic" && (args.has("width") || args.has("height")))
    throw UsageError("--width/--height set the synthetic frame size; with --source " + source +
                     " the size comes from the images");
  if (source == "pair" && (!args.has("left") || !args.has("right")))
    throw UsageError("--source pair needs --left L and --right R");
  if (source == "folder" && !args.has("folder"))
    throw UsageError("--source folder needs --folder DIR");
  if (source != "pair" && (args.has("left") || args.has("right")))
    throw UsageError("--left/--right belong to --source pair (use --left-pattern with --folder)");
  const std::string left_pattern = args.get("left-pattern", "left_%04d.png");
  const std::string right_pattern = args.get("right-pattern", "right_%04d.png");
  expand_pattern("--left-pattern", left_pattern, 0);
  expand_pattern("--right-pattern", right_pattern, 0);
  const bool realtime = args.flag("realtime");
  if (!realtime && args.has("realtime-priority"))
    throw UsageError("--realtime-priority needs --realtime");
  const int rt_priority = args.get_int("realtime-priority", kDefaultRealtimePriority);
  // Named as typed: "--realtime 0", not the priority's internal name.
  if (realtime) {
    const std::string typed = "--realtime " + std::to_string(rt_priority);
    as_usage_error(typed.c_str(), [&] { validate_realtime_priority(rt_priority); });
  }
  const bool mesh_output = args.flag("mesh-output");
  const std::string trace_path = args.get("trace", "");
  const int trace_frames = bounded_int(args, "trace-frames", 3, 1, 100);
  const bool quiet = args.flag("quiet");
  const std::string gpio_text = args.get("gpio", "");
  std::vector<GpioLineSpec> gpio_lines;
  if (args.has("gpio")) {
    as_usage_error("--gpio", [&] { gpio_lines = parse_gpio_specs(gpio_text); });
    if (!gpio_supported())
      throw Error(ErrorCode::kPlatform,
                  "--gpio " + gpio_text +
                      ": this build has no GPIO support (libgpiod v1 was not "
                      "found at build time; install libgpiod-dev and reconfigure)");
  }
  // Like match's: the format follows the extension, never onto an input or
  // the other report, the folder exists (output_paths.hpp).
  static const std::vector<OutputOption> kReports = {{"csv", {".csv"}}, {"json", {".json"}}, {"trace", {".json"}}};
  check_output_paths(args, kReports,
                     {{"--left", args.get("left", "")}, {"--right", args.get("right", "")},
                      {"--rig", args.get("rig", "")}, {"--rig-right", args.get("rig-right", "")}});
  // The synthetic scene's own limits (make_synthetic_scene: 16..4096 per side).
  const int synth_w = bounded_int(args, "width", 640, 16, kMaxImageSide);
  const int synth_h = bounded_int(args, "height", 480, 16, kMaxImageSide);
  // Validates every model option (and --ndisp) before frames are prepared.
  PipelineConfig config = stereo_config_from_args(args, synth_w, synth_h);

  // ---- frames, prepared before any timing
  const int run_frames = warmup + frames;
  FrameRing ring;
  if (source == "synthetic") {
    ring = synthetic_frames(synth_w, synth_h, config.params.num_disp,
                            std::min(run_frames, kSyntheticRing));
  } else if (source == "pair") {
    add_pair(ring, read_image_u8(args.get("left", "")), read_image_u8(args.get("right", "")),
             "the pair");
  } else {
    ring = folder_frames(args.get("folder", ""), left_pattern, right_pattern, run_frames);
  }
  config.schedule_workers = bounded_int(args, "schedule-workers", 0, 0, 256);
  config.max_width = ring.width;
  config.max_height = ring.height;
  if (args.has("rig")) {
    // Raw frames: the pipeline rectifies them (a stage of its own) into
    // frames of the rectified size.
    if (source == "synthetic") throw UsageError("--rig needs raw frames: --left/--right or --folder");
    const LoadedRig rig = load_rig(args, ring.width, ring.height);
    config.rectify = rig.maps;
    config.max_width = rig.maps->left.width;
    config.max_height = rig.maps->left.height;
    config.params = stereo_config_from_args(args, config.max_width, config.max_height).params;
  }

  // The frames of --folder are inputs too, known once read (before any computing).
  for (const char* option : {"csv", "json", "trace"})
    for (const std::string& frame : ring.files)
      if (args.has(option) && same_file(args.get(option, ""), frame))
        throw UsageError(std::string("--") + option + " " + args.get(option, "") + " is the frame '" + frame +
                         "' of --folder; refusing to overwrite an input (choose another output name)");
  const std::string csv_path = args.get("csv", ""), json_path = args.get("json", "");
  std::unique_ptr<TempFile> ply;
  if (mesh_output) ply = std::make_unique<TempFile>();

  // ---- markers, scheduling, pipeline
  std::unique_ptr<FrameMarker> marker;
  if (!gpio_lines.empty()) marker = open_gpio_marker(gpio_lines, "tristereo-profile");
  FrameMarkerDriver markers(marker.get());
  // Before configure(): the pipeline's workers are created there and inherit
  // the calling thread's SCHED_FIFO policy (PTHREAD_INHERIT_SCHED).
  // The guard puts this thread back to its old policy and unlocks memory on
  // every exit path; it is declared before the pipeline, so it runs after
  // the workers have been joined.
  struct RealtimeGuard {
    bool on = false;
    ThreadScheduling saved = current_thread_scheduling();
    ~RealtimeGuard() {
      if (!on) return;
      restore_thread_scheduling(saved);
      unlock_memory();
    }
  } rt_guard;
  if (realtime) {
    enable_realtime(rt_priority);
    rt_guard.on = true;
  }

  // GPIO stage lines (docs/profiling.md): slot 1 tritree, 2 the matching
  // interval (cost aggregation and DP interleave per row), 3 dp (stays low),
  // 4 interpolation, 5 mesh output; the fill has no line.
  struct MarkerListener : StageListener {
    FrameMarkerDriver* driver;
    explicit MarkerListener(FrameMarkerDriver* d) : driver(d) {}
    void on_stage(PipelineStage s, bool begin) noexcept override {
      int stage = kLineTritree;
      if (s == PipelineStage::kMatching) stage = kLineMatching;
      if (s == PipelineStage::kInterpolation) stage = kLineInterpolation;
      if (begin)
        driver->stage_begin(stage);
      else
        driver->stage_end(stage);
    }
  } listener(&markers);

  Pipeline pipeline;
  pipeline.configure(config);
  if (markers.enabled()) pipeline.set_stage_listener(&listener);
  // The trace keeps the last trace_frames measured frames; its storage is
  // reserved here, for the most spans such a frame can give (a path tile per
  // 16 pixels of a row in each pass, rows of costs and interpolation tiles).
  FrameTrace trace;
  if (!trace_path.empty()) {
    const std::size_t per_frame = 2 * static_cast<std::size_t>(ring.height) * (ring.width / 16 + 2) +
                                  4 * static_cast<std::size_t>(ring.height) + 256;
    trace.reserve(pipeline.worker_count(), per_frame * static_cast<std::size_t>(trace_frames));
    trace.set_enabled(false);
    pipeline.set_trace(&trace);
  }
  FrameLog log(static_cast<std::size_t>(frames));
  RssTrace rss(frames, RssTrace::interval_for(frames, kRssSamples));
  ProgressLine progress(quiet);
  ProfileOutputCheck output_check;

  std::vector<ImageView<const std::uint8_t>> lefts, rights;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    lefts.push_back(std::as_const(ring.left[k]).view());
    rights.push_back(std::as_const(ring.right[k]).view());
  }

  // ---- the frame loop
  std::int64_t loop_start_ns = 0;
  for (int i = 0; i < run_frames; ++i) {
    const bool measured = i >= warmup;
    if (i == warmup) {
      rss.push(0, current_rss_bytes());
      loop_start_ns = monotonic_ns();
    }
    const std::size_t slot = static_cast<std::size_t>(i) % ring.size();
    if (!trace_path.empty()) trace.set_enabled(i >= std::max(warmup, run_frames - trace_frames));
    const std::int64_t cpu0 = process_cpu_ns();
    const std::int64_t t0 = monotonic_ns();
    markers.frame_begin();
    const StereoOutput& out = pipeline.process(lefts[slot], rights[slot]);
    std::int64_t mesh_ns = 0;
    if (mesh_output) {
      markers.stage_begin(kLineMeshOutput);
      const std::int64_t m0 = monotonic_ns();
      write_mesh_ply(ply->path(), out.mesh, out.vertex_disp_q4, lefts[slot], nullptr, true);
      mesh_ns = monotonic_ns() - m0;
      markers.stage_end(kLineMeshOutput);
    }
    markers.frame_end();
    const std::int64_t t1 = monotonic_ns();
    const std::int64_t cpu1 = process_cpu_ns();

    if (measured) {
      const FrameTimings& t = pipeline.last_timings();
      FrameSample s;
      s.stage_ns[static_cast<int>(ProfileStage::kRectify)] = t.rectify_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kTritree)] = t.tritree_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kCostAggregation)] = t.cost_aggregation_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kDp)] = t.dp_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kPrior)] = t.prior_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kRightPass)] = t.right_pass_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kFill)] = t.fill_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kInterpolation)] = t.interpolation_ns;
      s.stage_ns[static_cast<int>(ProfileStage::kMeshOutput)] = mesh_ns;
      s.total_ns = t1 - t0;
      s.cpu_ns = cpu1 - cpu0;
      log.push(s);
      const int done = i - warmup + 1;
      if (rss.due(done)) rss.push(done, current_rss_bytes());  // outside the timed frame
      // Outside the timed frame too; the digest's strings are made only twice.
      if (i == warmup) {
        output_check.first_frame = 0;
        output_check.first_input = static_cast<std::int64_t>(slot);
        output_check.first_digest = digest_hex(out);
      }
      if (i == run_frames - 1) {
        output_check.has = true;
        output_check.last_frame = done - 1;
        output_check.last_input = static_cast<std::int64_t>(slot);
        output_check.last_digest = digest_hex(out);
      }
      progress.update("frame", done, frames, s.total_ns);
    } else {
      progress.update("warm-up", i + 1, warmup, t1 - t0);
    }
  }
  const std::int64_t wall_ns = monotonic_ns() - loop_start_ns;
  progress.clear();

  // ---- reports
  ProfileRunConfig rc;
  rc.source = source;
  rc.width = ring.width;
  rc.height = ring.height;
  rc.num_disp = config.params.num_disp;
  rc.d_min = config.params.d_min;
  rc.dense = config.params.dense;
  rc.weights = to_string(config.params.cost.weights);
  rc.window_w = config.params.cost.window_w;
  rc.window_h = config.params.cost.window_h;
  rc.psnr_db = config.params.tritree.psnr_deci_db / 10.0;
  rc.max_area_px2 = config.params.tritree.max_area_px2;
  rc.min_area_px2 = config.params.tritree.min_area_px2;
  rc.threads = pipeline.worker_count();
  rc.kernels = to_string(pipeline.active_kernels());
  rc.cpus = config.cpus;
  rc.realtime = realtime;
  rc.realtime_priority = realtime ? rt_priority : 0;
  rc.gpio = gpio_text;
  rc.mesh_output = mesh_output;
  rc.rectify = config.rectify != nullptr;
  rc.prior = support_prior_applies(config.params);
  rc.right_pass = config.params.validity.lr_max_diff_q4 >= 0 &&
                  config.params.validity.lr_source == LrSource::kMirroredPass;
  rc.warmup_frames = warmup;
  rc.frames = frames;
  rc.working_memory_bytes = static_cast<std::int64_t>(pipeline.working_memory_bytes());
  const ProfileMachine machine{cpu_model_name(), online_cpu_count()};
  const ProfileReport report = make_profile_report(rc, log, wall_ns, peak_rss_bytes(), machine, &rss, &output_check);

  OutputSet outputs;
  add_report(outputs, "--csv", csv_path, [&](std::ostream& os) { write_frames_csv(os, log, rc); });
  add_report(outputs, "--json", json_path, [&](std::ostream& os) { write_profile_json(os, report); });
  if (!trace_path.empty())
    outputs.add("--trace", trace_path, [&](const std::string& to) { write_chrome_trace(trace, to); });
  outputs.commit();
  if (trace.dropped() > 0)
    std::cerr << "tristereo profile: warning: the trace's storage was full, " << trace.dropped()
              << " spans were dropped\n";
  if (!quiet) write_profile_table(std::cout, report);
  return 0;
}

}  // namespace tristereo::cli
