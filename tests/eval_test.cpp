#include "tristereo/eval.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
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
  // End-point error: the mean |d - gt| of the five pixels with a disparity.
  EXPECT_DOUBLE_EQ(s.epe, (e06 + 2.0 + 0.5 + 0.25) / 5.0);
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
  EXPECT_EQ(z.epe, 0.0);
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
  EXPECT_DOUBLE_EQ(s.epe, (0.6875 + 0.0625) / 3.0);
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
  EXPECT_EQ(ok[0].gt_file, "");  // optional columns absent
  // The new sets' columns: gt_file, gt_format, noc_mask; KITTI's scale 256.
  const auto k = read_datasets_tsv(write(
      "k.tsv", "name\twidth\theight\tndisp\tgt_file\tgt_format\tgt_scale\tnoc_mask\n"
               "000000\t1242\t375\t80\tdisp_occ_0.png\tkitti16\t256\tnone\n"));
  ASSERT_EQ(k.size(), 1u);
  EXPECT_EQ(k[0].gt_scale, 256);
  EXPECT_EQ(k[0].gt_file, "disp_occ_0.png");
  EXPECT_EQ(k[0].gt_format, "kitti16");
  EXPECT_EQ(k[0].noc_mask, "none");
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

// Bad 3 px and D1 on hand-picked errors around both of D1's thresholds
// (3 px and 5 % of gt); every value is exact in float.
TEST(Eval, Bad3AndD1KnownAnswer) {
  Image<float> gt(8, 1, 1), disp(8, 1, 1);
  //            gt     d       error  > 3?  > 5 % gt?  D1
  gt.pixels = {10,    40,     80,    100,   200,   300,   50,   kInf};
  disp.pixels = {13,  44.5f,  84,    104,   211,   300.5f, kInf, 7};
  // 10: e 3 (not > 3).  40: e 4.5 > 3 and > 2 -> D1.  80: e 4 > 3, not > 4 -> bad3 only.
  // 100: e 4 > 3, not > 5 -> bad3 only.  200: e 11 > 10 -> D1.  300: e 0.5.
  // 50: invalid -> bad everywhere, D1.  inf gt: unknown, skipped.
  const BadPixelStats s = evaluate_disparity(cview(disp), cview(gt), {});
  EXPECT_EQ(s.evaluated, 7);
  EXPECT_EQ(s.invalid, 1);
  EXPECT_DOUBLE_EQ(s.bad_3, 100.0 * 5 / 7);  // 40, 80, 100, 200, invalid
  EXPECT_DOUBLE_EQ(s.d1, 100.0 * 3 / 7);     // 40, 200, invalid
  EXPECT_DOUBLE_EQ(s.bad_2, 100.0 * 6 / 7);  // + 10 (e 3)
  EXPECT_DOUBLE_EQ(s.bad_0_5, 100.0 * 6 / 7);  // 300's 0.5 is not > 0.5
  // At sample positions the same rule holds (Q4 input).
  const std::vector<Vertex> pts = {{1, 0}, {2, 0}, {6, 0}};
  const BadPixelStats p = evaluate_at_points(cview(gt), pts, {44 * 16 + 8, 84 * 16, kInvalidDispQ4}, {});
  EXPECT_EQ(p.evaluated, 3);
  EXPECT_DOUBLE_EQ(p.bad_3, 100.0);
  EXPECT_DOUBLE_EQ(p.d1, 200.0 / 3);
}

// Middlebury 2014's mask0nocc.png: 255 non-occluded, 128 occluded, 0 no ground
// truth. --mask counts 255 only; unknown GT (+inf) stays out even under 255.
TEST(Eval, Middlebury2014MaskSemantics) {
  Image<float> gt(5, 1, 1), disp(5, 1, 1);
  gt.pixels = {10, 20, 30, kInf, 50};
  disp.pixels = {10, 25, 30, 40, 55};
  ImageU8 mask(5, 1, 1);
  mask.pixels = {255, 128, 0, 255, 255};
  const BadPixelStats nonocc = evaluate_disparity(cview(disp), cview(gt), cview(mask));
  EXPECT_EQ(nonocc.evaluated, 2);  // pixels 0 and 4
  EXPECT_DOUBLE_EQ(nonocc.bad_2, 50.0);
  const BadPixelStats all = evaluate_disparity(cview(disp), cview(gt), {});
  EXPECT_EQ(all.evaluated, 4);  // every known pixel, whatever the mask says
  EXPECT_DOUBLE_EQ(all.bad_2, 50.0);
  EXPECT_DOUBLE_EQ(all.bad_0_5, 50.0);
}

