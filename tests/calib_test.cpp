// Calibration readers (Middlebury calib.txt, KITTI P0..P3, OpenCV YAML/XML)
// and the metric depth they give (include/tristereo/calib.hpp, depth.hpp).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/data.hpp"
#include "tristereo/calib.hpp"
#include "tristereo/depth.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

namespace fs = std::filesystem;

class Calib : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("tristereo_calib_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  fs::path dir_;
};

// The message of the Error f throws ("" and a test failure when it throws none).
std::string message_of(const std::function<void()>& f, ErrorCode* code = nullptr) {
  try {
    f();
  } catch (const Error& e) {
    if (code) *code = e.code();
    return e.what();
  }
  ADD_FAILURE() << "no tristereo::Error thrown";
  return "";
}

void expect_rel(double got, double want, double tol, const std::string& what) {
  EXPECT_LE(std::fabs(got - want), tol * std::fabs(want)) << what << ": " << got << " vs " << want;
}

// KITTI 2015 devkit calibration of frame 000000 (calib_cam_to_cam rectified P2/P3).
const char* kKittiText =
    "P0: 7.215377e+02 0.000000e+00 6.095593e+02 0.000000e+00 0.000000e+00 7.215377e+02 1.728540e+02 "
    "0.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00 0.000000e+00\n"
    "P1: 7.215377e+02 0.000000e+00 6.095593e+02 -3.875744e+02 0.000000e+00 7.215377e+02 1.728540e+02 "
    "0.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00 0.000000e+00\n"
    "P2: 7.215377e+02 0.000000e+00 6.095593e+02 4.485728e+01 0.000000e+00 7.215377e+02 1.728540e+02 "
    "2.163791e-01 0.000000e+00 0.000000e+00 1.000000e+00 2.745884e-03\n"
    "P3: 7.215377e+02 0.000000e+00 6.095593e+02 -3.395242e+02 0.000000e+00 7.215377e+02 1.728540e+02 "
    "2.199936e+00 0.000000e+00 0.000000e+00 1.000000e+00 2.729905e-03\n"
    "R0_rect: 9.999239e-01 9.837760e-03 -7.445048e-03 -9.869795e-03 9.999421e-01 -4.278459e-03 "
    "7.402527e-03 4.351614e-03 9.999631e-01\n";

// stereoRectify-style outputs for f = 700 px, cx1 = 320, cx2 = 331.5, cy = 240,
// Tx = -120 (millimetres): P2(0,3) = Tx f, Q(3,2) = -1/Tx, Q(3,3) = (cx1 - cx2)/Tx.
const char* kOpenCvYaml =
    "%YAML:1.0\n---\n"
    "image_width: 640\nimage_height: 480\n"
    "P1: !!opencv-matrix\n   rows: 3\n   cols: 4\n   dt: d\n"
    "   data: [ 700., 0., 320., 0., 0., 700., 240., 0., 0., 0., 1.,\n       0. ]\n"
    "P2: !!opencv-matrix\n   rows: 3\n   cols: 4\n   dt: d\n"
    "   data: [ 700., 0., 331.5, -84000., 0., 700., 240., 0., 0., 0.,\n       1., 0. ]\n";

const char* kOpenCvQYaml =
    "%YAML:1.0\n---\n"
    "Q: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n"
    "   data: [ 1., 0., 0., -320., 0., 1., 0., -240., 0., 0., 0., 700., 0., 0.,\n"
    "       8.3333333333333332e-03, 9.5833333333333326e-02 ]\n";

const char* kOpenCvXml =
    "<?xml version=\"1.0\"?>\n<opencv_storage>\n"
    "<imageSize>\n  640 480</imageSize>\n"
    "<P1 type_id=\"opencv-matrix\">\n  <rows>3</rows>\n  <cols>4</cols>\n  <dt>d</dt>\n"
    "  <data>\n    700. 0. 320. 0. 0. 700. 240. 0. 0. 0. 1. 0.</data></P1>\n"
    "<P2 type_id=\"opencv-matrix\">\n  <rows>3</rows>\n  <cols>4</cols>\n  <dt>d</dt>\n"
    "  <data>\n    700. 0. 331.5 -84000. 0. 700. 240. 0. 0. 0. 1. 0.</data></P2>\n"
    "</opencv_storage>\n";

