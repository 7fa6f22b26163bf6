// Raw rigs: the four calibration formats, their conventions checked on the
// two unrectified sets of ../shared/data, the rectification against the one
// OpenCV computed there, and bad files.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/data.hpp"
#include "support/json_numbers.hpp"
#include "tristereo/rig.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

std::string set_file(const std::string& set, const std::string& name) {
  return test::data_set_dir(set) + "/" + name;
}

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = std::string(TRISTEREO_BINARY_DIR) + "/rig-test-" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

double max_diff(const double* a, const double* b, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

struct Computed {
  const char* set;
  const char* file;
  DistortionModel model;
};

class RigRectification : public ::testing::TestWithParam<Computed> {};

// The rectification computed from M1 D1 M2 D2 R T against stereoRectify's own
// (alpha 0, CALIB_ZERO_DISPARITY) stored beside them. Measured: f within
// 2.7e-5 px, cx and cy within 1.1e-5 px (OpenCV keeps the corners of its
// principal-point step in float), R1 and R2 within 1e-15.
TEST_P(RigRectification, EqualsOpenCvStereoRectify) {
  const Computed c = GetParam();
  TRISTEREO_REQUIRE_DATA(c.set);
  const StereoRig rig = read_rig(set_file(c.set, c.file));
  EXPECT_EQ(rig.format, RigFormat::kOpenCv);
  EXPECT_EQ(rig.left.model, c.model);
  ASSERT_TRUE(rig.has_rectification);
  const Rectification mine = compute_rectification(rig);
  EXPECT_FALSE(mine.from_file);
  EXPECT_LT(max_diff(mine.R1.data(), rig.R1.data(), 9), 1e-12);
  EXPECT_LT(max_diff(mine.R2.data(), rig.R2.data(), 9), 1e-12);
  EXPECT_NEAR(mine.P1[0], rig.P1[0], 5e-5);
  EXPECT_NEAR(mine.P1[2], rig.P1[2], 3e-5);
  EXPECT_NEAR(mine.P1[6], rig.P1[6], 3e-5);
  EXPECT_NEAR(mine.P2[2], rig.P2[2], 3e-5);
  EXPECT_NEAR(mine.P2[3] / rig.P2[3], 1.0, 1e-6);
  std::printf("%s: f %.6f (OpenCV %.6f), cx %.6f (%.6f), cy %.6f (%.6f), P2(0,3) %.6f (%.6f)\n", c.set, mine.P1[0],
              rig.P1[0], mine.P1[2], rig.P1[2], mine.P1[6], rig.P1[6], mine.P2[3], rig.P2[3]);
  const Rectification given = rectify_rig(rig);
  EXPECT_TRUE(given.from_file);
  EXPECT_EQ(given.P1, rig.P1);
  const StereoCalibration cal = given.calibration();
  EXPECT_DOUBLE_EQ(cal.focal_px, rig.P1[0]);
  EXPECT_NEAR(cal.baseline_m, std::sqrt(rig.T[0] * rig.T[0] + rig.T[1] * rig.T[1] + rig.T[2] * rig.T[2]), 1e-9);
  EXPECT_EQ(cal.doffs_px, 0);
}

INSTANTIATE_TEST_SUITE_P(Sets, RigRectification,
                         ::testing::Values(Computed{"opencv-stereo-calib", "calib_opencv.yml", DistortionModel::kRational},
                                           Computed{"opencv-stereo-calib", "plumb_bob/calib_opencv.yml",
                                                    DistortionModel::kRadTan},
                                           Computed{"euroc-v101", "calib_opencv.yml", DistortionModel::kRadTan}));

// raw_position() against initUndistortRectifyMap's CV_32FC1 maps at the
// 16 x 16 grid of maps_grid.json: measured 3.1e-5 px (float32 rounding).
TEST(Rig, RawPositionEqualsOpenCvMaps) {
  TRISTEREO_REQUIRE_DATA("opencv-stereo-calib");
  for (const char* sub : {"", "plumb_bob/"}) {
    const std::string dir = test::data_set_dir("opencv-stereo-calib") + "/" + sub;
    const StereoRig rig = read_rig(dir + "calib_opencv.yml");
    const Rectification rect = rectify_rig(rig);
    const std::string json = test::read_text_file(dir + "maps_grid.json");
    const std::vector<double> xs = test::json_numbers_after(json, {"x"});
    const std::vector<double> ys = test::json_numbers_after(json, {"y"});
    ASSERT_EQ(xs.size(), 16u);
    double worst = 0;
    for (int cam = 0; cam < 2; ++cam) {
      const char* name = cam == 0 ? "left" : "right";
      const std::vector<double> mx = test::json_numbers_after(json, {name, "map_x"});
      const std::vector<double> my = test::json_numbers_after(json, {name, "map_y"});
      ASSERT_EQ(mx.size(), 256u);
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
          double x, y;
          raw_position(rig, rect, cam, xs[i], ys[j], &x, &y);
          worst = std::max({worst, std::fabs(x - mx[16 * j + i]), std::fabs(y - my[16 * j + i])});
        }
    }
    std::printf("%s maps: max |difference| %.3g px\n", sub, worst);
    EXPECT_LT(worst, 1e-4);
  }
}

