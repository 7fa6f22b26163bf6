// libFuzzer harness: the tristereo command line. The input is the argument
// list, one argument per line ("match\nleft.png\nright.png\n--ndisp\n8"), run
// through the program's own main() (apps/tristereo_main.cpp compiled with its
// main renamed, see CMakeLists.txt), run in a scratch folder that holds a
// small synthetic pair, its ground truth, a KITTI-scaled disparity PNG and a
// calib.txt. Checked: no crash, no sanitizer report, no exception escaping
// main, an exit code of 0, 1 or 2. TRISTEREO_FUZZ_VERBOSE=1 shows the
// program's output and each input's exit code.
//
// Safety and time bounds (an input outside them is rejected with -1, so it
// never enters the corpus):
//  - no argument may contain '/' or be "..": every path is a name inside the
//    scratch folder, so nothing is written outside it; after every run the
//    folder is put back (new files removed, changed fixtures rewritten);
//  - no --realtime (SCHED_FIFO and mlockall) and no --gpio (hardware lines);
//  - work is bounded: synthetic sizes (demo, synth, profile) must be given
//    and at most 64x64, the image files are the 32x24 fixtures (an input runs
//    one command, and the folder is restored before the next),
//    W * H * D * window area <= kWorkBudget (verify and --reference run the
//    float reference, ~1.8 us per term under the sanitizers), at most 4
//    frames, 5 warm-up frames (the default), 4 threads and 4 thread counts.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <streambuf>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_support.hpp"
#include "tristereo/calib.hpp"
#include "tristereo/io.hpp"
#include "tristereo/synth.hpp"

int tristereo_cli_main(int argc, char** argv);  // apps/tristereo_main.cpp's main

using namespace tristereo;
using namespace tristereo::fuzz;

namespace {

constexpr int kMaxArgs = 48;
constexpr long kMaxSide = 64;
constexpr int kFixtureWidth = 32, kFixtureHeight = 24;
constexpr long kMaxFrames = 4;
constexpr long kMaxThreads = 4;
constexpr std::int64_t kWorkBudget = 250000;

struct NullBuffer : std::streambuf {
  int overflow(int c) override { return c; }
};

struct Fixture {
  std::string name;
  std::vector<std::uint8_t> bytes;
  struct stat st {};
};

std::vector<Fixture>& fixtures() {
  static std::vector<Fixture> f;
  return f;
}

std::vector<std::uint8_t> slurp(const std::string& path) {
  std::vector<std::uint8_t> out;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) fail("cannot read fixture '" + path + "'");
  std::uint8_t buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) out.insert(out.end(), buf, buf + n);
  std::fclose(f);
  return out;
}

bool same_stat(const struct stat& a, const struct stat& b) {
  return a.st_ino == b.st_ino && a.st_size == b.st_size && a.st_mode == b.st_mode &&
         a.st_mtim.tv_sec == b.st_mtim.tv_sec && a.st_mtim.tv_nsec == b.st_mtim.tv_nsec;
}

void record(Fixture& f) {
  if (lstat(f.name.c_str(), &f.st) != 0) fail("cannot stat fixture '" + f.name + "'");
}

void make_fixtures() {
  SynthParams sp;
  sp.width = kFixtureWidth;
  sp.height = kFixtureHeight;
  sp.num_disp = 8;
  const SyntheticScene scene = make_synthetic_scene(sp);
  write_png_u8("left.png", scene.left.view());
  write_png_u8("right.png", scene.right.view());
  write_pgm("left.pgm", scene.left.view());
  write_pfm("disp_left.pfm", scene.disp_left.view());
  write_png_u8("nonocc.png", scene.nonocc_mask.view());
  ImageS16 q4(sp.width, sp.height, 1);
  for (std::size_t i = 0; i < q4.pixels.size(); ++i)
    q4.pixels[i] = static_cast<std::int16_t>(scene.disp_left.pixels[i] * 16);
  write_disparity("disp_kitti.png", q4.view(), DispPngScale::kKitti);
  write_disparity("disp_q4.png", q4.view(), DispPngScale::kQ4);
  const std::string calib =
      "cam0=[40 0 16; 0 40 12; 0 0 1]\ncam1=[40 0 17; 0 40 12; 0 0 1]\ndoffs=1\n"
      "baseline=100\nwidth=" + std::to_string(kFixtureWidth) +
      "\nheight=" + std::to_string(kFixtureHeight) + "\n";
  std::FILE* f = std::fopen("calib.txt", "wb");
  if (!f || std::fwrite(calib.data(), 1, calib.size(), f) != calib.size() || std::fclose(f) != 0)
    fail("cannot write calib.txt");
  for (const char* name : {"left.png", "right.png", "left.pgm", "disp_left.pfm", "nonocc.png",
                           "disp_kitti.png", "disp_q4.png", "calib.txt"}) {
    Fixture fx;
    fx.name = name;
    fx.bytes = slurp(name);
    record(fx);
    fixtures().push_back(fx);
  }
}

