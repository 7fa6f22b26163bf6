// The rectification stage: the remap kernel's SIMD twins against the scalar
// one, the integer stage against the float reference (bit for bit), the
// rectified frames against OpenCV's, and raw frames through the pipeline.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "support/data.hpp"
#include "support/kernel_param.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/rectify.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/status.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {
namespace {

class RemapKernel : public ::testing::TestWithParam<KernelChoice> {};

// Random maps over a padded source, every length from tail-only to several
// batches, the fractions' extremes (0 and 31 in each direction), canaries
// around the output.
TEST_P(RemapKernel, EqualsScalarTwin) {
  TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam());
  const KernelSet& simd = kernel_set_for(GetParam());
  const KernelSet& scalar = scalar_kernel_set();
  std::mt19937 rng(38);
  const int w = 53, h = 29;
  const std::size_t stride = 64;
  std::vector<std::uint8_t> src(stride * h);
  for (auto& p : src) p = static_cast<std::uint8_t>(rng() % 4 == 0 ? (rng() % 2) * 255 : rng() % 256);
  for (int n : {0, 1, 2, 3, 4, 7, 8, 9, 15, 16, 17, 31, 32, 33, 100, 257}) {
    std::vector<std::int16_t> xy(2 * static_cast<std::size_t>(n));
    std::vector<std::uint16_t> frac(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      xy[2 * i] = static_cast<std::int16_t>(rng() % (w - 1));
      xy[2 * i + 1] = static_cast<std::int16_t>(rng() % (h - 1));
      const int fx = i % 5 == 0 ? 0 : i % 5 == 1 ? 31 : static_cast<int>(rng() % 32);
      const int fy = i % 7 == 0 ? 0 : i % 7 == 1 ? 31 : static_cast<int>(rng() % 32);
      frac[i] = static_cast<std::uint16_t>(fy << 5 | fx);
    }
    std::vector<std::uint8_t> a(static_cast<std::size_t>(n) + 64, 0xA5), b(a);
    simd.remap_bilinear_row_u8(src.data(), stride, xy.data(), frac.data(), n, a.data() + 32);
    scalar.remap_bilinear_row_u8(src.data(), stride, xy.data(), frac.data(), n, b.data() + 32);
    for (std::size_t i = 0; i < a.size(); ++i)
      ASSERT_EQ(a[i], b[i]) << "n " << n << ", first difference at " << static_cast<long>(i) - 32;
  }
}

INSTANTIATE_TEST_SUITE_P(Sets, RemapKernel, ::testing::ValuesIn(test::simd_kernel_params()), test::KernelParamName());

ImageU8 gray(const ImageU8& img) {
  if (img.channels == 1) return img;
  ImageU8 g(img.width, img.height, 1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) g.at(x, y) = img.at(x, y, 0);
  return g;
}

struct RawPair {
  std::string set, name;
  StereoRig rig;
  Rectification rect;
  ImageU8 left, right;
  std::string cv_left, cv_right;  // OpenCV's rectified images ("" = none)
};

std::vector<RawPair> raw_pairs() {
  std::vector<RawPair> out;
  const std::string o = test::data_set_dir("opencv-stereo-calib"), e = test::data_set_dir("euroc-v101");
  for (const char* pair : {"01", "12"}) {
    RawPair p;
    p.set = "opencv-stereo-calib";
    p.name = std::string("rational ") + pair;
    p.rig = read_rig(o + "/calib_opencv.yml");
    p.rect = rectify_rig(p.rig);
    p.left = gray(read_image_u8(o + "/left" + pair + ".png"));
    p.right = gray(read_image_u8(o + "/right" + pair + ".png"));
    p.cv_left = o + "/rectified_cv_left" + pair + ".png";
    p.cv_right = o + "/rectified_cv_right" + pair + ".png";
    out.push_back(p);
  }
  RawPair pb;
  pb.set = "opencv-stereo-calib";
  pb.name = "plumb_bob 01";
  pb.rig = read_rig(o + "/plumb_bob/calib_opencv.yml");
  pb.rect = rectify_rig(pb.rig);
  pb.left = gray(read_image_u8(o + "/left01.png"));
  pb.right = gray(read_image_u8(o + "/right01.png"));
  pb.cv_left = o + "/plumb_bob/rectified_cv_left01.png";
  pb.cv_right = o + "/plumb_bob/rectified_cv_right01.png";
  out.push_back(pb);
  RawPair eu;
  eu.set = "euroc-v101";
  eu.name = "euroc 0000 (calib_opencv.yml)";
  eu.rig = read_rig(e + "/calib_opencv.yml");
  eu.rect = rectify_rig(eu.rig);
  eu.left = gray(read_image_u8(e + "/left_0000.png"));
  eu.right = gray(read_image_u8(e + "/right_0000.png"));
  eu.cv_left = e + "/rectified_cv_left_0000.png";
  eu.cv_right = e + "/rectified_cv_right_0000.png";
  out.push_back(eu);
  RawPair es = eu;
  es.name = "euroc 0000 (sensor.yaml, computed)";
  es.rig = read_rig(e + "/cam0_sensor.yaml", e + "/cam1_sensor.yaml");
  es.rect = rectify_rig(es.rig);
  es.cv_left = es.cv_right = "";
  out.push_back(es);
  return out;
}

