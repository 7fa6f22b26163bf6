// GPIO backend for builds without libgpiod v1: every open fails clearly.
#include "platform/gpio.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

bool gpio_supported() { return false; }

std::unique_ptr<FrameMarker> open_gpio_marker(const std::vector<GpioLineSpec>& lines,
                                              const std::string& consumer) {
  (void)lines;
  (void)consumer;
  throw Error(ErrorCode::kPlatform,
              "this build has no GPIO support (libgpiod v1 not found at build time; install "
              "libgpiod-dev and reconfigure with -DTRISTEREO_WITH_GPIOD=ON)");
}

}  // namespace tristereo