// Puts the scratch folder back as make_fixtures() left it.
void restore_scratch() {
  std::error_code ec;
  std::vector<std::filesystem::path> extra;
  for (const auto& e : std::filesystem::directory_iterator(".", ec)) {
    const std::string name = e.path().filename().string();
    bool known = false;
    for (const Fixture& f : fixtures()) known = known || f.name == name;
    if (!known) extra.push_back(e.path());
  }
  for (const auto& p : extra) std::filesystem::remove_all(p, ec);
  for (Fixture& f : fixtures()) {
    struct stat now {};
    if (lstat(f.name.c_str(), &now) == 0 && same_stat(now, f.st)) continue;
    std::filesystem::remove_all(f.name, ec);
    const std::string path = write_scratch(f.name, f.bytes);
    (void)path;
    record(f);
  }
}

// strtol-style integer (as cli::parse_int reads it); false if it is not one.
bool as_long(const std::string& s, long& v) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  v = std::strtol(s.c_str(), &end, 10);
  return *end == '\0' && errno == 0;
}

// Values of option `name` ("--name V" and "--name=V" forms), every occurrence.
std::vector<std::string> values_of(const std::vector<std::string>& args, const std::string& name) {
  std::vector<std::string> out;
  const std::string flag = "--" + name, prefix = flag + "=";
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == flag && i + 1 < args.size()) out.push_back(args[i + 1]);
    if (args[i].rfind(prefix, 0) == 0) out.push_back(args[i].substr(prefix.size()));
  }
  return out;
}

// The largest integer given for `name` (fallback when none parses), and
// false when one exceeds `limit` in magnitude.
bool bounded(const std::vector<std::string>& args, const std::string& name, long limit,
             long fallback, long& value) {
  value = fallback;
  bool any = false;
  for (const std::string& s : values_of(args, name)) {
    long v;
    if (!as_long(s, v)) continue;  // not a number: the parser must refuse it
    if (v > limit || v < -limit) return false;
    value = any ? std::max(value, v) : v;
    any = true;
  }
  return true;
}