class RectifyStage : public ::testing::TestWithParam<KernelChoice> {};

// The integer stage equals the float reference on every real raw frame of
// both sets, in both cameras, with every kernel set.
TEST_P(RectifyStage, EqualsReferenceOnRealFrames) {
  TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam());
  TRISTEREO_REQUIRE_DATA("opencv-stereo-calib");
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  for (const RawPair& p : raw_pairs()) {
    const RectifyMaps maps = build_rectify_maps(p.rig, p.rect);
    for (int cam = 0; cam < 2; ++cam) {
      const ImageU8& raw = cam == 0 ? p.left : p.right;
      ImageU8 mine(maps.left.width, maps.left.height, 1);
      remap_image(cam == 0 ? maps.left : maps.right, raw.view(), mine.view(), GetParam());
      const ImageU8 ref = reference_rectify(p.rig, p.rect, cam, raw);
      ASSERT_EQ(mine.pixels, ref.pixels) << p.name << " camera " << cam;
    }
  }
}

// Random rigs with strong distortion (many pixels whose taps leave the image,
// the border path) and odd sizes: integer == reference.
TEST_P(RectifyStage, EqualsReferenceOnRandomRigs) {
  TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    StereoRig rig;
    const int w = 17 + static_cast<int>(rng() % 90), h = 11 + static_cast<int>(rng() % 70);
    for (RawCamera* c : {&rig.left, &rig.right}) {
      c->width = w;
      c->height = h;
      const double f = w * (0.6 + 0.3 * u(rng));
      c->K = {f, 0, w / 2.0 + 3 * u(rng), 0, f * (1 + 0.01 * u(rng)), h / 2.0 + 3 * u(rng), 0, 0, 1};
      c->model = static_cast<DistortionModel>(trial % 3);
      if (c->model == DistortionModel::kEquidistant) c->dist = {0.1 * u(rng), 0.02 * u(rng), 0, 0, 0, 0, 0, 0};
      else c->dist = {0.3 * u(rng), 0.1 * u(rng), 0.01 * u(rng), 0.01 * u(rng), 0, 0.1 * u(rng), 0, 0};
    }
    const double a = 0.05 * u(rng);
    rig.R = {std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a)};
    rig.T = {-0.1, 0.005 * u(rng), 0.005 * u(rng)};
    Rectification rect;
    try {
      rect = compute_rectification(rig);
    } catch (const Error&) {
      continue;  // a random lens may fold over: refused, as it should be
    }
    const RectifyMaps maps = build_rectify_maps(rig, rect);
    ImageU8 raw(w, h, 1);
    for (auto& px : raw.pixels) px = static_cast<std::uint8_t>(rng());
    for (int cam = 0; cam < 2; ++cam) {
      ImageU8 mine(w, h, 1);
      remap_image(cam == 0 ? maps.left : maps.right, raw.view(), mine.view(), GetParam());
      ASSERT_EQ(mine.pixels, reference_rectify(rig, rect, cam, raw).pixels) << "trial " << trial << " camera " << cam;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Sets, RectifyStage, ::testing::ValuesIn(test::all_kernel_params()), test::KernelParamName());

// Against OpenCV's own rectified images (initUndistortRectifyMap CV_32FC1 +
// remap INTER_LINEAR, BORDER_CONSTANT 0): the same fixed-point remap, on a map
// that differs from OpenCV's float32 one by <= 3.1e-5 px, so only the pixels
// whose 1/32 rounding flips differ. Measured on the 8 images (4 pairs): max
// |difference| 2-4 grey levels, mean 0.00009-0.00015, 23-46 pixels of
// 307200/360960 differ; the thresholds are those with a margin.
TEST(Rectify, MatchesOpenCvRectifiedImages) {
  TRISTEREO_REQUIRE_DATA("opencv-stereo-calib");
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  for (const RawPair& p : raw_pairs()) {
    if (p.cv_left.empty()) continue;
    const RectifyMaps maps = build_rectify_maps(p.rig, p.rect);
    for (int cam = 0; cam < 2; ++cam) {
      ImageU8 mine(maps.left.width, maps.left.height, 1);
      remap_image(cam == 0 ? maps.left : maps.right, (cam == 0 ? p.left : p.right).view(), mine.view());
      const ImageU8 cv = gray(read_image_u8(cam == 0 ? p.cv_left : p.cv_right));
      ASSERT_EQ(cv.width, mine.width);
      int worst = 0;
      double sum = 0;
      long differ = 0;
      for (std::size_t i = 0; i < cv.pixels.size(); ++i) {
        const int d = std::abs(int(cv.pixels[i]) - int(mine.pixels[i]));
        worst = std::max(worst, d);
        sum += d;
        differ += d != 0;
      }
      std::printf("%s camera %d: max |diff| %d, mean %.5f, %ld of %zu pixels differ\n", p.name.c_str(), cam, worst,
                  sum / cv.pixels.size(), differ, cv.pixels.size());
      EXPECT_LE(worst, 6) << p.name;
      EXPECT_LT(sum / cv.pixels.size(), 0.0005) << p.name;
      EXPECT_LT(differ, 100) << p.name;
    }
  }
}