struct TempDir {
  fs::path dir = fs::temp_directory_path() / ("tristereo_evalfmt_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(dir); }
  ~TempDir() { fs::remove_all(dir); }
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
};

TEST(Eval, PfmGroundTruthWithInfinityIsUnknown) {
  TempDir t;
  Image<float> gt(3, 2, 1);
  gt.pixels = {1.25f, kInf, 3.0f, -kInf, 5.5f, kNaN};
  write_pfm(t / "gt.pfm", cview(gt));
  EXPECT_EQ(detect_disp_file_format(t / "gt.pfm", DispFileFormat::kKitti), DispFileFormat::kPfm);
  const Image<float> r = read_disparity_px(t / "gt.pfm", DispFileFormat::kPfm, 1);
  ASSERT_EQ(r.width, 3);
  ASSERT_EQ(r.height, 2);
  EXPECT_EQ(r.pixels[0], 1.25f);
  EXPECT_EQ(r.pixels[1], kInf);
  EXPECT_EQ(r.pixels[3], kInf);  // -inf and NaN become +inf: one "none" value
  EXPECT_EQ(r.pixels[5], kInf);
  Image<float> disp(3, 2, 1);
  disp.pixels = {1.25f, 2, 6.5f, 4, kInf, 6};
  const BadPixelStats s = evaluate_disparity(cview(disp), cview(r), {});
  EXPECT_EQ(s.evaluated, 3);  // 1.25, 3, 5.5
  EXPECT_EQ(s.invalid, 1);
  EXPECT_DOUBLE_EQ(s.bad_3, 200.0 / 3);  // 3 vs 6.5 (e 3.5) and the invalid one
}

TEST(Eval, Kitti16BitGroundTruthWithZerosIsUnknown) {
  TempDir t;
  Image<std::uint16_t> raw(4, 1, 1);
  raw.pixels = {0, 256, 2561, 65535};  // unknown, 1, 10.00390625, 255.99609375
  write_png_u16(t / "gt.png", cview(raw));
  EXPECT_EQ(detect_disp_file_format(t / "gt.png", DispFileFormat::kKitti), DispFileFormat::kKitti);
  EXPECT_EQ(detect_disp_file_format(t / "gt.png", DispFileFormat::kQ4), DispFileFormat::kQ4);
  const Image<float> k = read_disparity_px(t / "gt.png", DispFileFormat::kKitti, 1);
  EXPECT_EQ(k.pixels[0], kInf);
  EXPECT_EQ(k.pixels[1], 1.0f);
  EXPECT_EQ(k.pixels[2], 10.00390625f);
  EXPECT_EQ(k.pixels[3], 255.99609375f);
  const Image<float> q = read_disparity_px(t / "gt.png", DispFileFormat::kQ4, 1);
  EXPECT_EQ(q.pixels[1], 16.0f);
  EXPECT_EQ(q.pixels[2], 160.0625f);
  Image<float> disp(4, 1, 1);
  disp.pixels = {3, 5, 10, 250};  // e: -, 4 (D1: 4 > 3 and > 0.05), 0.0039, 5.996 (not > 12.8)
  const BadPixelStats s = evaluate_disparity(cview(disp), cview(k), {});
  EXPECT_EQ(s.evaluated, 3);
  EXPECT_DOUBLE_EQ(s.d1, 100.0 / 3);
  EXPECT_DOUBLE_EQ(s.bad_3, 200.0 / 3);
}

TEST(Eval, Png8GroundTruthDividesByScale) {
  TempDir t;
  ImageU8 raw(3, 1, 1);
  raw.pixels = {0, 4, 255};
  write_png_u8(t / "gt8.png", cview(raw));
  EXPECT_EQ(detect_disp_file_format(t / "gt8.png", DispFileFormat::kQ4), DispFileFormat::kPng8);
  const Image<float> g = read_disparity_px(t / "gt8.png", DispFileFormat::kPng8, 4);
  EXPECT_EQ(g.pixels[0], 0.0f);  // 0 stays 0: unknown as ground truth
  EXPECT_EQ(g.pixels[1], 1.0f);
  EXPECT_EQ(g.pixels[2], 63.75f);
}

TEST(Eval, DisparityFilesOfTheWrongKindAreRefused) {
  TempDir t;
  Image<float> f(2, 2, 1, 1.0f);
  write_pfm(t / "a.pfm", cview(f));
  Image<float> rgb(2, 2, 3, 1.0f);
  write_pfm(t / "rgb.pfm", cview(rgb));
  ImageU8 g8(2, 2, 1, 7), c8(2, 2, 3, 7);
  write_png_u8(t / "g8.png", cview(g8));
  write_png_u8(t / "c8.png", cview(c8));
  Image<std::uint16_t> g16(2, 2, 1, 300);
  write_png_u16(t / "g16.png", cview(g16));
  std::ofstream(t / "junk.bin") << "not an image at all";
  std::ofstream(t / "short.png") << "\x89PNG";
  std::ofstream(t / "empty.pfm").close();
  const auto read = [&](const std::string& name, DispFileFormat fmt) {
    return code_of([&] { read_disparity_px(t / name, fmt, 1); });
  };
  EXPECT_EQ(read("a.pfm", DispFileFormat::kKitti), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("a.pfm", DispFileFormat::kPng8), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("rgb.pfm", DispFileFormat::kPfm), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("g8.png", DispFileFormat::kQ4), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("g8.png", DispFileFormat::kPfm), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("c8.png", DispFileFormat::kPng8), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("g16.png", DispFileFormat::kPng8), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("junk.bin", DispFileFormat::kPfm), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("missing.pfm", DispFileFormat::kPfm), ErrorCode::kIoError);
  EXPECT_EQ(code_of([&] { read_disparity_px(t.dir.string(), DispFileFormat::kPfm, 1); }),
            ErrorCode::kIoError);
  EXPECT_EQ(code_of([&] { read_disparity_px(t / "g8.png", DispFileFormat::kPng8, 0); }),
            ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { read_disparity_px(t / "g8.png", DispFileFormat::kPng8, 256); }),
            ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { detect_disp_file_format(t / "junk.bin", DispFileFormat::kQ4); }),
            ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([&] { detect_disp_file_format(t / "short.png", DispFileFormat::kQ4); }),
            ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read("empty.pfm", DispFileFormat::kPfm), ErrorCode::kUnsupportedFormat);
  try {
    detect_disp_file_format(t / "empty.pfm", DispFileFormat::kQ4);
    ADD_FAILURE() << "an empty file was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is empty"), std::string::npos) << e.what();
  }
  try {  // the message says what the file is and what was asked
    read_disparity_px(t / "a.pfm", DispFileFormat::kKitti, 1);
    ADD_FAILURE() << "a PFM was read as a KITTI PNG";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a PFM file, not a kitti disparity file"), std::string::npos)
        << e.what();
  }
  DispFileFormat fmt{};
  EXPECT_TRUE(parse_disp_file_format("kitti", &fmt));
  EXPECT_EQ(fmt, DispFileFormat::kKitti);
  EXPECT_FALSE(parse_disp_file_format("KITTI", &fmt));
  EXPECT_FALSE(parse_disp_file_format("auto", &fmt));
}

