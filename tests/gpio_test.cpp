// GPIO frame markers: spec parsing, the driver's exact line sequence (with a
// recording test double), and the hardware error path on a machine without
// the chip asked for.
#include <gtest/gtest.h>
#include <unistd.h>

#include <string>
#include <utility>
#include <vector>

#include "platform/frame_marker_driver.hpp"
#include "platform/gpio.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

TEST(GpioSpec, Parses) {
  GpioLineSpec s = parse_gpio_spec("gpiochip0:17");
  EXPECT_EQ(s.chip, "gpiochip0");
  EXPECT_EQ(s.line, 17u);
  s = parse_gpio_spec("2:5");
  EXPECT_EQ(s.chip, "gpiochip2");
  EXPECT_EQ(s.line, 5u);
  s = parse_gpio_spec("/dev/gpiochip1:0");
  EXPECT_EQ(s.chip, "/dev/gpiochip1");
  EXPECT_EQ(s.line, 0u);
  s = parse_gpio_spec(" pinctrl-bcm2711 : 27 ");
  EXPECT_EQ(s.chip, "pinctrl-bcm2711");
  EXPECT_EQ(s.line, 27u);
  const std::vector<GpioLineSpec> list = parse_gpio_specs("gpiochip0:17,0:27");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[1].chip, "gpiochip0");
  EXPECT_EQ(list[1].line, 27u);
}

TEST(GpioSpec, RejectsGarbage) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "missing ':'"},           {"gpiochip0", "missing ':'"},
      {":17", "missing chip"},       {"gpiochip0:", "missing line"},
      {"gpiochip0:-1", "'-1'"},      {"gpiochip0:x", "'x'"},
      {"gpiochip0:99999999", "exceeds"}, {"gpiochip0:1.5", "'1.5'"}};
  for (const auto& c : cases) {
    try {
      parse_gpio_spec(c.first);
      FAIL() << "accepted '" << c.first << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      const std::string message = e.what();
      EXPECT_NE(message.find(c.second), std::string::npos) << message;
      EXPECT_NE(message.find(std::string("'") + c.first + "'"), std::string::npos) << message;
    }
  }
  EXPECT_THROW(parse_gpio_specs("0:17,"), Error);
}

TEST(GpioOpen, MissingChipIsAClearError) {
  const std::string chip = "gpiochip977";
  ASSERT_NE(access(("/dev/" + chip).c_str(), F_OK), 0) << "this machine has /dev/" << chip;
  try {
    open_gpio_marker({{chip, 3}}, "tristereo-test");
    FAIL() << "opened a chip that does not exist";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kPlatform);
    const std::string message = e.what();
    if (gpio_supported()) {
      EXPECT_EQ(message.rfind("GPIO chip '" + chip + "' not found: ", 0), 0u) << message;
    } else {
      EXPECT_NE(message.find("no GPIO support"), std::string::npos) << message;
    }
  }
}

TEST(GpioOpen, BadLineListsAreRejected) {
  if (!gpio_supported()) {
    EXPECT_THROW(open_gpio_marker({}, "t"), Error);
    return;
  }
  try {
    open_gpio_marker({}, "t");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  }
  try {
    open_gpio_marker({{"gpiochip977", 4}, {"gpiochip977", 4}}, "t");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("gpiochip977:4 is listed twice"), std::string::npos)
        << e.what();
  }
}

// The "line beyond the chip" error needs a real /dev/gpiochip*; it is checked on
// a board with `tristereo profile --frames 1 --gpio gpiochip0:9999`
// (docs/profiling.md), not in this hardware-free suite.

// Records every set() call as (slot, level).
class RecordingMarker final : public FrameMarker {
 public:
  explicit RecordingMarker(int lines) : lines_(lines) {}
  void set(int line_slot, bool high) noexcept override { events.emplace_back(line_slot, high); }
  int line_count() const override { return lines_; }
  std::vector<std::pair<int, bool>> events;

 private:
  int lines_;
};

using Events = std::vector<std::pair<int, bool>>;

TEST(FrameMarkerDriver, FrameAndStageLines) {
  RecordingMarker marker(3);  // frame + stages 0 and 1
  FrameMarkerDriver driver(&marker);
  EXPECT_TRUE(driver.enabled());
  EXPECT_EQ(driver.stage_lines(), 2);
  driver.frame_begin();
  for (int stage = 0; stage < 4; ++stage) {  // stages 2, 3 have no line
    driver.stage_begin(stage);
    driver.stage_end(stage);
  }
  driver.frame_end();
  const Events expected = {{0, true}, {1, true}, {1, false}, {2, true}, {2, false}, {0, false}};
  EXPECT_EQ(marker.events, expected);
}

TEST(FrameMarkerDriver, FrameEndDropsStageLinesLeftHigh) {
  RecordingMarker marker(4);
  FrameMarkerDriver driver(&marker);
  driver.frame_begin();
  driver.stage_begin(0);
  driver.stage_begin(2);  // e.g. a stage that threw before stage_end
  driver.frame_end();
  driver.frame_begin();
  driver.frame_end();
  const Events expected = {{0, true}, {1, true}, {3, true}, {1, false},
                           {3, false}, {0, false}, {0, true}, {0, false}};
  EXPECT_EQ(marker.events, expected);
}

TEST(FrameMarkerDriver, SingleLineMarksFramesOnly) {
  RecordingMarker marker(1);
  FrameMarkerDriver driver(&marker);
  EXPECT_EQ(driver.stage_lines(), 0);
  for (int frame = 0; frame < 2; ++frame) {
    driver.frame_begin();
    driver.stage_begin(0);
    driver.stage_end(0);
    driver.stage_begin(-1);
    driver.frame_end();
  }
  const Events expected = {{0, true}, {0, false}, {0, true}, {0, false}};
  EXPECT_EQ(marker.events, expected);
}

TEST(FrameMarkerDriver, NullMarkerIsDisabled) {
  FrameMarkerDriver driver(nullptr);
  EXPECT_FALSE(driver.enabled());
  EXPECT_EQ(driver.stage_lines(), 0);
  driver.frame_begin();
  driver.stage_begin(0);
  driver.stage_end(0);
  driver.frame_end();
}

}  // namespace
}  // namespace tristereo