// The chessboard corners of every raw pair, rectified: the same corner on
// the same row. README of each set: OpenCV gets a mean |dy| of 0.215 px
// (median 0.159) on the book's rig and 0.060 px on EuRoC; our computed
// rectification measures the same (to 1e-4 px), and our rectified corners
// equal the sets' (OpenCV's undistortPointsIter) to 1e-3 px on EuRoC.
TEST(Rig, RectifiedCornersShareTheirRow) {
  for (const char* set : {"opencv-stereo-calib", "euroc-v101"}) {
    TRISTEREO_REQUIRE_DATA(set);
    const StereoRig rig = read_rig(set_file(set, "calib_opencv.yml"));
    const Rectification rect = compute_rectification(rig);
    const Rectification given = rectify_rig(rig);
    const std::string json = test::read_text_file(set_file(set, "corners.json"));
    std::vector<double> dys;
    double worst_vs_opencv = 0;
    std::size_t pos = json.find("\"pairs\"");
    // opencv-stereo-calib's rectified corners follow the pairs, under "rectified".
    const std::size_t stop = std::min(json.find("\"rectified\"", pos), json.size());
    for (;;) {
      std::size_t at = json.find("\"pair\"", pos);
      if (at == std::string::npos || at > stop) break;
      std::size_t end = 0;
      const std::vector<double> l = test::json_numbers_after(json, {"left"}, at, &end);
      const std::vector<double> r = test::json_numbers_after(json, {"right"}, end, &end);
      ASSERT_EQ(l.size(), r.size());
      for (std::size_t i = 0; i + 1 < l.size(); i += 2) {
        double ul, vl, ur, vr;
        rectified_position(rig, rect, 0, l[i], l[i + 1], &ul, &vl);
        rectified_position(rig, rect, 1, r[i], r[i + 1], &ur, &vr);
        dys.push_back(std::fabs(vl - vr));
      }
      if (std::string(set) == "euroc-v101") {
        const std::vector<double> lr = test::json_numbers_after(json, {"left_rectified"}, at);
        ASSERT_EQ(lr.size(), l.size());
        for (std::size_t i = 0; i + 1 < l.size(); i += 2) {
          double u, v;
          rectified_position(rig, given, 0, l[i], l[i + 1], &u, &v);
          worst_vs_opencv = std::max({worst_vs_opencv, std::fabs(u - lr[i]), std::fabs(v - lr[i + 1])});
        }
      }
      pos = end;
    }
    ASSERT_GT(dys.size(), 300u) << set;
    double mean = 0;
    for (double d : dys) mean += d / dys.size();
    std::sort(dys.begin(), dys.end());
    const double median = dys[dys.size() / 2];
    std::printf("%s: %zu corners, mean |dy| %.4f px, median %.4f px; vs OpenCV's rectified corners %.2g px\n", set,
                dys.size(), mean, median, worst_vs_opencv);
    if (std::string(set) == "euroc-v101") {
      EXPECT_LT(mean, 0.1);
      EXPECT_LT(worst_vs_opencv, 1e-3);
    } else {
      EXPECT_LT(mean, 0.3);
      EXPECT_LT(median, 0.25);
    }
  }
}