// The ratio signal: a ground truth stored 4x (Middlebury v2 teddy) read
// unscaled is 4x the disparity; read right, about 1.
TEST(Eval, ScaleCheckFindsTheFactor) {
  Image<float> disp(10, 10, 1), gt(10, 10, 1);
  for (int i = 0; i < 100; ++i) {
    disp.pixels[i] = 5.0f + static_cast<float>(i % 7);
    gt.pixels[i] = 4.0f * disp.pixels[i];
  }
  gt.pixels[3] = 0;  // unknown pixels and invalid disparities are left out
  disp.pixels[4] = kInf;
  const EvalInputCheck c = check_eval_inputs(cview(disp), cview(gt));
  EXPECT_EQ(c.pixels, 100);
  EXPECT_EQ(c.both, 98);
  EXPECT_EQ(c.gt_unknown, 1);
  EXPECT_EQ(c.disp_none, 1);
  EXPECT_DOUBLE_EQ(c.median_gt_over_disp, 4.0);
  EXPECT_TRUE(scale_looks_wrong(c));
  for (int i = 0; i < 100; ++i) gt.pixels[i] = disp.pixels[i] + (i % 3 == 0 ? 9.0f : 0.25f);
  const EvalInputCheck ok = check_eval_inputs(cview(disp), cview(gt));
  EXPECT_FALSE(scale_looks_wrong(ok));  // a third of the pixels far off is a bad map, not a scale
  EXPECT_LT(ok.median_gt_over_disp, 1.1);
  // Nothing comparable: no verdict.
  const Image<float> none(10, 10, 1, kInf);
  EXPECT_FALSE(scale_looks_wrong(check_eval_inputs(cview(none), cview(gt))));
  EXPECT_EQ(code_of([&] { check_eval_inputs(cview(Image<float>(9, 10, 1)), cview(gt)); }),
            ErrorCode::kSizeMismatch);
}