TEST_F(Calib, MiddleburyAdirondackDepthFromGroundTruth) {
  TRISTEREO_REQUIRE_DATA("middlebury2014");
  const std::string dir = test::data_set_dir("middlebury2014") + "/adirondack";
  const StereoCalibration c = read_calibration(dir + "/calib.txt");
  EXPECT_EQ(c.format, CalibFormat::kMiddlebury);
  // calib.txt: cam0=[ 1038.018 0 322.037 ; 0 1038.018 243.393 ; 0 0 1 ], doffs= 53.271,
  // baseline= 176.252 (mm), width= 718, height= 496.
  const double f = 1038.018, b_m = 0.176252, doffs = 53.271;
  EXPECT_DOUBLE_EQ(c.focal_px, f);
  EXPECT_DOUBLE_EQ(c.cx_px, 322.037);
  EXPECT_DOUBLE_EQ(c.cy_px, 243.393);
  EXPECT_DOUBLE_EQ(c.doffs_px, doffs);
  EXPECT_DOUBLE_EQ(c.baseline_m, b_m);
  EXPECT_EQ(c.width, 718);
  EXPECT_EQ(c.height, 496);
  check_calibration_size(c, 718, 496);

  const Image<float> gt = read_pfm(dir + "/disp0GT.pfm");
  const Image<float> depth = depth_m_from_disp_px(gt.view(), c.camera());
  const std::string pfm = write("depth.pfm", ""), png = write("depth.png", "");
  const DepthWriteReport rp = write_depth(pfm, depth.view());
  const DepthWriteReport rm = write_depth(png, depth.view());
  const Image<float> back = read_pfm(pfm);
  const Image<std::uint16_t> mm = read_png_u16(png);
  std::int64_t known = 0;
  double worst = 0;
  for (int y = 0; y < gt.height; ++y)
    for (int x = 0; x < gt.width; ++x) {
      const float d = gt.at(x, y);
      if (!std::isfinite(d)) {
        ASSERT_TRUE(std::isinf(back.at(x, y))) << x << "," << y;
        ASSERT_EQ(mm.at(x, y), 0) << x << "," << y;
        continue;
      }
      ++known;
      const double z = f * b_m / (d + doffs);
      worst = std::max(worst, std::fabs(back.at(x, y) - z) / z);
      // Millimetres rounded to nearest (from the float depth: at most a
      // rounding step beyond half a millimetre).
      ASSERT_LE(std::fabs(mm.at(x, y) - z * 1000), 0.5 + 1e-3) << x << "," << y;
    }
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(known, 300000);
  EXPECT_EQ(rp.valid, known);
  EXPECT_EQ(rm.valid, known);
  EXPECT_EQ(rm.out_of_range, 0);
}

