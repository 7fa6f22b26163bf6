#include "tristereo/eval.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"
#include "support/data.hpp"

namespace fs = std::filesystem;

namespace tristereo {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

template <typename T>
ImageView<const T> cview(const Image<T>& img) {
  return img.view();
}

template <typename F>
ErrorCode code_of(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.code();
  }
  ADD_FAILURE() << "no tristereo::Error thrown";
  return ErrorCode::kPlatform;
}

// 4 x 2 ground truth with two unknown pixels (0 and NaN) and a disparity map
// whose errors are 0, 0.6, 2, (none), 0.5, 0.25 on the six known pixels.
struct Fixture {
  Image<float> gt{4, 2, 1}, disp{4, 2, 1};
  Fixture() {
    gt.pixels = {1, 2, 3, 0, 5, kNaN, 7, 8};
    disp.pixels = {1, 2.6f, 5, 9, kInf, 1, 7.5f, 8.25f};
  }
};

TEST(Eval, HandBuiltKnownAnswer) {
  Fixture f;
  const BadPixelStats s = evaluate_disparity(cview(f.disp), cview(f.gt), {});
  EXPECT_EQ(s.evaluated, 6);
  EXPECT_EQ(s.invalid, 1);
  EXPECT_DOUBLE_EQ(s.bad_0_5, 50.0);        // 0.6, 2, invalid (0.5 is not > 0.5)
  EXPECT_DOUBLE_EQ(s.bad_1, 100.0 / 3.0);   // 2, invalid
  EXPECT_DOUBLE_EQ(s.bad_2, 100.0 / 6.0);   // invalid (2 is not > 2)
  const double e06 = static_cast<double>(2.6f) - 2.0;
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt((e06 * e06 + 4.0 + 0.25 + 0.0625) / 5.0));
}

TEST(Eval, MaskSelectsPixelsAndNaNIsInvalid) {
  Fixture f;
  ImageU8 mask(4, 2, 1, 0);
  mask.pixels = {255, 255, 255, 255, 128, 0, 0, 0};  // only 255 counts
  const BadPixelStats s = evaluate_disparity(cview(f.disp), cview(f.gt), cview(mask));
  EXPECT_EQ(s.evaluated, 3);
  EXPECT_EQ(s.invalid, 0);
  EXPECT_DOUBLE_EQ(s.bad_1, 100.0 / 3.0);
  f.disp.pixels[0] = kNaN;
  const BadPixelStats t = evaluate_disparity(cview(f.disp), cview(f.gt), cview(mask));
  EXPECT_EQ(t.invalid, 1);
  EXPECT_DOUBLE_EQ(t.bad_0_5, 100.0);
  // Nothing to evaluate: all zero, no NaN.
  ImageU8 none(4, 2, 1, 0);
  const BadPixelStats z = evaluate_disparity(cview(f.disp), cview(f.gt), cview(none));
  EXPECT_EQ(z.evaluated, 0);
  EXPECT_EQ(z.bad_1, 0.0);
  EXPECT_EQ(z.rms, 0.0);
}

TEST(Eval, AtPointsUsesQ4AndInvalid) {
  Fixture f;
  const std::vector<Vertex> pts = {{0, 0}, {1, 0}, {3, 0}, {0, 1}, {3, 1}};
  // 1.0 exact; 2 + 11/16 (err 0.6875); unknown gt; invalid; 8 + 1/16.
  const std::vector<std::int16_t> d = {16, 43, 100, kInvalidDispQ4, 129};
  const BadPixelStats s = evaluate_at_points(cview(f.gt), pts, d, {});
  EXPECT_EQ(s.evaluated, 4);
  EXPECT_EQ(s.invalid, 1);
  EXPECT_DOUBLE_EQ(s.bad_0_5, 50.0);
  EXPECT_DOUBLE_EQ(s.bad_1, 25.0);
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt((0.6875 * 0.6875 + 0.0625 * 0.0625) / 3.0));
  EXPECT_EQ(code_of([&] { evaluate_at_points(cview(f.gt), {{4, 0}}, {16}, {}); }),
            ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { evaluate_at_points(cview(f.gt), pts, {16}, {}); }),
            ErrorCode::kSizeMismatch);
}

TEST(Eval, BadInput) {
  Fixture f;
  const Image<float> small(3, 2, 1);
  EXPECT_EQ(code_of([&] { evaluate_disparity(cview(small), cview(f.gt), {}); }),
            ErrorCode::kSizeMismatch);
  const ImageU8 mask(4, 3, 1);
  EXPECT_EQ(code_of([&] { evaluate_disparity(cview(f.disp), cview(f.gt), cview(mask)); }),
            ErrorCode::kSizeMismatch);
  const Image<float> rgb(4, 2, 3);
  EXPECT_EQ(code_of([&] { evaluate_disparity(cview(rgb), cview(f.gt), {}); }),
            ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([&] { evaluate_disparity({}, cview(f.gt), {}); }), ErrorCode::kInvalidArgument);
}

std::string middlebury() { return test::data_set_dir("middlebury"); }

