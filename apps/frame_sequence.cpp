#include "apps/frame_sequence.hpp"

#include <dirent.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "apps/cli_args.hpp"
#include "apps/output_paths.hpp"
#include "platform/clock.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {
bool file_exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }
}  // namespace

std::string expand_pattern(const std::string& option, const std::string& pattern, int index) {
  std::string out;
  int fields = 0;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%';
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    const bool zero = j < pattern.size() && pattern[j] == '0';
    if (zero) ++j;
    int width = 0;
    while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && width < 100)
      width = width * 10 + (pattern[j++] - '0');
    if (j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i' && pattern[j] != 'u') ||
        width > 32)
      throw UsageError(option + " '" + pattern +
                       "': only one %d-style field (e.g. %04d) is allowed");
    std::string digits = std::to_string(index);
    if (static_cast<int>(digits.size()) < width)
      digits.insert(0, static_cast<std::size_t>(width) - digits.size(), zero ? '0' : ' ');
    out += digits;
    ++fields;
    i = j;
  }
  if (fields != 1)
    throw UsageError(option + " '" + pattern + "' must contain exactly one %d-style field, found " +
                     std::to_string(fields));
  return out;
}

std::vector<SequenceFrame> folder_sequence(const std::string& dir, const std::string& left_pattern,
                                           const std::string& right_pattern, int max_frames) {
  DIR* d = opendir(dir.c_str());
  if (!d)
    throw Error(ErrorCode::kIoError, "cannot read folder '" + dir + "': " + std::strerror(errno));
  closedir(d);
  const std::string base = dir.empty() || dir.back() == '/' ? dir : dir + "/";
  auto left_path = [&](int i) { return base + expand_pattern("--left-pattern", left_pattern, i); };
  auto right_path = [&](int i) { return base + expand_pattern("--right-pattern", right_pattern, i); };
  // Sequences are numbered from 0 or from 1.
  const int first = file_exists(left_path(0)) ? 0 : 1;
  if (!file_exists(left_path(first)))
    throw Error(ErrorCode::kIoError, "folder '" + dir + "' has no first frame: neither '" +
                                         left_path(0) + "' nor '" + left_path(1) + "' exists");
  std::vector<SequenceFrame> frames;
  for (int i = first; static_cast<int>(frames.size()) < max_frames && file_exists(left_path(i)); ++i)
    frames.push_back({i, left_path(i), right_path(i)});
  return frames;
}

std::vector<SequenceFrame> list_sequence(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(ErrorCode::kIoError, "cannot open list '" + path + "': " + std::strerror(errno));
  const std::string dir = folder_of(path);
  const auto beside = [&](const std::string& p) { return p.front() == '/' || dir == "." ? p : dir + "/" + p; };
  std::vector<SequenceFrame> frames;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // a list written on Windows
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string s; words >> s;) w.push_back(s);
    if (w.empty() || w[0][0] == '#') continue;
    if (w.size() != 2)
      throw Error(ErrorCode::kInvalidArgument,
                  path + ":" + std::to_string(line_no) + ": expected two paths 'LEFT RIGHT', got " +
                      std::to_string(w.size()) + " words (paths with spaces are not supported)");
    frames.push_back({static_cast<int>(frames.size()), beside(w[0]), beside(w[1])});
  }
  if (in.bad()) throw Error(ErrorCode::kIoError, "cannot read list '" + path + "': " + std::strerror(errno));
  if (frames.empty())
    throw Error(ErrorCode::kInvalidArgument, "list '" + path + "' holds no pair (one 'LEFT RIGHT' per line)");
  return frames;
}

ProgressLine::ProgressLine(bool quiet) : enabled_(!quiet && isatty(STDERR_FILENO)) {}

void ProgressLine::update(const char* phase, int done, int total, std::int64_t last_ns) {
  update(phase, done, total, -1, last_ns);
}

void ProgressLine::update(const char* phase, int done, int total, int failed, std::int64_t last_ns) {
  if (!enabled_) return;
  const std::int64_t now = monotonic_ns();
  if (done < total && now - last_print_ns_ < 100000000) return;
  last_print_ns_ = now;
  if (failed >= 0)
    std::fprintf(stderr, "\r%s %d/%d (%d failed)  last frame %.2f ms   ", phase, done, total, failed,
                 static_cast<double>(last_ns) / 1e6);
  else
    std::fprintf(stderr, "\r%s %d/%d  last frame %.2f ms   ", phase, done, total,
                 static_cast<double>(last_ns) / 1e6);
  std::fflush(stderr);
}

void ProgressLine::clear() {
  if (enabled_) std::fprintf(stderr, "\r%70s\r", "");
}

}  // namespace tristereo::cli