TEST_F(Calib, KittiDevkitP2P3) {
  const StereoCalibration c = read_calibration(write("000000.txt", kKittiText));
  EXPECT_EQ(c.format, CalibFormat::kKitti);
  const double f = 7.215377e+02, b_m = (4.485728e+01 + 3.395242e+02) / 7.215377e+02;
  EXPECT_DOUBLE_EQ(c.focal_px, f);
  EXPECT_DOUBLE_EQ(c.cx_px, 6.095593e+02);
  EXPECT_DOUBLE_EQ(c.cy_px, 1.728540e+02);
  EXPECT_DOUBLE_EQ(c.doffs_px, 0.0);
  expect_rel(c.baseline_m, b_m, 1e-12, "baseline");
  expect_rel(c.baseline_m, 0.5327, 1e-3, "KITTI's 0.54 m stereo rig");
  // Disparities 1 .. 255.9375 px in Q4, through the depth writer.
  Image<std::int16_t> disp(64, 64, 1);
  for (int i = 0; i < 64 * 64; ++i) disp.pixels[i] = static_cast<std::int16_t>(16 + i % 4080);
  disp.pixels[5] = kInvalidDispQ4;
  const std::string pfm = write("kitti_depth.pfm", "");
  write_depth(pfm, depth_m_from_disp_q4(disp.view(), c.camera()).view());
  const Image<float> back = read_pfm(pfm);
  for (int i = 0; i < 64 * 64; ++i) {
    if (i == 5) {
      EXPECT_TRUE(std::isinf(back.pixels[i]));
      continue;
    }
    expect_rel(back.pixels[i], f * b_m / (disp.pixels[i] / 16.0), 1e-6, "pixel " + std::to_string(i));
  }
  // Without P2/P3 the gray pair P0/P1 is used.
  const std::string gray = std::string(kKittiText).substr(0, std::string(kKittiText).find("P2:"));
  const StereoCalibration g = read_calibration(write("gray.txt", gray));
  expect_rel(g.baseline_m, 3.875744e+02 / 7.215377e+02, 1e-12, "P0/P1 baseline");
}

TEST_F(Calib, OpenCvYamlXmlAndQAgree) {
  const StereoCalibration y = read_calibration(write("stereo.yml", kOpenCvYaml), CalibFormat::kAuto, 0.001);
  const StereoCalibration x = read_calibration(write("stereo.xml", kOpenCvXml), CalibFormat::kAuto, 0.001);
  const StereoCalibration q = read_calibration(write("q.yml", kOpenCvQYaml), CalibFormat::kOpenCv, 0.001);
  for (const StereoCalibration* c : {&y, &x, &q}) {
    SCOPED_TRACE(c->path);
    EXPECT_EQ(c->format, CalibFormat::kOpenCv);
    EXPECT_DOUBLE_EQ(c->focal_px, 700.0);
    EXPECT_DOUBLE_EQ(c->cx_px, 320.0);
    EXPECT_DOUBLE_EQ(c->cy_px, 240.0);
    expect_rel(c->doffs_px, 11.5, 1e-12, "doffs");
    expect_rel(c->baseline_m, 0.12, 1e-12, "baseline");
  }
  EXPECT_EQ(y.width, 640);
  EXPECT_EQ(y.height, 480);
  EXPECT_EQ(x.width, 640);
  EXPECT_EQ(x.height, 480);
  EXPECT_EQ(q.width, 0);  // Q alone states no size: any input size is accepted
  check_calibration_size(q, 1242, 375);
  // Metres are the default unit: the same file then says 120 m.
  expect_rel(read_calibration(write("m.yml", kOpenCvYaml)).baseline_m, 120.0, 1e-12, "unit m");
  // Depth: Z = f B / (d + doffs), 16 px -> 700 * 0.12 / 27.5.
  Image<std::int16_t> disp(1, 1, 1, 16 * 16);
  expect_rel(depth_m_from_disp_q4(disp.view(), y.camera()).at(0, 0), 700 * 0.12 / 27.5, 1e-6, "Z");
}