TEST(Eval, DatasetsTsvAndMiddleburyGroundTruth) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  const std::vector<MiddleburyScene> s = read_datasets_tsv(middlebury() + "/datasets.tsv");
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].name, "tsukuba");
  EXPECT_EQ(s[0].width, 384);
  EXPECT_EQ(s[0].height, 288);
  EXPECT_EQ(s[0].ndisp, 16);
  EXPECT_EQ(s[0].gt_scale, 16);
  EXPECT_EQ(s[1].name, "venus");
  EXPECT_EQ(s[1].gt_scale, 8);
  EXPECT_EQ(s[3].name, "cones");
  EXPECT_EQ(s[3].ndisp, 60);
  EXPECT_EQ(s[3].gt_scale, 4);

  // The README's largest disparities: 14, 19.75, 52.75, 55.
  const float expect_max[4] = {14.f, 19.75f, 52.75f, 55.f};
  for (int i = 0; i < 4; ++i) {
    const std::string dir = middlebury() + "/" + s[i].name + "/";
    const Image<float> gt = load_middlebury_gt(dir + "disp_left.png", s[i].gt_scale);
    const ImageU8 raw = read_image_u8(dir + "disp_left.png");
    float mx = 0;
    for (std::size_t k = 0; k < gt.pixels.size(); ++k) {
      ASSERT_EQ(gt.pixels[k], raw.pixels[k] / static_cast<float>(s[i].gt_scale));
      mx = std::max(mx, gt.pixels[k]);
    }
    EXPECT_EQ(mx, expect_max[i]) << s[i].name;
    // GT against itself is perfect; GT + 1 px is bad at 0.5 but not at 1 or 2.
    const ImageU8 nonocc = read_image_u8(dir + "nonocc.png");
    const BadPixelStats self = evaluate_disparity(cview(gt), cview(gt), cview(nonocc));
    EXPECT_GT(self.evaluated, 50000);
    EXPECT_EQ(self.bad_0_5, 0.0);
    EXPECT_EQ(self.rms, 0.0);
    Image<float> plus1 = gt;
    for (float& v : plus1.pixels) v += 1.f;
    const BadPixelStats p1 = evaluate_disparity(cview(plus1), cview(gt), cview(nonocc));
    EXPECT_EQ(p1.evaluated, self.evaluated);
    EXPECT_EQ(p1.bad_0_5, 100.0);
    EXPECT_EQ(p1.bad_1, 0.0);
    EXPECT_EQ(p1.rms, 1.0);
  }
  EXPECT_EQ(code_of([&] { load_middlebury_gt(middlebury() + "/venus/left.png", 8); }),
            ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([&] { load_middlebury_gt(middlebury() + "/venus/disp_left.png", 0); }),
            ErrorCode::kInvalidArgument);
}

TEST(Eval, MalformedDatasetsTsv) {
  const fs::path dir = fs::temp_directory_path() / ("tristereo_eval_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  EXPECT_EQ(code_of([&] { read_datasets_tsv((dir / "missing.tsv").string()); }), ErrorCode::kIoError);
  EXPECT_EQ(code_of([&] { read_datasets_tsv(write("e.tsv", "")); }), ErrorCode::kCorruptFile);
  EXPECT_EQ(code_of([&] { read_datasets_tsv(write("c.tsv", "name\twidth\theight\tndisp\nx\t1\t2\t3\n")); }),
            ErrorCode::kCorruptFile);  // no gt_scale column
  EXPECT_EQ(code_of([&] {
              read_datasets_tsv(write("n.tsv", "name\twidth\theight\tndisp\tgt_scale\nx\t1a\t2\t3\t4\n"));
            }),
            ErrorCode::kCorruptFile);
  EXPECT_EQ(code_of([&] {
              read_datasets_tsv(write("s.tsv", "name\twidth\theight\tndisp\tgt_scale\nx\t1\t2\n"));
            }),
            ErrorCode::kCorruptFile);
  // Column order is free and CRLF line ends are accepted.
  const auto ok = read_datasets_tsv(
      write("ok.tsv", "gt_scale\tname\tndisp\theight\twidth\r\n4\tfoo\t60\t375\t450\r\n"));
  ASSERT_EQ(ok.size(), 1u);
  EXPECT_EQ(ok[0].name, "foo");
  EXPECT_EQ(ok[0].width, 450);
  EXPECT_EQ(ok[0].height, 375);
  EXPECT_EQ(ok[0].ndisp, 60);
  EXPECT_EQ(ok[0].gt_scale, 4);
  fs::remove_all(dir);
}

// The synthetic planar scene scored against its own ground truth through the
// Q4 conversion: exact, except the unmatched columns excluded by nonocc.
TEST(Eval, SyntheticPlanarGroundTruthThroughQ4) {
  const SyntheticScene s = make_planar_scene(40, 10, 6, 2);
  ImageS16 q4(40, 10, 1, static_cast<std::int16_t>(6 * 16));
  for (int y = 0; y < 10; ++y) q4.at(0, y) = kInvalidDispQ4;  // column 0 has no match anyway
  const Image<float> d = disp_q4_to_float(cview(q4));
  const BadPixelStats in_nonocc = evaluate_disparity(cview(d), cview(s.disp_left), cview(s.nonocc_mask));
  EXPECT_EQ(in_nonocc.evaluated, 34 * 10);
  EXPECT_EQ(in_nonocc.bad_0_5, 0.0);
  const BadPixelStats all = evaluate_disparity(cview(d), cview(s.disp_left), {});
  EXPECT_EQ(all.evaluated, 400);
  EXPECT_EQ(all.invalid, 10);
  EXPECT_DOUBLE_EQ(all.bad_2, 2.5);
}

}  // namespace
}  // namespace tristereo
