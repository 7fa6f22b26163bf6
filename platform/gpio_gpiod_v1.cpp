// GPIO backend on libgpiod v1 (Debian's libgpiod-dev 1.6). The v2 API is
// entirely different; this is the only file that includes gpiod.h.
#include <gpiod.h>

#include <cerrno>
#include <cstring>

#include "platform/gpio.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

class GpiodFrameMarker final : public FrameMarker {
 public:
  GpiodFrameMarker() = default;
  GpiodFrameMarker(const GpiodFrameMarker&) = delete;
  GpiodFrameMarker& operator=(const GpiodFrameMarker&) = delete;

  ~GpiodFrameMarker() override {
    // Leave the lines low so a trace ends in the idle state; released lines
    // keep whatever level they had.
    for (gpiod_line* line : lines_) {
      gpiod_line_set_value(line, 0);
      gpiod_line_release(line);
    }
    // Lines belong to their chip; close chips only after releasing them.
    for (Chip& chip : chips_) gpiod_chip_close(chip.handle);
  }

  void set(int line_slot, bool high) noexcept override {
    if (line_slot < 0 || line_slot >= static_cast<int>(lines_.size())) return;
    // A failed write is not worth aborting a frame over: the scope trace will
    // show the missing edge.
    gpiod_line_set_value(lines_[static_cast<size_t>(line_slot)], high ? 1 : 0);
  }

  int line_count() const override { return static_cast<int>(lines_.size()); }

  void add_line(const GpioLineSpec& spec, const std::string& consumer) {
    gpiod_chip* chip = open_chip(spec.chip);
    const unsigned count = gpiod_chip_num_lines(chip);
    const std::string chip_name = gpiod_chip_name(chip);
    if (spec.line >= count) {
      throw Error(ErrorCode::kPlatform, "GPIO line " + std::to_string(spec.line) +
                                            " does not exist on " + chip_name + " (it has " +
                                            std::to_string(count) + " lines)");
    }
    gpiod_line* line = gpiod_chip_get_line(chip, spec.line);
    if (line == nullptr) {
      throw Error(ErrorCode::kPlatform, "cannot get GPIO line " + std::to_string(spec.line) +
                                            " on " + chip_name + ": " + std::strerror(errno));
    }
    if (gpiod_line_request_output(line, consumer.c_str(), 0) != 0) {
      const int err = errno;
      std::string message = "cannot request GPIO line " + std::to_string(spec.line) + " on " +
                            chip_name + " as output: " + std::strerror(err);
      if (err == EBUSY) {
        const char* owner = gpiod_line_consumer(line);
        message += std::string(" (in use by '") + (owner != nullptr ? owner : "?") +
                   "'; see gpioinfo)";
      }
      throw Error(ErrorCode::kPlatform, message);
    }
    lines_.push_back(line);
  }

 private:
  struct Chip {
    std::string spec;
    gpiod_chip* handle;
  };

  gpiod_chip* open_chip(const std::string& spec) {
    for (const Chip& chip : chips_) {
      if (chip.spec == spec) return chip.handle;
    }
    errno = 0;
    gpiod_chip* handle = gpiod_chip_open_lookup(spec.c_str());
    if (handle == nullptr) {
      const int err = errno != 0 ? errno : ENOENT;
      if (err == ENOENT || err == ENODEV) {
        throw Error(ErrorCode::kPlatform, "GPIO chip '" + spec + "' not found: " +
                                              std::strerror(err) + " (list chips with gpiodetect)");
      }
      std::string message = "cannot open GPIO chip '" + spec + "': " + std::strerror(err);
      if (err == EACCES || err == EPERM) {
        message += " (check the permissions of /dev/gpiochip*, e.g. membership of group gpio)";
      }
      throw Error(ErrorCode::kPlatform, message);
    }
    chips_.push_back({spec, handle});
    return handle;
  }

  std::vector<Chip> chips_;
  std::vector<gpiod_line*> lines_;
};

}  // namespace

bool gpio_supported() { return true; }

std::unique_ptr<FrameMarker> open_gpio_marker(const std::vector<GpioLineSpec>& lines,
                                              const std::string& consumer) {
  if (lines.empty()) {
    throw Error(ErrorCode::kInvalidArgument, "open_gpio_marker: no GPIO lines given");
  }
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (lines[i].chip == lines[j].chip && lines[i].line == lines[j].line) {
        throw Error(ErrorCode::kInvalidArgument,
                    "open_gpio_marker: GPIO line " + lines[i].chip + ":" +
                        std::to_string(lines[i].line) + " is listed twice (slots " +
                        std::to_string(j) + " and " + std::to_string(i) + ")");
      }
    }
  }
  // On an Error the partially built marker's destructor releases what was
  // already requested.
  auto marker = std::make_unique<GpiodFrameMarker>();
  for (const GpioLineSpec& spec : lines) {
    marker->add_line(spec, consumer.empty() ? std::string("tristereo") : consumer);
  }
  return marker;
}

}  // namespace tristereo