bool within_bounds(const std::vector<std::string>& args) {
  for (const std::string& a : args) {
    if (a.find('/') != std::string::npos || a == ".." || a.find('\0') != std::string::npos)
      return false;
    if (a.rfind("--realtime", 0) == 0 || a.rfind("--gpio", 0) == 0) return false;
  }
  const std::string& cmd = args[0];
  const bool synthetic = cmd == "demo" || cmd == "synth" ||
                         (cmd == "profile" && values_of(args, "left").empty() &&
                          values_of(args, "folder").empty());
  // Synthetic frames default to 640x480: require small explicit sizes.
  const long default_w = synthetic ? 640 : kFixtureWidth, default_h = synthetic ? 480 : kFixtureHeight;
  long w, h, d, frames, warmup, threads;  // warm-up: default 5, tiny frames
  if (!bounded(args, "width", kMaxSide, default_w, w) || !bounded(args, "height", kMaxSide, default_h, h) ||
      w > kMaxSide || h > kMaxSide)
    return false;
  if (!bounded(args, "ndisp", 1 << 20, 64, d) || !bounded(args, "frames", kMaxFrames, 100, frames) ||
      !bounded(args, "warmup", kMaxFrames, 5, warmup) || !bounded(args, "threads", kMaxThreads, 0, threads))
    return false;
  if (cmd == "profile" && frames > kMaxFrames) return false;  // the default is 100
  for (const std::string& list : values_of(args, "thread-counts")) {
    int items = 0;
    std::size_t start = 0;
    while (start <= list.size()) {
      const std::size_t comma = std::min(list.find(',', start), list.size());
      long t;
      if (as_long(list.substr(start, comma - start), t) && (t > kMaxThreads || t < -kMaxThreads))
        return false;
      if (++items > 4) return false;
      start = comma + 1;
    }
  }
  long ww = 5, wh = 5;
  for (const std::string& s : values_of(args, "window")) {
    const std::size_t x = s.find('x');
    long a = 0, b = 0;
    const bool ok = x == std::string::npos ? (as_long(s, a) && (b = a, true))
                                           : as_long(s.substr(0, x), a) && as_long(s.substr(x + 1), b);
    if (!ok) continue;
    if (a > 31 || b > 31 || a < -31 || b < -31) return false;
    ww = std::max(ww, std::labs(a));
    wh = std::max(wh, std::labs(b));
  }
  d = std::max(1L, std::min(std::labs(d), 256L));
  return std::int64_t{w} * h * d * ww * wh <= kWorkBudget;
}

}  // namespace

// The program runs inside the scratch folder, and only while it runs:
// libFuzzer resolves its own relative paths (corpus folders, artifacts)
// against the folder it was started in.
class InScratch {
 public:
  InScratch() {
    if (chdir(scratch_dir().c_str()) != 0) fail("chdir('" + scratch_dir() + "'): " + std::strerror(errno));
  }
  ~InScratch() {
    if (fchdir(home_fd()) != 0) fail(std::string("fchdir back: ") + std::strerror(errno));
  }
  static int home_fd() {
    static const int fd = open(".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    return fd;
  }
};

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const std::string& dir = scratch_dir();
  setenv("TMPDIR", dir.c_str(), 1);  // profile --mesh-output's temp file lands here too
  if (InScratch::home_fd() < 0) fail(std::string("open('.'): ") + std::strerror(errno));
  {
    InScratch in_scratch;
    make_fixtures();
  }
  // The program's messages are not findings; sanitizer reports go to fd 2.
  // TRISTEREO_FUZZ_VERBOSE=1 keeps them and prints each exit code.
  if (std::getenv("TRISTEREO_FUZZ_VERBOSE")) return 0;
  static NullBuffer null;
  std::cout.rdbuf(&null);
  std::cerr.rdbuf(&null);
  const int devnull = open("/dev/null", O_WRONLY);
  if (devnull >= 0) {
    dup2(devnull, STDOUT_FILENO);
    close(devnull);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args;
  std::string cur;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == '\n') {
      args.push_back(cur);
      cur.clear();
    } else {
      cur += static_cast<char>(data[i]);
    }
  }
  if (!cur.empty() || args.empty()) args.push_back(cur);
  if (args.size() > kMaxArgs || !within_bounds(args)) return -1;

  std::vector<std::string> storage = {"tristereo"};
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : storage) argv.push_back(s.data());
  argv.push_back(nullptr);
  InScratch in_scratch;
  int rc = -1;
  try {
    rc = tristereo_cli_main(static_cast<int>(storage.size()), argv.data());
  } catch (const std::exception& e) {
    fail(std::string("an exception escaped main: ") + e.what());
  } catch (...) {
    fail("an unknown exception escaped main");
  }
  static const bool verbose = std::getenv("TRISTEREO_FUZZ_VERBOSE") != nullptr;
  if (verbose) {
    std::string line;
    for (const std::string& a : args) line += " '" + a + "'";
    std::fprintf(stderr, "cli:%s -> exit %d\n", line.c_str(), rc);
  }
  TRISTEREO_FUZZ_CHECK(rc == 0 || rc == 1 || rc == 2, "exit code " + std::to_string(rc));
  restore_scratch();
  return 0;
}
