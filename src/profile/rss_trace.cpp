#include "src/profile/rss_trace.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <string>

#include "tristereo/status.hpp"

namespace tristereo {

std::int64_t current_rss_bytes() noexcept {
  // "size resident shared text lib data dt" in pages; a few dozen bytes.
  const int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  char buf[128];
  const ssize_t n = read(fd, buf, sizeof buf - 1);
  close(fd);
  if (n <= 0) return 0;
  buf[n] = '\0';
  const char* p = buf;
  while (*p && *p != ' ') ++p;  // skip "size"
  while (*p == ' ') ++p;
  std::int64_t pages = 0;
  for (; *p >= '0' && *p <= '9'; ++p) pages = pages * 10 + (*p - '0');
  const long page = sysconf(_SC_PAGESIZE);
  return page > 0 ? pages * page : 0;
}

RssTrace::RssTrace(std::int64_t frames, std::int64_t every_frames)
    : frames_(frames), every_(every_frames) {
  if (frames < 1 || every_frames < 1)
    throw Error(ErrorCode::kInvalidArgument,
                "RSS trace of " + std::to_string(frames) + " frames every " +
                    std::to_string(every_frames) + " (both must be >= 1)");
  samples_.resize(static_cast<std::size_t>(frames / every_frames + 2));
}

std::int64_t RssTrace::interval_for(std::int64_t frames, std::int64_t max_samples) {
  if (max_samples < 1) max_samples = 1;
  return std::max<std::int64_t>(1, (frames + max_samples - 1) / max_samples);
}

bool RssTrace::push(std::int64_t frame, std::int64_t rss_bytes) noexcept {
  if (size_ == samples_.size()) return false;
  if (size_ > 0 && samples_[size_ - 1].frame == frame) return false;
  samples_[size_++] = {frame, rss_bytes};
  return true;
}

RssSummary RssTrace::summary() const {
  if (size_ == 0) throw Error(ErrorCode::kInvalidArgument, "summary of an empty RSS trace");
  RssSummary s;
  s.samples = size_;
  s.start_bytes = samples_[0].rss_bytes;
  s.end_bytes = samples_[size_ - 1].rss_bytes;
  s.max_bytes = s.start_bytes;
  for (std::size_t i = 0; i < size_; ++i) s.max_bytes = std::max(s.max_bytes, samples_[i].rss_bytes);
  return s;
}

}  // namespace tristereo