// The swap signal needs both halves: DISP like a ground truth (holes, float
// values) and GT like a fixed-point matcher's output (complete, 1/16 grid).
TEST(Eval, SwapCheckNeedsBothSignals) {
  const int n = 1000;
  Image<float> float_gt_with_holes(n, 1, 1), q4_complete(n, 1, 1);
  for (int i = 0; i < n; ++i) {
    float_gt_with_holes.pixels[i] = i % 50 == 0 ? kInf : 10.3f + 0.001f * static_cast<float>(i);
    q4_complete.pixels[i] = 10.0f + static_cast<float>(i % 16) / 16.0f;
  }
  // Swapped: eval GT DISP.
  const EvalInputCheck swapped = check_eval_inputs(cview(float_gt_with_holes), cview(q4_complete));
  EXPECT_EQ(swapped.disp_none, 20);
  EXPECT_EQ(swapped.gt_unknown, 0);
  EXPECT_EQ(swapped.gt_off_q4_grid, 0);
  EXPECT_GT(swapped.disp_off_q4_grid, 900);
  EXPECT_TRUE(files_look_swapped(swapped));
  // The right order is not flagged.
  EXPECT_FALSE(files_look_swapped(check_eval_inputs(cview(q4_complete), cview(float_gt_with_holes))));
  // A matcher that leaves holes, scored against a complete Q4-grid ground
  // truth (Middlebury v2 venus: complete, value / 8): holes alone are no swap.
  Image<float> q4_with_holes = q4_complete;
  for (int i = 0; i < n; i += 10) q4_with_holes.pixels[i] = kInf;
  EXPECT_FALSE(files_look_swapped(check_eval_inputs(cview(q4_with_holes), cview(q4_complete))));
  // A float-output matcher with holes against a float ground truth: no swap either.
  Image<float> float_complete = float_gt_with_holes;
  for (float& v : float_complete.pixels) v = std::isfinite(v) ? v : 12.34f;
  EXPECT_FALSE(files_look_swapped(check_eval_inputs(cview(float_gt_with_holes), cview(float_complete))));
}