TEST_F(Calib, BadFilesNameFileLineAndKey) {
  ErrorCode code{};
  // Missing key.
  std::string m = message_of([&] { read_calibration(write("a.txt", "cam0=[1 0 2; 0 1 3; 0 0 1]\ndoffs=0\n")); }, &code);
  EXPECT_EQ(code, ErrorCode::kCorruptFile);
  EXPECT_NE(m.find("a.txt"), std::string::npos) << m;
  EXPECT_NE(m.find("key 'baseline'"), std::string::npos) << m;
  // Non-numeric value: names the line.
  m = message_of([&] { read_calibration(write("b.txt", "cam0=[1 0 2; 0 1 3; 0 0 1]\ndoffs=0\nbaseline=abc\n")); }, &code);
  EXPECT_EQ(code, ErrorCode::kCorruptFile);
  EXPECT_NE(m.find("line 3"), std::string::npos) << m;
  EXPECT_NE(m.find("'abc' is not a finite number"), std::string::npos) << m;
  // Zero baseline, negative focal length.
  m = message_of([&] { read_calibration(write("c.txt", "cam0=[500 0 2; 0 500 3; 0 0 1]\ndoffs=0\nbaseline=0\n")); }, &code);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(m.find("line 3, key 'baseline'"), std::string::npos) << m;
  m = message_of([&] { read_calibration(write("d.txt", "cam0=[-5 0 2; 0 -5 3; 0 0 1]\ndoffs=0\nbaseline=100\n")); }, &code);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(m.find("line 1, key 'focal length'"), std::string::npos) << m;
  // A 3x3 matrix with 8 numbers.
  m = message_of([&] { read_calibration(write("e.txt", "cam0=[1 0 2; 0 1 3; 0 0]\ndoffs=0\nbaseline=1\n")); });
  EXPECT_NE(m.find("key 'cam0'"), std::string::npos) << m;
  // KITTI: P3 missing; P2 with 11 numbers.
  m = message_of([&] { read_calibration(write("k.txt", "P2: 1 0 0 0 0 1 0 0 0 0 1 0\n"), CalibFormat::kKitti); });
  EXPECT_NE(m.find("P2/P3"), std::string::npos) << m;
  m = message_of([&] { read_calibration(write("k2.txt", "P2: 1 0 0 0 0 1 0 0 0 0 1\nP3: 1 0 0 -1 0 1 0 0 0 0 1 0\n")); });
  EXPECT_NE(m.find("line 1, key 'P2'"), std::string::npos) << m;
  // OpenCV: neither P1/P2 nor Q; a matrix of the wrong shape.
  m = message_of([&] { read_calibration(write("o.yml", "%YAML:1.0\n---\nK1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [1,0,0,0,1,0,0,0,1]\n")); });
  EXPECT_NE(m.find("P1/P2"), std::string::npos) << m;
  m = message_of([&] {
    read_calibration(write("o2.yml", "%YAML:1.0\nQ: !!opencv-matrix\n   rows: 3\n   cols: 4\n   dt: d\n   data: [1,0,0,0,1,0,0,0,1,0,0,0]\n"));
  });
  EXPECT_NE(m.find("line 2, key 'Q'"), std::string::npos) << m;
  EXPECT_NE(m.find("expected 4x4"), std::string::npos) << m;
  // Unknown format, missing file, a size mismatch.
  m = message_of([&] { read_calibration(write("x.txt", "hello\n")); }, &code);
  EXPECT_EQ(code, ErrorCode::kUnsupportedFormat);
  message_of([&] { read_calibration((dir_ / "missing.txt").string()); }, &code);
  EXPECT_EQ(code, ErrorCode::kIoError);
  const StereoCalibration c = read_calibration(write("ok.yml", kOpenCvYaml));
  m = message_of([&] { check_calibration_size(c, 641, 480); }, &code);
  EXPECT_EQ(code, ErrorCode::kSizeMismatch);
  EXPECT_NE(m.find("640x480"), std::string::npos) << m;
  EXPECT_NE(m.find("641x480"), std::string::npos) << m;
  // Bad unit, bad format names.
  message_of([&] { read_calibration(write("ok2.yml", kOpenCvYaml), CalibFormat::kAuto, 0); }, &code);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(parse_calib_format("kitti"), CalibFormat::kKitti);
  message_of([&] { parse_calib_format("ros"); }, &code);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
}

