// Resident memory of the process, sampled during a profiling run (the soak:
// does memory stay flat over thousands of frames?).
//
// current_rss_bytes() reads /proc/self/statm into a stack buffer, so sampling
// inside the frame loop allocates nothing; RssTrace stores the samples in
// storage allocated once, before the loop, like FrameLog.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tristereo {

// Resident set size of this process now, in bytes (statm's resident pages x
// the page size); 0 where /proc is unavailable. Unlike peak_rss_bytes() (the
// high-water mark) it goes down when memory is returned.
std::int64_t current_rss_bytes() noexcept;

struct RssSample {
  std::int64_t frame = 0;      // measured frames completed when sampled
  std::int64_t rss_bytes = 0;
};

// Summary of a trace: first, last and largest sample (bytes) and how many.
struct RssSummary {
  std::size_t samples = 0;
  std::int64_t start_bytes = 0;
  std::int64_t end_bytes = 0;
  std::int64_t max_bytes = 0;
};

class RssTrace {
 public:
  // One sample every `every_frames` measured frames (>= 1) of a run of
  // `frames` measured frames, plus one before the first and one after the
  // last: capacity frames / every_frames + 2. Throws Error(kInvalidArgument)
  // if frames or every_frames is < 1.
  RssTrace(std::int64_t frames, std::int64_t every_frames);

  // The interval that keeps a run of `frames` to at most ~max_samples samples.
  static std::int64_t interval_for(std::int64_t frames, std::int64_t max_samples);

  std::int64_t every_frames() const noexcept { return every_; }
  // True when the loop should sample after `done` measured frames: 0, every
  // multiple of every_frames(), and the last frame.
  bool due(std::int64_t done) const noexcept {
    return done == 0 || done % every_ == 0 || done == frames_;
  }
  // Records a sample; false (nothing recorded) when full or when `frame` was
  // already sampled. Never allocates.
  bool push(std::int64_t frame, std::int64_t rss_bytes) noexcept;

  std::size_t size() const noexcept { return size_; }
  const RssSample& operator[](std::size_t i) const { return samples_[i]; }

  // Throws Error(kInvalidArgument) on an empty trace.
  RssSummary summary() const;

 private:
  std::int64_t frames_;
  std::int64_t every_;
  std::vector<RssSample> samples_;
  std::size_t size_ = 0;
};

}  // namespace tristereo