// Every scene of every set through the support loader: sizes agree, the
// ground truth scores 0 against itself by the README's metric, and the known
// pixel counts are those of the files (KITTI about 20 % LiDAR coverage).
TEST(Eval, EveryDataSetSceneLoadsAndScoresItsGroundTruthPerfectly) {
  TRISTEREO_REQUIRE_ALL_DATA();
  const std::vector<test::DataScene> scenes = test::load_all_data_scenes();
  ASSERT_EQ(scenes.size(), 13u);
  std::map<std::string, int> per_set;
  for (const test::DataScene& s : scenes) {
    SCOPED_TRACE(s.set + "/" + s.name);
    ++per_set[s.set];
    ASSERT_EQ(s.gt.width, s.left.width);
    ASSERT_EQ(s.gt.height, s.left.height);
    ASSERT_EQ(s.right.width, s.left.width);
    EXPECT_EQ(readme_score(s, s.gt.view()), 0.0);
    const BadPixelStats self = evaluate_disparity(s.gt.view(), s.gt.view(), {});
    EXPECT_EQ(self.d1, 0.0);
    EXPECT_EQ(self.invalid, 0);
    float max_gt = 0;
    for (float g : s.gt.pixels)
      if (std::isfinite(g)) max_gt = std::max(max_gt, g);
    EXPECT_LT(max_gt, static_cast<float>(s.ndisp));  // the search range covers the ground truth
    // Shifting by 3.5 px: bad 3 everywhere; D1 exactly where 3.5 > 5 % of gt (gt < 70).
    Image<float> shifted = s.gt;
    std::int64_t below70 = 0;
    for (float& v : shifted.pixels) {
      if (std::isfinite(v) && v != 0.f) below70 += v < 70.f;
      v += 3.5f;
    }
    const BadPixelStats sh = evaluate_disparity(shifted.view(), s.gt.view(), {});
    EXPECT_EQ(sh.bad_3, 100.0);
    EXPECT_DOUBLE_EQ(sh.d1, 100.0 * static_cast<double>(below70) / static_cast<double>(sh.evaluated));
    if (s.set == "middlebury2014") {
      // mask0nocc.png: 0 exactly where the ground truth is unknown.
      ASSERT_EQ(s.nonocc.width, s.gt.width);
      for (std::size_t i = 0; i < s.gt.pixels.size(); ++i)
        ASSERT_EQ(s.nonocc.pixels[i] == 0, !std::isfinite(s.gt.pixels[i])) << "pixel " << i;
      EXPECT_LT(evaluate_disparity(s.gt.view(), s.gt.view(), s.nonocc.view()).evaluated, self.evaluated);
    }
    if (s.set == "middlebury") {
      EXPECT_TRUE(std::isnan(s.peer_sgbm));  // v2 has set means only (issue #14)
    } else {
      EXPECT_GT(s.peer_sgbm, 0.0);
      EXPECT_GT(s.peer_bm, 0.0);
      EXPECT_GT(s.peer_libelas, 0.0);
    }
    if (s.set == "kitti2015") {
      EXPECT_EQ(s.nonocc.width, 0);
      EXPECT_EQ(s.metric, test::DataMetric::kD1);
      EXPECT_GT(self.evaluated, s.gt.pixels.size() / 10);  // README: about 20 % of the pixels
      EXPECT_LT(self.evaluated, s.gt.pixels.size() * 3 / 10);
    }
  }
  EXPECT_EQ(per_set["middlebury"], 4);
  EXPECT_EQ(per_set["middlebury2014"], 6);
  EXPECT_EQ(per_set["kitti2015"], 2);
  EXPECT_EQ(per_set["eth3d"], 1);
  // Known pixel counts, from the files themselves (eval GT GT --json).
  EXPECT_EQ(evaluate_disparity(scenes[10].gt.view(), scenes[10].gt.view(), {}).evaluated, 88975);
  EXPECT_EQ(scenes[10].name, "000000");
  // The README's peer table, e.g. jadeplant: SGBM 51.9, StereoBM 65.2, libelas 40.1.
  EXPECT_EQ(scenes[5].name, "jadeplant");
  EXPECT_EQ(scenes[5].peer_sgbm, 51.9);
  EXPECT_EQ(scenes[5].peer_bm, 65.2);
  EXPECT_EQ(scenes[5].peer_libelas, 40.1);
  EXPECT_EQ(scenes[12].name, "playground");
  EXPECT_EQ(scenes[12].peer_sgbm, 7.4);
}

}  // namespace
}  // namespace tristereo