// Raw frames through the pipeline give what the rectified frames give, for
// 1 and 3 workers, and every kernel set agrees.
TEST(Rectify, PipelineOnRawFramesEqualsPipelineOnRectifiedFrames) {
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  const std::string e = test::data_set_dir("euroc-v101");
  const StereoRig rig = read_rig(e + "/cam0_sensor.yaml", e + "/cam1_sensor.yaml");
  auto maps = std::make_shared<RectifyMaps>(build_rectify_maps(rig, rectify_rig(rig)));
  const ImageU8 left = gray(read_image_u8(e + "/left_0000.png")), right = gray(read_image_u8(e + "/right_0000.png"));
  ImageU8 rl(752, 480, 1), rr(752, 480, 1);
  remap_image(maps->left, left.view(), rl.view());
  remap_image(maps->right, right.view(), rr.view());
  PipelineConfig plain;
  plain.max_width = 752;
  plain.max_height = 480;
  plain.params.d_min = 0;
  plain.params.num_disp = 64;
  plain.threads = 2;
  Pipeline expected;
  expected.configure(plain);
  const std::vector<std::int16_t> want = expected.process(rl.view(), rr.view()).disp_q4.pixels;
  for (KernelChoice k : test::all_kernel_params()) {
    if (!test::kernel_set_runnable(k)) continue;
    for (int threads : {1, 3}) {
      PipelineConfig raw = plain;
      raw.rectify = maps;
      raw.threads = threads;
      raw.kernels = k;
      Pipeline p;
      p.configure(raw);
      EXPECT_GE(p.working_memory_bytes(), maps->memory_bytes() + 2 * 752 * 480);
      EXPECT_EQ(p.process(left.view(), right.view()).disp_q4.pixels, want) << to_string(k) << ", " << threads;
    }
  }
  // The matcher on the rectified EuRoC pair: the README's SGBM has 80 % valid
  // pixels with a median of 21.8 px; the chessboard is at 20.5-21.9 px.
  std::vector<double> d;
  for (std::int16_t v : want)
    if (v >= 0) d.push_back(v / 16.0);
  std::sort(d.begin(), d.end());
  const double median = d[d.size() / 2];
  std::printf("euroc 0000 raw in: %.1f %% valid, median disparity %.2f px\n", 100.0 * d.size() / want.size(), median);
  EXPECT_GT(median, 17);
  EXPECT_LT(median, 27);
  // A raw frame of another size is refused, naming both sizes.
  PipelineConfig raw = plain;
  raw.rectify = maps;
  Pipeline p;
  p.configure(raw);
  const ImageU8 small(640, 480, 1);
  EXPECT_THROW(p.process(small.view(), small.view()), Error);
}

// Analytic maps: a pinhole rig without distortion whose rectification is the
// identity gives the raw image back exactly (every position is a whole pixel:
// one tap of weight 1024); moving the rectified principal point by -3 px in
// x takes every pixel from 3 px to its right (black beyond the raw image),
// and by -0.5 px gives the rounded mean of two neighbours.
TEST(Rectify, AnalyticMapsIdentityAndPrincipalPointShift) {
  const int w = 61, h = 37;
  StereoRig rig;
  for (RawCamera* c : {&rig.left, &rig.right}) {
    c->K = {500, 0, 30, 0, 500, 18, 0, 0, 1};
    c->width = w;
    c->height = h;
  }
  rig.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  rig.T = {-0.1, 0, 0};
  Rectification rect;
  rect.R1 = rect.R2 = rig.R;
  rect.width = w;
  rect.height = h;
  rect.from_file = true;
  std::mt19937 rng(3838);
  ImageU8 raw(w, h, 1);
  for (auto& p : raw.pixels) p = static_cast<std::uint8_t>(rng() % 256);
  for (double shift : {0.0, 3.0, 0.5}) {
    rect.P1 = {500, 0, 30 - shift, 0, 0, 500, 18, 0, 0, 0, 1, 0};
    rect.P2 = {500, 0, 30 - shift, -50, 0, 500, 18, 0, 0, 0, 1, 0};
    const RectifyMaps maps = build_rectify_maps(rig, rect);
    for (KernelChoice k : test::all_kernel_params()) {
      if (!test::kernel_set_runnable(k)) continue;
      for (int cam = 0; cam < 2; ++cam) {
        ImageU8 out(w, h, 1);
        remap_image(cam == 0 ? maps.left : maps.right, raw.view(), out.view(), k);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            int want;
            if (shift == 0.5) {
              const int a = raw.at(x, y), b = x + 1 < w ? raw.at(x + 1, y) : 0;
              want = (a + b + 1) >> 1;  // (512 a + 512 b + 512) >> 10
            } else {
              const int sx = x + static_cast<int>(shift);
              want = sx < w ? raw.at(sx, y) : 0;
            }
            ASSERT_EQ(out.at(x, y), want) << "shift " << shift << ", " << to_string(k) << ", camera " << cam
                                          << " at (" << x << ", " << y << ")";
          }
      }
    }
  }
}