// EuRoC's two sensor.yaml: [R | T] = inv(T_BS1) T_BS0, the README's check:
// T = (-0.110074, 0.000399, -0.000854) m, |T| = 0.110078 m along -x, and the
// same R and T as the set's calib_opencv.yml.
TEST(Rig, EurocSensorPairGivesTheBaselineAlongX) {
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  const StereoRig rig = read_rig(set_file("euroc-v101", "cam0_sensor.yaml"), set_file("euroc-v101", "cam1_sensor.yaml"));
  EXPECT_EQ(rig.format, RigFormat::kEuroc);
  EXPECT_FALSE(rig.has_rectification);
  EXPECT_NEAR(rig.T[0], -0.110074, 1e-6);
  EXPECT_NEAR(rig.T[1], 0.000399, 1e-6);
  EXPECT_NEAR(rig.T[2], -0.000854, 1e-6);
  EXPECT_NEAR(std::sqrt(rig.T[0] * rig.T[0] + rig.T[1] * rig.T[1] + rig.T[2] * rig.T[2]), 0.110078, 1e-6);
  EXPECT_EQ(rig.left.width, 752);
  EXPECT_DOUBLE_EQ(rig.left.K[0], 458.654);
  EXPECT_DOUBLE_EQ(rig.right.dist[1], 0.07451284);
  const StereoRig cv = read_rig(set_file("euroc-v101", "calib_opencv.yml"));
  EXPECT_LT(max_diff(rig.R.data(), cv.R.data(), 9), 1e-12);
  EXPECT_LT(max_diff(rig.T.data(), cv.T.data(), 3), 1e-12);
  const StereoCalibration cal = rectify_rig(rig).calibration();
  EXPECT_NEAR(cal.focal_px, 436.2346, 1e-3);  // README: depth = 48.02 / d metres
  EXPECT_NEAR(cal.focal_px * cal.baseline_m, 48.0198, 1e-3);
}

// The ROS camera_info pairs hold the same calibration as calib_opencv.yml:
// the rig's pose comes back from R1, R2 and P2 to 1e-9.
TEST(Rig, RosCameraInfoPairs) {
  for (const char* sub : {"opencv-stereo-calib/", "opencv-stereo-calib/plumb_bob/", "euroc-v101/"}) {
    const std::string set = std::string(sub).substr(0, std::string(sub).find('/'));
    TRISTEREO_REQUIRE_DATA(set);
    const std::string dir = test::data_root() + "/" + sub;
    const StereoRig ros = read_rig(dir + "left.yaml", dir + "right.yaml");
    const StereoRig cv = read_rig(dir + "calib_opencv.yml");
    EXPECT_EQ(ros.format, RigFormat::kRosCameraInfo);
    EXPECT_EQ(ros.left.model, cv.left.model) << sub;
    EXPECT_LT(max_diff(ros.left.K.data(), cv.left.K.data(), 9), 1e-9);
    EXPECT_LT(max_diff(ros.right.dist.data(), cv.right.dist.data(), 8), 1e-12);
    EXPECT_LT(max_diff(ros.R.data(), cv.R.data(), 9), 1e-9) << sub;
    EXPECT_LT(max_diff(ros.T.data(), cv.T.data(), 3), 1e-9) << sub;
    EXPECT_EQ(ros.P2, cv.P2);
    EXPECT_EQ(ros.right_path, dir + "right.yaml");
  }
}

// A Kalibr camchain of the EuRoC rig (T_cn_cnm1 = inv(T_BS1) T_BS0, as
// third-party EuRoC camchains write it) reads as the two sensor.yaml do.
TEST(Rig, KalibrCamchain) {
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  const StereoRig euroc =
      read_rig(set_file("euroc-v101", "cam0_sensor.yaml"), set_file("euroc-v101", "cam1_sensor.yaml"));
  char rows[4][200];
  for (int i = 0; i < 3; ++i)
    std::snprintf(rows[i], sizeof rows[i], "  - [%.17g, %.17g, %.17g, %.17g]\n", euroc.R[3 * i], euroc.R[3 * i + 1],
                  euroc.R[3 * i + 2], euroc.T[i]);
  std::snprintf(rows[3], sizeof rows[3], "  - [0.0, 0.0, 0.0, 1.0]\n");
  const std::string text =
      "cam0:\n  camera_model: pinhole\n  intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
      "  distortion_model: radtan\n  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n"
      "  resolution: [752, 480]\n  rostopic: /cam0/image_raw\n  cam_overlaps: [1]\n"
      "cam1:\n  T_cn_cnm1:\n" + std::string(rows[0]) + rows[1] + rows[2] + rows[3] +
      "  camera_model: pinhole  # Kalibr writes comments too\n  intrinsics: [457.587, 456.134, 379.999, 255.238]\n"
      "  distortion_model: radtan\n  distortion_coeffs: [-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05]\n"
      "  resolution: [752, 480]\n";
  const StereoRig k = read_rig(temp_file("camchain.yaml", text));
  EXPECT_EQ(k.format, RigFormat::kKalibr);
  EXPECT_LT(max_diff(k.R.data(), euroc.R.data(), 9), 1e-15);
  EXPECT_LT(max_diff(k.T.data(), euroc.T.data(), 3), 1e-15);
  EXPECT_EQ(k.left.K, euroc.left.K);
  EXPECT_EQ(k.right.dist, euroc.right.dist);

  // Equidistant (fisheye) cameras are read and rectified too.
  std::string fisheye = text;
  for (std::size_t p; (p = fisheye.find("radtan")) != std::string::npos;) fisheye.replace(p, 6, "equidistant");
  const StereoRig f = read_rig(temp_file("camchain-fisheye.yaml", fisheye));
  EXPECT_EQ(f.left.model, DistortionModel::kEquidistant);
  const Rectification r = rectify_rig(f);
  double x, y;
  raw_position(f, r, 0, r.P1[2], r.P1[6], &x, &y);
  EXPECT_TRUE(std::isfinite(x) && std::isfinite(y));
  double u, v;
  rectified_position(f, r, 0, x, y, &u, &v);
  EXPECT_NEAR(u, r.P1[2], 1e-9);
  EXPECT_NEAR(v, r.P1[6], 1e-9);
}

