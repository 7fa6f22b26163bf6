#include "tests/fuzz/fuzz_support.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace tristereo::fuzz {

namespace {

// Memory-backed when possible: every input is written to a file, and on a
// disk-backed /tmp creating it costs milliseconds (300 executions per second
// instead of several thousand).
std::string scratch_parent() {
  const char* chosen = std::getenv("TRISTEREO_FUZZ_TMPDIR");
  if (chosen && *chosen) return chosen;
  if (access("/dev/shm", W_OK | X_OK) == 0) return "/dev/shm";
  const char* tmp = std::getenv("TMPDIR");
  return tmp && *tmp ? tmp : "/tmp";
}

std::string make_scratch_dir() {
  std::string templ = scratch_parent() + "/tristereo-fuzz-XXXXXX";
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) fail("mkdtemp('" + templ + "'): " + std::strerror(errno));
  return buf.data();
}

// Removes the scratch folder at exit (only in the process that made it).
struct ScratchDir {
  std::string path = make_scratch_dir();
  pid_t owner = getpid();
  ~ScratchDir() {
    if (getpid() != owner) return;
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

}  // namespace

const std::string& scratch_dir() {
  static const ScratchDir dir;
  return dir.path;
}

std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = scratch_dir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) fail("cannot create '" + path + "': " + std::strerror(errno));
  const bool ok = (size == 0 || std::fwrite(data, 1, size, f) == size);
  if (std::fclose(f) != 0 || !ok) fail("cannot write '" + path + "'");
  return path;
}

void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz check failed: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace tristereo::fuzz