// The two files of the EuRoC rig: the sensor.yaml pair (rectification
// computed here, in double) and the ROS camera_info pair (OpenCV's
// stereoRectify of the same calibration, read as given). Their rectified
// pairs are not byte-identical: f, cx, cy agree to ~1e-5 px, and the few
// positions whose 1/32 rounding falls on the other side differ (measured: 15
// and 13 of 360960 pixels, at most 3 grey levels). The ROS pair and
// calib_opencv.yml (the same OpenCV rectification) give the same images.
TEST(Rectify, EurocSensorYamlAndRosCameraInfoPairsAgree) {
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  const std::string e = test::data_set_dir("euroc-v101");
  const StereoRig sensor = read_rig(e + "/cam0_sensor.yaml", e + "/cam1_sensor.yaml");
  const StereoRig ros = read_rig(e + "/left.yaml", e + "/right.yaml");
  const StereoRig cv = read_rig(e + "/calib_opencv.yml");
  const RectifyMaps ms = build_rectify_maps(sensor, rectify_rig(sensor));
  const RectifyMaps mr = build_rectify_maps(ros, rectify_rig(ros));
  const RectifyMaps mc = build_rectify_maps(cv, rectify_rig(cv));
  for (int cam = 0; cam < 2; ++cam) {
    const ImageU8 raw = gray(read_image_u8(e + (cam == 0 ? "/left_0000.png" : "/right_0000.png")));
    ImageU8 a(752, 480, 1), b(752, 480, 1), c(752, 480, 1);
    remap_image(cam == 0 ? ms.left : ms.right, raw.view(), a.view());
    remap_image(cam == 0 ? mr.left : mr.right, raw.view(), b.view());
    remap_image(cam == 0 ? mc.left : mc.right, raw.view(), c.view());
    int worst = 0;
    long differ = 0, differ_cv = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
      const int d = std::abs(int(a.pixels[i]) - int(b.pixels[i]));
      worst = std::max(worst, d);
      differ += d != 0;
      differ_cv += b.pixels[i] != c.pixels[i];
    }
    std::printf("euroc 0000 camera %d: sensor.yaml vs camera_info %ld pixels differ (max %d); camera_info vs "
                "calib_opencv.yml %ld\n",
                cam, differ, worst, differ_cv);
    EXPECT_LE(worst, 4);
    EXPECT_LT(differ, 60);
    EXPECT_EQ(differ_cv, 0);
  }
}

}  // namespace
}  // namespace tristereo

namespace tristereo {
namespace {

// verify on raw frames: the reference rectifies by its float definition and
// matches, every kernel set and thread count rectifies by its stage; all
// identical on a real raw pair (one: the float reference of a whole frame is
// slow under the ARM emulators), the rig's rectification computed from its
// EuRoC sensor.yaml files.
TEST(Rectify, VerifyCoversRawFramesBitForBit) {
  TRISTEREO_REQUIRE_DATA("opencv-stereo-calib");
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  const std::vector<RawPair> pairs = raw_pairs();
  int checked = 0;
  for (const RawPair& p : pairs) {
    if (p.name != "euroc 0000 (sensor.yaml, computed)") continue;
    SCOPED_TRACE(p.name);
    StereoParams params;
    params.num_disp = 32;
    const VerifyReport r = verify_bit_exact_raw(p.left, p.right, p.rig, p.rect, params, {1, 3});
    EXPECT_TRUE(r.bit_exact);
    EXPECT_EQ(r.cases.size(), 2 * available_kernel_sets().size());
    for (const VerifyCase& c : r.cases) EXPECT_TRUE(c.identical) << to_string(c.kernels) << ": " << c.first_difference;
    ++checked;
  }
  EXPECT_EQ(checked, 1);
}

}  // namespace
}  // namespace tristereo
