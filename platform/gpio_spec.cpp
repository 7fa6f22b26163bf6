// The libgpiod-independent part of gpio.hpp (compiled in every build).
#include <cctype>

#include "platform/text_util.hpp"
#include "platform/gpio.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

FrameMarker::~FrameMarker() = default;

namespace {

[[noreturn]] void throw_bad_spec(const std::string& text, const std::string& why) {
  throw Error(ErrorCode::kInvalidArgument,
              "invalid GPIO line '" + text + "': " + why +
                  " (expected CHIP:LINE, e.g. \"gpiochip0:17\" or \"0:17\")");
}

bool all_digits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

}  // namespace

GpioLineSpec parse_gpio_spec(const std::string& text) {
  const std::string body = trim_spaces(text);
  const size_t colon = body.rfind(':');
  if (colon == std::string::npos) throw_bad_spec(text, "missing ':' between chip and line");
  const std::string chip = trim_spaces(body.substr(0, colon));
  const std::string line = trim_spaces(body.substr(colon + 1));
  if (chip.empty()) throw_bad_spec(text, "missing chip");
  if (line.empty()) throw_bad_spec(text, "missing line number");
  if (!all_digits(line)) throw_bad_spec(text, "line '" + line + "' is not a non-negative number");
  if (line.size() > 6 || std::stoul(line) > kMaxGpioLine) {
    throw_bad_spec(text, "line " + line + " exceeds " + std::to_string(kMaxGpioLine));
  }
  GpioLineSpec spec;
  spec.line = static_cast<unsigned>(std::stoul(line));
  if (all_digits(chip)) {
    if (chip.size() > 6) throw_bad_spec(text, "chip number '" + chip + "' is too large");
    spec.chip = "gpiochip" + std::to_string(std::stoul(chip));
  } else {
    spec.chip = chip;
  }
  return spec;
}

std::vector<GpioLineSpec> parse_gpio_specs(const std::string& text) {
  std::vector<GpioLineSpec> specs;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    specs.push_back(parse_gpio_spec(text.substr(start, comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return specs;
}

}  // namespace tristereo