TEST_F(Calib, ValuesOutsideWhatARigCanHaveAreRefusedInEveryFormat) {
  // Issue 41: f = B = 1e300 wrote +inf everywhere, B = 1e-300 wrote 0 m.
  struct Case {
    const char* name;
    std::string text;
    const char* where;  // line and key the message must name
    const char* what;   // the bound, numbers in %g
  };
  const std::vector<Case> cases = {
      {"m_f.txt", "cam0=[1e300 0 48; 0 1e300 32; 0 0 1]\ndoffs=2\nbaseline=120\n", "line 1, key 'focal length'",
       "focal length 1e+300 px is outside [1, 1e+06] px"},
      {"m_b.txt", "cam0=[200 0 48; 0 200 32; 0 0 1]\ndoffs=2\nbaseline=1e-297\n", "line 3, key 'baseline'",
       "baseline 1e-300 m is outside [0.0001, 1000] m"},
      {"m_b2.txt", "cam0=[200 0 48; 0 200 32; 0 0 1]\ndoffs=2\nbaseline=2e6\n", "line 3, key 'baseline'",
       "baseline 2000 m is outside [0.0001, 1000] m"},
      {"m_cx.txt", "cam0=[200 0 500; 0 200 32; 0 0 1]\ndoffs=2\nbaseline=120\nwidth=96\nheight=64\n",
       "line 1, key 'principal point'", "principal point cx 500 px is outside [-96, 192] px (for a 96x64 image)"},
      {"m_doffs.txt", "cam0=[200 0 48; 0 200 32; 0 0 1]\ndoffs=-400\nbaseline=120\nwidth=96\nheight=64\n",
       "key 'doffs'", "doffs -400 px is outside [-288, 288] px (for a 96x64 image)"},
      {"k_f.txt",
       "P2: 1e7 0 600 0 0 1e7 170 0 0 0 1 0\nP3: 1e7 0 600 -5e6 0 1e7 170 0 0 0 1 0\n", "line 1, key 'focal length'",
       "focal length 1e+07 px is outside [1, 1e+06] px"},
      {"o_b.yml", std::string(kOpenCvYaml), "key 'baseline'", ""},  // replaced below: a 1e-7 m baseline
  };
  for (Case c : cases) {
    if (std::string(c.name) == "o_b.yml") {
      // P2(0,3) = -Tx f: Tx = 1e-7 units (metres by default).
      const std::size_t at = c.text.find("-84000.");
      c.text.replace(at, 7, "-7e-5");
      c.what = "baseline 1e-07 m is outside [0.0001, 1000] m";
    }
    ErrorCode code{};
    const std::string m = message_of([&] { read_calibration(write(c.name, c.text)); }, &code);
    EXPECT_EQ(code, ErrorCode::kInvalidArgument) << c.name;
    EXPECT_NE(m.find(c.where), std::string::npos) << c.name << ": " << m;
    EXPECT_NE(m.find(c.what), std::string::npos) << c.name << ": " << m;
    EXPECT_LT(m.size(), 260u) << c.name << ": no 300-digit numbers: " << m;
  }
  // The bounds themselves, as --camera is held to them.
  CameraParams cam{200, 0.1, 48, 32, 2};
  EXPECT_FALSE(check_camera_bounds(cam, 96, 64));
  cam.baseline = kMinBaselineM;
  EXPECT_FALSE(check_camera_bounds(cam, 96, 64));
  cam.baseline = std::nan("");
  EXPECT_EQ(check_camera_bounds(cam, 96, 64).field, CameraField::kBaseline);
  cam.baseline = 0.1;
  cam.cy = -65;
  EXPECT_EQ(check_camera_bounds(cam, 96, 64).field, CameraField::kPrincipalPoint);
  EXPECT_FALSE(check_camera_bounds(cam, 0, 0)) << "no size known: the largest readable image's bounds";
}

