// tristereo match --folder DIR | --list FILE: every pair of a recorded run.
//
// The pipeline is configured once, for the first readable frame's size. A
// reader thread decodes the next frames while the current one is matched,
// into a ring of kSlots slots (a bounded queue: it is at most kSlots - 1
// frames ahead). What allocates per frame: the decoder's own image buffers
// (moved into the slot), the per-frame output names, and the writers of the
// outputs and their OutputSet (as in a one-pair run); the pipeline itself
// allocates nothing after configure() (tests/no_alloc_test.cpp).
//
// A bad frame (unreadable or corrupt file, missing right image, another size
// than the first frame, an output that cannot be written) is reported on
// stderr with its files and skipped: its outputs are all or nothing like a
// one-pair run's, and the run goes on. The exit code is 1 if any failed.
#include "apps/match_sequence.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "apps/frame_sequence.hpp"
#include "apps/match_outputs.hpp"
#include "apps/match_warnings.hpp"
#include "apps/output_paths.hpp"
#include "apps/stereo_options.hpp"
#include "apps/stereo_pair.hpp"
#include "platform/clock.hpp"
#include "platform/thread_pool.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {

constexpr int kSlots = 3;
constexpr int kMaxFrames = 10000000;

// The outputs written once per frame: their values are name patterns.
const char* const kFrameOutputs[] = {"disp", "disp-color", "mesh", "depth", "points", "samples", "valid", "confidence"};

// A decoded frame, or why it could not be.
struct Slot {
  int index = -1;  // in the sequence
  ImageU8 left, right;
  std::string error;  // empty: decoded
  ErrorCode code = ErrorCode::kIoError;
};

// The reader thread's ring: it fills slot produced % kSlots while fewer than
// kSlots are waiting, the matcher empties slot consumed % kSlots. A slot is
// touched without the lock by its one owner of the moment.
class FrameQueue {
 public:
  Slot& slot(int n) { return slots_[static_cast<std::size_t>(n % kSlots)]; }
  // Producer: waits for a free slot; false when the run was stopped.
  bool wait_free(int n) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return stop_ || n - consumed_ < kSlots; });
    return !stop_;
  }
  void publish() {
    std::lock_guard<std::mutex> lock(mutex_);
    ++produced_;
    changed_.notify_all();
  }
  // Consumer: waits until frame n is decoded.
  void wait_ready(int n) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return produced_ > n; });
  }
  void release() {
    std::lock_guard<std::mutex> lock(mutex_);
    ++consumed_;
    changed_.notify_all();
  }
  void stop() {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    changed_.notify_all();
  }

 private:
  Slot slots_[kSlots];
  std::mutex mutex_;
  std::condition_variable changed_;
  int produced_ = 0, consumed_ = 0;
  bool stop_ = false;
};

// --stats FILE.jsonl: one line per frame, written as they come to a temporary
// beside the target (flushed per line) and renamed into place at the end; a
// device or FIFO target is written in place.
class JsonLines {
 public:
  explicit JsonLines(const std::string& target) : target_(target) {
    struct stat st {};
    const bool special = ::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
    path_ = special ? target
                    : folder_of(target) + "/." + name_of(target) + ".tmp-" + std::to_string(::getpid()) + ".jsonl";
    file_ = std::fopen(path_.c_str(), "w");
    if (!file_) throw Error(ErrorCode::kIoError, "--stats: cannot write '" + target + "': " + std::strerror(errno));
    temp_ = !special;
  }
  ~JsonLines() {
    if (file_) std::fclose(file_);
    if (temp_) std::remove(path_.c_str());
  }
  JsonLines(const JsonLines&) = delete;
  JsonLines& operator=(const JsonLines&) = delete;
  void write(const std::string& line) {
    if (std::fputs(line.c_str(), file_) < 0 || std::fputc('\n', file_) < 0 || std::fflush(file_) != 0)
      throw Error(ErrorCode::kIoError, "--stats: cannot write '" + target_ + "': " + std::strerror(errno));
  }
  void commit() {
    const bool ok = ::fsync(::fileno(file_)) == 0 || !temp_;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed)
      throw Error(ErrorCode::kIoError, "--stats: cannot write '" + target_ + "': " + std::strerror(errno));
    if (temp_ && std::rename(path_.c_str(), target_.c_str()) != 0)
      throw Error(ErrorCode::kIoError, "--stats: cannot rename into '" + target_ + "': " + std::strerror(errno));
    temp_ = false;
  }

 private:
  std::string target_, path_;
  std::FILE* file_ = nullptr;
  bool temp_ = false;
};

