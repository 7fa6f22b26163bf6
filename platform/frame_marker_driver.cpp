#include "platform/frame_marker_driver.hpp"

#include <algorithm>

namespace tristereo {

namespace {
int usable_stage_lines(const FrameMarker* marker) {
  if (marker == nullptr) return 0;
  return std::clamp(marker->line_count() - 1, 0, FrameMarkerDriver::kMaxStageLines);
}
}  // namespace

FrameMarkerDriver::FrameMarkerDriver(FrameMarker* marker) noexcept
    : marker_(marker), stage_lines_(usable_stage_lines(marker)) {}

void FrameMarkerDriver::frame_begin() noexcept {
  if (marker_ == nullptr) return;
  marker_->set(0, true);
}

void FrameMarkerDriver::frame_end() noexcept {
  if (marker_ == nullptr) return;
  for (int s = 0; stage_high_mask_ != 0; ++s) {
    if (stage_high_mask_ & (1u << s)) {
      marker_->set(1 + s, false);
      stage_high_mask_ &= ~(1u << s);
    }
  }
  marker_->set(0, false);
}

void FrameMarkerDriver::stage_begin(int stage) noexcept {
  if (marker_ == nullptr || stage < 0 || stage >= stage_lines_) return;
  marker_->set(1 + stage, true);
  stage_high_mask_ |= 1u << stage;
}

void FrameMarkerDriver::stage_end(int stage) noexcept {
  if (marker_ == nullptr || stage < 0 || stage >= stage_lines_) return;
  marker_->set(1 + stage, false);
  stage_high_mask_ &= ~(1u << stage);
}

}  // namespace tristereo