TEST_F(Calib, AUtf8ByteOrderMarkIsNotPartOfTheFirstKey) {
  // Windows editors start a saved text file with EF BB BF; before issue 41
  // it made "cam0" unrecognisable.
  const std::string text = "cam0=[700 0 320; 0 700 240; 0 0 1]\ndoffs=2\nbaseline=120\n";
  const StereoCalibration plain = read_calibration(write("plain.txt", text));
  const StereoCalibration bom = read_calibration(write("bom.txt", "\xEF\xBB\xBF" + text));
  EXPECT_EQ(bom.format, CalibFormat::kMiddlebury);
  EXPECT_EQ(bom.focal_px, plain.focal_px);
  EXPECT_EQ(bom.baseline_m, plain.baseline_m);
  EXPECT_EQ(bom.doffs_px, plain.doffs_px);
  const StereoCalibration yaml = read_calibration(write("bom.yml", std::string("\xEF\xBB\xBF") + kOpenCvYaml));
  EXPECT_EQ(yaml.format, CalibFormat::kOpenCv);
  EXPECT_EQ(yaml.focal_px, 700);
}

// A stream has no size to check and no end: the reader stops one byte past its limit.
TEST_F(Calib, StreamsFoldersAndBinaryFilesAreNotCalibrations) {
  ErrorCode code{};
  std::string m = message_of([&] { read_calibration("/dev/zero"); }, &code);
  EXPECT_EQ(code, ErrorCode::kUnsupportedFormat);
  EXPECT_NE(m.find("not a calibration file"), std::string::npos) << m;
  m = message_of([&] { read_calibration(dir_.string()); }, &code);
  EXPECT_EQ(code, ErrorCode::kIoError) << m;
  m = message_of([&] { read_calibration(write("bin.txt", std::string("cam0=\0\1", 7))); }, &code);
  EXPECT_EQ(code, ErrorCode::kUnsupportedFormat);
  EXPECT_NE(m.find("NUL bytes"), std::string::npos) << m;
  m = message_of([&] { read_calibration(write("big.txt", std::string((1 << 20) + 1, '#'))); }, &code);
  EXPECT_EQ(code, ErrorCode::kUnsupportedFormat);
  m = message_of([&] { read_calibration((dir_ / "missing.txt").string()); }, &code);
  EXPECT_NE(m.find("No such file or directory"), std::string::npos) << m;
}

TEST_F(Calib, PointCloudHasOnePointPerValidPixel) {
  Image<std::int16_t> disp(5, 4, 1, 32);
  disp.at(1, 1) = kInvalidDispQ4;
  disp.at(2, 2) = -200;  // d + doffs <= 0: no depth
  const ImageU8 left(5, 4, 3, 100);
  CameraParams cam{};
  cam.focal_px = 10;
  cam.baseline = 0.5;
  cam.cx = 2;
  cam.cy = 1.5;
  cam.doffs = 1;
  const std::string p = write("pts.ply", "");
  EXPECT_EQ(write_points_ply(p, disp.view(), left.view(), cam, false), 18);
  std::ifstream f(p);
  std::string line;
  int points = 0;
  bool in_body = false;
  while (std::getline(f, line)) {
    if (line == "element vertex 18") points = -1;
    if (in_body) {
      float x, y, z;
      int r, g, b;
      ASSERT_EQ(std::sscanf(line.c_str(), "%f %f %f %d %d %d", &x, &y, &z, &r, &g, &b), 6) << line;
      EXPECT_FLOAT_EQ(z, 10 * 0.5 / 3.0);  // d = 2 px, doffs = 1
      EXPECT_EQ(r, 100);
      ++points;
    }
    if (line == "end_header") {
      ASSERT_EQ(points, -1) << "header without 'element vertex 18'";
      points = 0;
      in_body = true;
    }
  }
  EXPECT_EQ(points, 18);
  ErrorCode code{};
  const ImageU8 small(4, 4, 3);
  message_of([&] { write_points_ply(p, disp.view(), small.view(), cam, true); }, &code);
  EXPECT_EQ(code, ErrorCode::kSizeMismatch);
  message_of([&] { write_depth(write("d.jpg", ""), Image<float>(2, 2, 1).view()); }, &code);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
}