// The deterministic atan and tan of the equidistant model against libm.
TEST(Rig, DistortionRoundTripsEveryModel) {
  TRISTEREO_REQUIRE_DATA("euroc-v101");
  StereoRig rig = read_rig(set_file("euroc-v101", "cam0_sensor.yaml"), set_file("euroc-v101", "cam1_sensor.yaml"));
  for (DistortionModel m : {DistortionModel::kRadTan, DistortionModel::kRational, DistortionModel::kEquidistant}) {
    rig.left.model = rig.right.model = m;
    if (m == DistortionModel::kRational) rig.left.dist[7] = rig.right.dist[7] = -0.05;
    if (m == DistortionModel::kEquidistant) rig.left.dist = rig.right.dist = {-0.01, 0.002, -0.001, 0.0003};
    const Rectification r = compute_rectification(rig);
    double worst = 0;
    for (int cam = 0; cam < 2; ++cam)
      for (double v = 0; v < 480; v += 37)
        for (double u = 0; u < 752; u += 41) {
          double x, y, u2, v2;
          raw_position(rig, r, cam, u, v, &x, &y);
          rectified_position(rig, r, cam, x, y, &u2, &v2);
          worst = std::max({worst, std::fabs(u2 - u), std::fabs(v2 - v)});
        }
    EXPECT_LT(worst, 1e-6) << to_string(m);
  }
}

struct BadRig {
  const char* name;
  std::string text;
  std::string second;  // "" = a one-file format
  std::vector<std::string> expect;  // substrings of the message
};

std::string opencv_rig(const std::string& replace_key = "", const std::string& with = "") {
  std::string t =
      "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
      "M1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n"
      "D1: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ -0.1, 0.01, 0., 0., 0. ]\n"
      "M2: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n"
      "D2: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ -0.1, 0.01, 0., 0., 0. ]\n"
      "R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\n"
      "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ -0.1, 0., 0. ]\n";
  if (!replace_key.empty()) {
    const std::size_t at = t.find(replace_key);
    t.replace(at, t.find('\n', t.find("data", at)) - at, with);
  }
  return t;
}

