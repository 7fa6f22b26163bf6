// GPIO frame markers: drive output lines high/low at frame and stage
// boundaries so an oscilloscope or logic analyser measures the true latency
// on the target, independent of the clocks inside the process.
//
// The hardware side goes through libgpiod v1 (the character device
// /dev/gpiochipN) when it was found at build time; otherwise open_gpio_marker
// throws and gpio_supported() is false. The logic of which line goes high when
// lives in FrameMarkerDriver (frame_marker_driver.hpp) and works with any
// FrameMarker, including a test double.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace tristereo {

// A set of output lines addressed by slot 0 .. line_count() - 1.
class FrameMarker {
 public:
  virtual ~FrameMarker();
  // Drives line `line_slot` high or low. Must be cheap and must not throw: it
  // is called inside the frame loop. Slots outside 0 .. line_count() - 1 are
  // ignored.
  virtual void set(int line_slot, bool high) noexcept = 0;
  virtual int line_count() const = 0;
};

// One GPIO line: a chip (name "gpiochip0", label, path "/dev/gpiochip0" or
// number, anything gpiod_chip_open_lookup accepts) and the line offset on it.
struct GpioLineSpec {
  std::string chip;
  unsigned line = 0;
};

// Largest line offset parse_gpio_spec accepts.
constexpr unsigned kMaxGpioLine = 65535;

// Parses "gpiochip0:17", "0:17" (a bare number n means "gpiochipN") or
// "/dev/gpiochip0:17". Throws Error(kInvalidArgument) naming the text when the
// colon, the chip or the line number is missing or malformed.
GpioLineSpec parse_gpio_spec(const std::string& text);

// A comma-separated list of specs, e.g. "gpiochip0:17,gpiochip0:27" for the
// frame line and the first stage line. Throws like parse_gpio_spec.
std::vector<GpioLineSpec> parse_gpio_specs(const std::string& text);

// True when this build can open GPIO lines (libgpiod v1 found at build time).
bool gpio_supported();

// Requests every line in `lines` as an output, initially low, labelled
// `consumer` (shown by gpioinfo); slot i of the result is lines[i]. Lines are
// driven low and released when the marker is destroyed. Throws
// Error(kInvalidArgument) for an empty or duplicated list and Error(kPlatform)
// when a chip is missing or inaccessible, a line does not exist or is busy, or
// this build has no GPIO support; nothing stays requested after an Error.
std::unique_ptr<FrameMarker> open_gpio_marker(const std::vector<GpioLineSpec>& lines,
                                              const std::string& consumer);

}  // namespace tristereo