TEST_F(Calib, PointCloudRefusesPointsBeyondFloat) {
  const Image<std::int16_t> disp(5, 4, 1, 32);
  const ImageU8 left(5, 4, 3, 100);
  CameraParams huge{1e30, 1e30, 2.0, 1.5, 0.0};  // Z = 1e60 / 2: finite in double, not in float
  const std::string p = (dir_ / "huge.ply").string();
  ErrorCode code{};
  const std::string m = message_of([&] { write_points_ply(p, disp.view(), left.view(), huge, true); }, &code);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(m.find("beyond float range"), std::string::npos) << m;
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(fs::is_empty(dir_)) << "a temporary was left behind";
}


// ---- Depth limits: what the metric outputs keep.

TEST(DepthLimits, KeepExactlyWhatTheyState) {
  CameraParams cam{};
  cam.focal_px = 100;
  cam.baseline = 0.1;  // f B = 10 m px
  cam.doffs = 1;       // effective disparity d + 1
  // d (px) -> d + doffs, Z = 10 / (d + 1)
  const std::int16_t d_q4[] = {kInvalidDispQ4, -16, 0, 8, 16, 17, 16 * 4, 16 * 9, 16 * 19};
  const auto run = [&](const DepthLimits& l, std::int64_t* removed) {
    std::vector<std::int16_t> v(std::begin(d_q4), std::end(d_q4));
    *removed = apply_depth_limits({v.data(), static_cast<int>(v.size()), 1, 1,
                                   static_cast<std::ptrdiff_t>(v.size() * 2)},
                                  cam, l);
    return v;
  };
  std::int64_t removed = 0;
  // Default: d + doffs >= 2 px (d >= 1), no depth limit. -1 px gives d + doffs = 0: no depth.
  std::vector<std::int16_t> kept = run(DepthLimits{}, &removed);
  const std::vector<std::int16_t> want_default = {kInvalidDispQ4, kInvalidDispQ4, kInvalidDispQ4, kInvalidDispQ4,
                                                  16, 17, 64, 144, 304};
  EXPECT_EQ(kept, want_default);
  EXPECT_EQ(removed, 3);  // the invalid input is not counted
  // 0: every d + doffs > 0 (the 0.5 px disparity too).
  DepthLimits all;
  all.min_disparity_px = 0;
  kept = run(all, &removed);
  EXPECT_EQ(kept[2], 0);
  EXPECT_EQ(kept[3], 8);
  EXPECT_EQ(kept[1], kInvalidDispQ4);
  EXPECT_EQ(removed, 1);
  // Z in [1, 2] m: d + 1 in [5, 10] px: d = 4 (Z = 2) and d = 9 (Z = 1) kept, both edges inclusive.
  DepthLimits band;
  band.min_depth_m = 1;
  band.max_depth_m = 2;
  kept = run(band, &removed);
  const std::vector<std::int16_t> want_band = {kInvalidDispQ4, kInvalidDispQ4, kInvalidDispQ4, kInvalidDispQ4,
                                               kInvalidDispQ4, kInvalidDispQ4, 64, 144, kInvalidDispQ4};
  EXPECT_EQ(kept, want_band);
  EXPECT_EQ(removed, 6);
}

TEST(DepthLimits, BadValuesAreRefusedNamingTheField) {
  const auto msg = [](const DepthLimits& l) { return message_of([&] { check_depth_limits(l); }); };
  DepthLimits l;
  l.min_disparity_px = -1;
  EXPECT_NE(msg(l).find("min_disparity_px"), std::string::npos);
  l = DepthLimits{};
  l.min_depth_m = std::numeric_limits<double>::infinity();
  EXPECT_NE(msg(l).find("min_depth_m"), std::string::npos);
  l = DepthLimits{};
  l.min_depth_m = 3;
  l.max_depth_m = 2;
  EXPECT_NE(msg(l).find("max_depth_m must be above min_depth_m"), std::string::npos);
  l.max_depth_m = 0;  // no upper limit
  EXPECT_NO_THROW(check_depth_limits(l));
}