double p50_ms(std::vector<std::int64_t>& v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return static_cast<double>(*mid) / 1e6;
}

// Every frame's expanded output names, checked before the run: never an
// input of any frame (by device and inode), never one name twice.
void check_sequence_outputs(const Args& args, const std::vector<SequenceFrame>& frames) {
  std::set<std::pair<dev_t, ino_t>> inputs;
  for (const SequenceFrame& f : frames)
    for (const std::string* p : {&f.left, &f.right}) {
      struct stat st {};
      if (::stat(p->c_str(), &st) == 0) inputs.insert({st.st_dev, st.st_ino});
    }
  std::set<std::string> names;
  const auto check = [&](const std::string& option, const std::string& path, const SequenceFrame* f) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && inputs.count({st.st_dev, st.st_ino}))
      throw UsageError(option + " " + path + " is an input of the sequence" +
                       (f ? " (written for frame " + std::to_string(f->number) + ")" : std::string()) +
                       "; refusing to overwrite an input (choose another output name)");
    if (!names.insert(path).second)
      throw UsageError(option + " " + path + " is written twice" +
                       (f ? " (for frame " + std::to_string(f->number) + ")" : std::string()) +
                       "; give each output its own name");
  };
  if (args.has("stats")) check("--stats", args.get("stats", ""), nullptr);
  for (const SequenceFrame& f : frames)
    for (const char* o : kFrameOutputs)
      if (args.has(o)) check(std::string("--") + o, expand_pattern(std::string("--") + o, args.get(o, ""), f.number), &f);
}

}  // namespace

void add_sequence_options(std::set<std::string>& values, std::set<std::string>& flags) {
  values.insert({"folder", "list", "left-pattern", "right-pattern"});
  flags.insert("quiet");
}

const char* sequence_help() {
  return R"(Sequences (a recorded run in one process; instead of LEFT RIGHT):
  --folder DIR              the pairs DIR/left_0000.png, DIR/right_0000.png, ... numbered
                            from 0 or 1, up to the first missing left file
  --left-pattern P          left file names in DIR, one %d-style field (default left_%04d.png)
  --right-pattern P         (default right_%04d.png)
  --list FILE               one "LEFT RIGHT" pair of paths per line, relative to FILE's
                            folder; lines starting with '#' are comments; frames numbered
                            from 0 in the list's order
  The output options --disp, --disp-color, --mesh, --depth, --points, --samples are then
  name patterns with exactly one %d-style field (e.g. out/disp_%04d.pfm), which gets the
  frame's number; each frame's outputs are all or nothing. --stats FILE.jsonl writes one
  JSON line per frame (--stats's object, with "frame", "left" and "right"). The pipeline
  is configured for the first frame's size; the next frames are decoded while one is
  matched. A bad frame (corrupt or missing file, another size) is named on stderr and
  skipped, and the run goes on: exit 1 if any frame failed. At the end stdout has a
  summary (frames done and failed, fps, median ms per stage); a progress line is shown
  on stderr when it is a terminal.
  --quiet                   no summary, no progress line
)";
}

