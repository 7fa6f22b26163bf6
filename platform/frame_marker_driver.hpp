// Which GPIO line goes high when, independent of how lines are driven.
//
// Slot 0 is the frame line: high from frame_begin() to frame_end(). Slot
// 1 + s, when the marker has that many lines, is high while stage s runs, so
// a 2-channel scope shows the frame and one stage, a logic analyser all of
// them. With a null marker every call is a no-op (a single branch), so the
// pipeline calls the driver unconditionally.
//
// Call from the thread that runs the frame loop; the driver has no locking.
#pragma once

#include "platform/gpio.hpp"

namespace tristereo {

class FrameMarkerDriver {
 public:
  static constexpr int kMaxStageLines = 32;

  // `marker` may be null (markers disabled); it is not owned and must outlive
  // the driver.
  explicit FrameMarkerDriver(FrameMarker* marker = nullptr) noexcept;

  bool enabled() const noexcept { return marker_ != nullptr; }
  // Stages that have their own line: min(line_count() - 1, kMaxStageLines), or 0.
  int stage_lines() const noexcept { return stage_lines_; }

  void frame_begin() noexcept;
  // Also drops any stage line left high (a stage that threw), so every frame
  // ends with all lines low.
  void frame_end() noexcept;
  // Stages without a line (s < 0 or s >= stage_lines()) are ignored.
  void stage_begin(int stage) noexcept;
  void stage_end(int stage) noexcept;

 private:
  FrameMarker* marker_;
  int stage_lines_;
  unsigned stage_high_mask_ = 0;  // bit s: stage s line is high
};

}  // namespace tristereo