TEST(Rig, BadFilesNameFileLineAndKey) {
  const std::string ros_left =
      "image_width: 640\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [500, 0, 320, 0, 500, 240, "
      "0, 0, 1]\ndistortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, "
      "0]\nrectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nprojection_matrix:\n  "
      "rows: 3\n  cols: 4\n  data: [500, 0, 320, 0, 0, 500, 240, 0, 0, 0, 1, 0]\n";
  std::string ros_unknown_model = ros_left;
  ros_unknown_model.replace(ros_unknown_model.find("plumb_bob"), 9, "kannala_brandt");
  std::string ros_bad_p = ros_left;
  ros_bad_p.replace(ros_bad_p.find("rows: 3\n  cols: 4"), 17, "rows: 3\n  cols: 3");
  const std::vector<BadRig> cases = {
      {"missing-T", opencv_rig("T:", ""), "", {"rig-test-missing-T", "key 'T'", "missing"}},
      {"rotation",
       opencv_rig("R:", "R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0.5, 0., 0., 1., 0., 0., 0., 1. ]"),
       "",
       {"line 25", "key 'R'", "is not a rotation"}},
      {"zero-baseline", opencv_rig("T:", "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ 0., 0., 0. ]"),
       "",
       {"line 30", "key 'T'", "baseline |T| = 0 m is outside"}},
      {"d-count", opencv_rig("D2:", "D2: !!opencv-matrix\n   rows: 1\n   cols: 6\n   dt: d\n   data: [ 0, 0, 0, 0, 0, 0 ]"),
       "",
       {"line 20", "key 'D2'", "got 6"}},
      {"thin-prism",
       opencv_rig("D1:", "D1: !!opencv-matrix\n   rows: 1\n   cols: 12\n   dt: d\n   data: [ 0, 0, 0, 0, 0, 0, 0, 0, 0.1, 0, 0, 0 ]"),
       "",
       {"key 'D1'", "thin-prism"}},
      {"focal",
       opencv_rig("M2:", "M2: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1e300, 0., 320., 0., 500., 240., 0., 0., 1. ]"),
       "",
       {"line 15", "key 'M2'", "focal length 1e+300 px is outside"}},
      {"not-a-number",
       opencv_rig("M1:", "M1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., abc, 0., 500., 240., 0., 0., 1. ]"),
       "",
       {"line 5", "key 'M1'", "'abc' is not a finite number"}},
      {"ros-alone", ros_left, "", {"ROS camera_info", "the right camera's file is needed"}},
      {"ros-model", ros_left, ros_unknown_model, {"rig-test-ros-model-right", "line 7", "key 'distortion_model'",
                                                   "'kannala_brandt' is not supported"}},
      {"ros-shape", ros_left, ros_bad_p, {"line 16", "key 'projection_matrix'", "expected 3x4, the file says 3x3"}},
      {"unknown", "hello: 1\n", "", {"not a raw stereo rig"}},
      {"euroc-bad", "%YAML:1.0\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0,\n   0, 1, 0, 0, 0, 0, 1, 0]\n"
                    "intrinsics: [458.654, 457.296, 367.215, 248.375]\ndistortion_model: radial-tangential\n"
                    "distortion_coefficients: [0, 0, 0, 0]\nresolution: [752, 480]\n",
       "same", {"line 5", "key 'T_BS/data'", "expected 16 numbers, got 12"}},
      {"kalibr-bad", "cam0:\n  camera_model: omni\n  intrinsics: [1, 2, 3, 4]\ncam1:\n  intrinsics: [1]\n", "",
       {"line 2", "key 'cam0/camera_model'", "'omni' is not supported"}},
      {"yaml-unclosed", "cam0:\n  intrinsics: [1, 2,\ncam1: x\n", "", {"line 2", "no closing ']'"}},
  };
  for (const BadRig& c : cases) {
    const std::string left = temp_file(std::string(c.name) + (c.second.empty() ? "" : "-left"), c.text);
    std::string right;
    if (c.second == "same") right = temp_file(std::string(c.name) + "-right", c.text);
    else if (!c.second.empty()) right = temp_file(std::string(c.name) + "-right", c.second);
    try {
      read_rig(left, right);
      ADD_FAILURE() << c.name << ": no error";
    } catch (const Error& e) {
      for (const std::string& s : c.expect)
        EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << c.name << ": '" << e.what() << "' lacks '" << s << "'";
    }
  }
}

// Inputs the rectification refuses: swapped cameras, a vertical rig.
TEST(Rig, RectificationRefusesSwappedAndVerticalRigs) {
  const std::string swapped =
      opencv_rig("T:", "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ 0.1, 0., 0. ]");
  const StereoRig a = read_rig(temp_file("swapped.yml", swapped));
  EXPECT_THROW(
      {
        try {
          compute_rectification(a);
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("left and right swapped?"), std::string::npos) << e.what();
          throw;
        }
      },
      Error);
  const std::string vertical =
      opencv_rig("T:", "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ 0., -0.1, 0. ]");
  EXPECT_THROW(compute_rectification(read_rig(temp_file("vertical.yml", vertical))), Error);
  const StereoRig ok = read_rig(temp_file("ok.yml", opencv_rig()));
  const Rectification r = compute_rectification(ok);
  EXPECT_NEAR(r.calibration().baseline_m, 0.1, 1e-12);
}

}  // namespace
}  // namespace tristereo