// On the scenes with a calibration (ETH3D, Middlebury 2014; KITTI 000000 with
// its devkit calibration above), the default limits leave out the far field
// the matcher invents: before them depths reach hundreds of metres where the
// scenes end within tens; after, no depth lies beyond f B / 2, and most of the
// pixels left out that have ground truth were wrong by more than 2 px.
TEST_F(Calib, DefaultDepthLimitsLeaveOutTheFarFieldOnRealScenes) {
  TRISTEREO_REQUIRE_DATA("eth3d");
  TRISTEREO_REQUIRE_DATA("middlebury2014");
  TRISTEREO_REQUIRE_DATA("kitti2015");
  std::vector<std::pair<test::DataScene, CameraParams>> scenes;
  for (const test::DataScene& s : test::load_data_set("eth3d"))
    scenes.emplace_back(s, read_calibration(s.dir + "/calib.txt").camera());
  for (const test::DataScene& s : test::load_data_set("middlebury2014"))
    scenes.emplace_back(s, read_calibration(s.dir + "/calib.txt").camera());
  const CameraParams kitti = read_calibration(write("kitti.txt", kKittiText)).camera();
  for (const test::DataScene& s : test::load_data_set("kitti2015"))
    if (s.name == "000000") scenes.emplace_back(s, kitti);
  ASSERT_GE(scenes.size(), 3u);
  for (const auto& [scene, cam] : scenes) {
    SCOPED_TRACE(scene.set + "/" + scene.name);
    PipelineConfig config;
    config.max_width = scene.left.width;
    config.max_height = scene.left.height;
    config.params.num_disp = scene.ndisp;
    config.threads = 2;
    Pipeline pipeline;
    pipeline.configure(config);
    const StereoOutput& out = pipeline.process(scene.left.view(), scene.right.view());
    ImageS16 limited = out.disp_q4;
    const std::int64_t removed = apply_depth_limits(limited.view(), cam, DepthLimits{});
    const Image<float> z_all = depth_m_from_disp_q4(out.disp_q4.view(), cam);
    const Image<float> z = depth_m_from_disp_q4(limited.view(), cam);
    const double far_limit = cam.focal_px * cam.baseline / 2.0;
    double z_all_max = 0, z_max = 0;
    // Relative depth errors against the ground truth's depth, of the pixels
    // the limits leave out and of those they keep.
    std::vector<double> err_out, err_kept;
    for (int y = 0; y < z.height; ++y)
      for (int x = 0; x < z.width; ++x) {
        if (std::isfinite(z_all.at(x, y))) z_all_max = std::max(z_all_max, double{z_all.at(x, y)});
        if (std::isfinite(z.at(x, y))) z_max = std::max(z_max, double{z.at(x, y)});
        const float g = scene.gt.at(x, y);
        if (out.disp_q4.at(x, y) == kInvalidDispQ4 || !std::isfinite(g) || !(g + cam.doffs > 0)) continue;
        const double z_gt = cam.focal_px * cam.baseline / (g + cam.doffs);
        const double z_d = std::isfinite(z_all.at(x, y)) ? z_all.at(x, y) : 1e9;
        (limited.at(x, y) == kInvalidDispQ4 ? err_out : err_kept).push_back(std::fabs(z_d - z_gt) / z_gt);
      }
    const auto median = [](std::vector<double> v) {
      if (v.empty()) return 0.0;
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    EXPECT_LE(z_max, far_limit * (1 + 1e-6));
    std::printf("%s/%s: f B / 2 = %.1f m; depth max %.1f m before the limits, %.1f m after; %lld pixels left "
                "out; median relative depth error with ground truth: %zu left out %.3f, %zu kept %.4f\n",
                scene.set.c_str(), scene.name.c_str(), far_limit, z_all_max, z_max,
                static_cast<long long>(removed), err_out.size(), median(err_out), err_kept.size(),
                median(err_kept));
    if (err_out.size() >= 100) {
      EXPECT_GT(median(err_out), 10 * median(err_kept));
    }
  }
}

}  // namespace
}  // namespace tristereo