int match_sequence(const Args& args) {
  if (!args.positional().empty())
    throw UsageError(std::string("--") + (args.has("folder") ? "folder" : "list") +
                     " names the frames: no LEFT RIGHT paths beside it (got '" + args.positional()[0] + "')");
  if (args.has("folder") && args.has("list")) throw UsageError("--folder and --list both name the frames: give one");
  for (const char* alone : {"reference", "rig", "rig-right"})
    if (args.has(alone))
      throw UsageError(std::string("--") + alone + " is for one pair; it is not supported with --folder or --list");
  // Every option is checked before any frame is read.
  (void)stereo_config_from_args(args, 2, 2);
  (void)depth_limits_from_args(args);
  const std::string left_pattern = args.get("left-pattern", "left_%04d.png");
  const std::string right_pattern = args.get("right-pattern", "right_%04d.png");
  expand_pattern("--left-pattern", left_pattern, 0);
  expand_pattern("--right-pattern", right_pattern, 0);
  for (const char* o : kFrameOutputs)
    if (args.has(o)) expand_pattern(std::string("--") + o, args.get(o, ""), 0);
  const bool quiet = args.flag("quiet");

  const std::vector<SequenceFrame> frames =
      args.has("folder") ? folder_sequence(args.get("folder", ""), left_pattern, right_pattern, kMaxFrames)
                         : list_sequence(args.get("list", ""));
  // The first frame's names through match's checks (extensions, folders,
  // inputs, each other), then every frame's names against every input.
  {
    Args first = args;
    for (const char* o : kFrameOutputs)
      if (args.has(o)) first.set(o, expand_pattern(std::string("--") + o, args.get(o, ""), frames[0].number));
    std::vector<OutputOption> outputs;
    for (const OutputOption& o : match_output_options())
      outputs.push_back(std::string(o.option) == "stats" ? OutputOption{"stats", {".jsonl"}} : o);
    check_output_paths(first, outputs,
                       {{"LEFT", frames[0].left}, {"RIGHT", frames[0].right}, {"--list", args.get("list", "")},
                        {"--calib", args.get("calib", "")}});
    check_sequence_outputs(args, frames);
  }
  std::optional<JsonLines> stats;
  if (args.has("stats")) stats.emplace(args.get("stats", ""));

  // ---- the reader thread: decodes frame n into slot n % kSlots.
  FrameQueue queue;
  const int total = static_cast<int>(frames.size());
  std::thread reader([&] {
    for (int n = 0; n < total; ++n) {
      if (!queue.wait_free(n)) return;
      Slot& s = queue.slot(n);
      s.index = n;
      s.error.clear();
      try {
        s.left = read_image_u8(frames[n].left);
        s.right = read_image_u8(frames[n].right);
      } catch (const Error& e) {
        s.error = e.what();
        s.code = e.code();
      } catch (const std::exception& e) {
        s.error = e.what();
        s.code = ErrorCode::kIoError;
      }
      queue.publish();
    }
  });
  struct Joiner {
    FrameQueue& q;
    std::thread& t;
    ~Joiner() {
      q.stop();
      t.join();
    }
  } joiner{queue, reader};

  // ---- the frame loop
  Pipeline pipeline;
  PipelineConfig config;
  MatchRun run;
  bool configured = false;
  int width = 0, height = 0, done = 0, failed = 0;
  Args frame_args = args;
  frame_args.unset("stats");  // the run's, not each frame's
  std::vector<std::int64_t> t_tritree, t_cost, t_paths, t_right, t_fill, t_interp, t_total, t_wait, t_write;
  for (auto* v : {&t_tritree, &t_cost, &t_paths, &t_right, &t_fill, &t_interp, &t_total, &t_wait, &t_write})
    v->reserve(frames.size());
  ProgressLine progress(quiet);
  std::int64_t loop_start_ns = 0, last_ns = 0;
  bool configuring = false;  // errors there stop the run (the options, not the frame)
  for (int n = 0; n < total; ++n) {
    const SequenceFrame& f = frames[static_cast<std::size_t>(n)];
    const std::int64_t t0 = monotonic_ns();
    queue.wait_ready(n);
    Slot& s = queue.slot(n);
    const std::int64_t t_ready = monotonic_ns();
    try {
      if (!s.error.empty()) throw Error(s.code, s.error);
      check_stereo_pair(f.left, s.left, f.right, s.right);
      if (!configured) {
        configuring = true;
        // The first readable frame sets the size, the camera and the warnings.
        width = s.left.width;
        height = s.left.height;
        config = stereo_config_from_args(args, width, height);
        check_disp_output(args, config.params);
        run.config = config;
        run.camera = camera_from_args(args, width, height, &run.camera_source);
        run.depth_limits = depth_limits_from_args(args);
        const StereoParams& p = config.params;
        const ImageU8 lg = s.left.channels == 1 ? ImageU8() : to_gray(s.left);
        const ImageU8 rg = s.right.channels == 1 ? ImageU8() : to_gray(s.right);
        for (const std::string& w :
             {swapped_warning(s.left.channels == 1 ? s.left.view() : lg.view(),
                              s.right.channels == 1 ? s.right.view() : rg.view(), p.d_min, p.num_disp),
              range_outside_image_warning(width, p.d_min, p.num_disp),
              run.camera ? no_depth_warning(*run.camera,
                                            run.camera_source == "--camera" ? run.camera_source
                                                                            : "--calib " + run.camera_source,
                                            p.d_min, p.num_disp)
                         : std::string(),
              threads_warning(config.threads,
                              static_cast<int>(config.cpus.empty() ? ThreadPool::available_cpus().size()
                                                                   : config.cpus.size()),
                              !config.cpus.empty())})
          if (!w.empty()) std::cerr << w << "\n";
        pipeline.configure(config);
        run.implementation = std::string("integer/") + to_string(pipeline.active_kernels());
        run.threads = pipeline.worker_count();
        configured = true;
        configuring = false;
        loop_start_ns = monotonic_ns();
      } else if (s.left.width != width || s.left.height != height) {
        throw Error(ErrorCode::kSizeMismatch, "the pair is " + std::to_string(s.left.width) + "x" +
                                                  std::to_string(s.left.height) + " but the sequence's first frame is " +
                                                  std::to_string(width) + "x" + std::to_string(height));
      }
      run.result = &pipeline.process(s.left.view(), s.right.view());
      run.timings = pipeline.last_timings();
      const std::int64_t t_done = monotonic_ns();
      for (const char* o : kFrameOutputs)
        if (args.has(o)) frame_args.set(o, expand_pattern(std::string("--") + o, args.get(o, ""), f.number));
      write_match_outputs(frame_args, s.left, run);
      if (stats) stats->write(stats_json_line(run, f.number, f.left, f.right));
      const std::int64_t t_end = monotonic_ns();
      ++done;
      t_tritree.push_back(run.timings.tritree_ns);
      t_cost.push_back(run.timings.cost_aggregation_ns);
      t_paths.push_back(run.timings.dp_ns);
      t_right.push_back(run.timings.right_pass_ns);
      t_fill.push_back(run.timings.fill_ns);
      t_interp.push_back(run.timings.interpolation_ns);
      t_total.push_back(run.timings.total_ns);
      t_wait.push_back(t_ready - t0);
      t_write.push_back(t_end - t_done);
      last_ns = t_end - t0;
    } catch (const UsageError&) {
      throw;  // an option that does not fit the frames (e.g. --camera): the run's error
    } catch (const Error& e) {
      if (configuring) throw;
      progress.clear();
      ++failed;
      std::cerr << "tristereo match: frame " << f.number << " (" << f.left << ", " << f.right
                << ") skipped: error (" << error_code_name(e.code()) << "): " << e.what() << "\n";
    }
    queue.release();
    progress.update("frame", n + 1, total, failed, last_ns);
  }
  const std::int64_t wall_ns = monotonic_ns() - loop_start_ns;
  progress.clear();
  if (stats) stats->commit();
  if (!quiet) {
    char buf[1024];
    const double fps = done > 0 && wall_ns > 0 ? done / (static_cast<double>(wall_ns) / 1e9) : 0.0;
    std::snprintf(buf, sizeof buf,
                  "%d frames: %d done, %d failed; %.2f fps (%dx%d, %s, %d threads)\n"
                  "median ms: tritree %.2f, cost aggregation %.2f, %s %.2f, right view %.2f, fill %.2f, "
                  "interpolation %.2f, frame %.2f; waiting for the reader %.2f, outputs %.2f\n",
                  total, done, failed, fps, width, height, run.implementation.c_str(), run.threads,
                  p50_ms(t_tritree), p50_ms(t_cost), config.params.optimizer == Optimizer::kPaths ? "paths" : "dp",
                  p50_ms(t_paths), p50_ms(t_right), p50_ms(t_fill), p50_ms(t_interp), p50_ms(t_total),
                  p50_ms(t_wait), p50_ms(t_write));
    std::cout << buf;
  }
  return failed > 0 ? 1 : 0;
}

}  // namespace tristereo::cli
