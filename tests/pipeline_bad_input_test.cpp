// DESIGN.md "Bad input": every public entry point answers with a clear Error and
// leaves what the caller owns (and the previous frame's output) untouched.
#include <gtest/gtest.h>

#include "support/scenes.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/status.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {
namespace {

template <class F>
void expect_error(F&& f, ErrorCode code, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "expected an Error containing '" << needle << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

PipelineConfig small_config() {
  PipelineConfig c;
  c.max_width = 64;
  c.max_height = 48;
  c.params.num_disp = 16;
  c.pin_threads = false;
  return c;
}

TEST(BadInput, ConfigureRejectsBadParameters) {
  Pipeline p;
  auto with = [&](auto mutate) {
    PipelineConfig c = small_config();
    mutate(c);
    return [&p, c] { p.configure(c); };
  };
  expect_error(with([](PipelineConfig& c) { c.params.num_disp = 0; }), ErrorCode::kInvalidArgument, "num_disp");
  expect_error(with([](PipelineConfig& c) { c.params.num_disp = 257; }), ErrorCode::kInvalidArgument, "num_disp");
  expect_error(with([](PipelineConfig& c) { c.params.cost.window_w = 4; }), ErrorCode::kInvalidArgument, "odd");
  expect_error(with([](PipelineConfig& c) { c.params.cost.window_h = 33; }), ErrorCode::kInvalidArgument, "window_h");
  expect_error(with([](PipelineConfig& c) { c.params.tritree.psnr_deci_db = 50; }), ErrorCode::kInvalidArgument, "psnr");
  expect_error(with([](PipelineConfig& c) { c.params.tritree.max_area_px2 = 0; }), ErrorCode::kInvalidArgument, "max_area");
  expect_error(with([](PipelineConfig& c) { c.params.dp.lambda_q4 = 40000; }), ErrorCode::kInvalidArgument, "lambda");
  expect_error(with([](PipelineConfig& c) { c.params.cost.truncation = 0; }), ErrorCode::kInvalidArgument, "truncation");
  expect_error(with([](PipelineConfig& c) { c.max_width = 1; }), ErrorCode::kInvalidArgument, "maximum size");
  expect_error(with([](PipelineConfig& c) { c.max_height = 5000; }), ErrorCode::kInvalidArgument, "maximum size");
  expect_error(with([](PipelineConfig& c) { c.threads = -1; }), ErrorCode::kInvalidArgument, "threads");
  EXPECT_FALSE(p.configured());
}

TEST(BadInput, ProcessBeforeConfigure) {
  Pipeline p;
  ImageU8 img(8, 8, 1);
  expect_error([&] { p.process(img.view(), img.view()); }, ErrorCode::kNotConfigured, "configure");
}

TEST(BadInput, ProcessRejectsBadImagesAndKeepsThePreviousOutput) {
  test::Rng rng(3);
  const ImageU8 l = test::random_image(rng, 64, 48);
  const ImageU8 r = test::shifted_view(rng, l, 3, 2);
  Pipeline p;
  p.configure(small_config());
  const StereoOutput& out = p.process(l.view(), r.view());
  const std::string before = digest_hex(out);
  const ImageU8 l_copy = l, r_copy = r;

  ImageU8 small(32, 48, 1), big(65, 48, 1), tiny(1, 48, 1), two_ch(64, 48, 2);
  ImageView<const std::uint8_t> null_view = l.view();
  null_view.data = nullptr;
  ImageView<const std::uint8_t> bad_stride = l.view();
  bad_stride.stride_bytes = 10;
  ImageU8 rgb(64, 48, 3);

  expect_error([&] { p.process(l.view(), small.view()); }, ErrorCode::kSizeMismatch, "32x48");
  expect_error([&] { p.process(big.view(), big.view()); }, ErrorCode::kInvalidArgument, "configured maximum");
  expect_error([&] { p.process(tiny.view(), tiny.view()); }, ErrorCode::kInvalidArgument, "at least 2x2");
  expect_error([&] { p.process(two_ch.view(), two_ch.view()); }, ErrorCode::kUnsupportedFormat, "channels");
  expect_error([&] { p.process(null_view, r.view()); }, ErrorCode::kInvalidArgument, "null");
  expect_error([&] { p.process(l.view(), bad_stride); }, ErrorCode::kInvalidArgument, "stride");
  expect_error([&] { p.process(l.view(), rgb.view()); }, ErrorCode::kSizeMismatch, "channel");

  // Inputs untouched, previous output still readable and unchanged.
  EXPECT_EQ(l.pixels, l_copy.pixels);
  EXPECT_EQ(r.pixels, r_copy.pixels);
  EXPECT_EQ(digest_hex(out), before);
}

TEST(BadInput, ReferenceRejectsBadInputToo) {
  ImageU8 a(10, 10, 1), b(11, 10, 1);
  StereoParams p;
  p.num_disp = 4;
  expect_error([&] { run_reference(a, b, p); }, ErrorCode::kSizeMismatch, "11x10");
  p.num_disp = 0;
  expect_error([&] { run_reference(a, a, p); }, ErrorCode::kInvalidArgument, "num_disp");
}

TEST(BadInput, UnknownKernelSetIsAClearError) {
  PipelineConfig c = small_config();
  Pipeline p;
#if defined(__x86_64__) || defined(__i386__)
  c.kernels = KernelChoice::kNeon;
#else
  c.kernels = KernelChoice::kAvx2;
#endif
  expect_error([&] { p.configure(c); }, ErrorCode::kInvalidArgument, "not compiled");
  EXPECT_THROW(parse_kernel_choice("avx9"), Error);
}

}  // namespace
}  // namespace tristereo
