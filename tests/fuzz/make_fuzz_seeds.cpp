// Writes the seed corpora of the fuzz harnesses (tests/fuzz/corpus/<harness>/)
// with the project's own writers, so the seeds are files tristereo itself
// produces. The committed corpus is this program's output:
//
//   build/tests/fuzz/make_fuzz_seeds tests/fuzz/corpus
//
// Images are tiny (a few hundred bytes each): libFuzzer mutates small inputs
// fastest, and the whole corpus stays far below 1 MiB.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/synth.hpp"

using namespace tristereo;
namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

// A deterministic textured image (no dependence on the synthetic scene's
// minimum size of 16 px).
ImageU8 pattern(int w, int h, int channels, int seed) {
  ImageU8 img(w, h, channels);
  std::uint32_t s = 2463534242u + static_cast<std::uint32_t>(seed);
  for (auto& v : img.pixels) {
    s ^= s << 13;
    s ^= s >> 17;
    s ^= s << 5;
    v = static_cast<std::uint8_t>(s);
  }
  return img;
}

void image_seeds(const fs::path& png, const fs::path& pnm) {
  const ImageU8 gray = pattern(7, 5, 1, 1), rgb = pattern(5, 4, 3, 2), one = pattern(1, 1, 1, 3);
  write_png_u8((png / "gray_7x5.png").string(), gray.view());
  write_png_u8((png / "rgb_5x4.png").string(), rgb.view());
  write_png_u8((png / "gray_1x1.png").string(), one.view());
  Image<std::uint16_t> g16(6, 3, 1);
  for (std::size_t i = 0; i < g16.pixels.size(); ++i) g16.pixels[i] = static_cast<std::uint16_t>(i * 4099);
  write_png_u16((png / "gray16_6x3.png").string(), g16.view());
  SynthParams sp;
  sp.width = 16;
  sp.height = 16;
  sp.num_disp = 8;
  write_png_u8((png / "synthetic_16x16.png").string(), make_synthetic_scene(sp).left.view());

  write_pgm((pnm / "gray_7x5.pgm").string(), gray.view());
  write_ppm((pnm / "rgb_5x4.ppm").string(), rgb.view());
  // The ASCII kinds the reader accepts (P2/P3), as the PNM specification writes them.
  write_text(pnm / "ascii_3x2.pgm", "P2\n# a comment\n3 2\n255\n0 128 255\n7 8 9\n");
  write_text(pnm / "ascii_2x1.ppm", "P3\n2 1\n255\n255 0 0  0 255 0\n");
}

void disparity_seeds(const fs::path& pfm, const fs::path& disp_png) {
  ImageS16 q4(6, 4, 1);
  for (std::size_t i = 0; i < q4.pixels.size(); ++i) q4.pixels[i] = static_cast<std::int16_t>(i * 37 + 16);
  q4.pixels[3] = kInvalidDispQ4;
  write_disparity((disp_png / "q4_6x4.png").string(), q4.view(), DispPngScale::kQ4);
  write_disparity((disp_png / "kitti_6x4.png").string(), q4.view(), DispPngScale::kKitti);
  write_disparity((pfm / "disp_6x4.pfm").string(), q4.view());
  ImageF32 rgb(3, 2, 3);
  for (std::size_t i = 0; i < rgb.pixels.size(); ++i) rgb.pixels[i] = 0.25f * static_cast<float>(i) - 1.0f;
  write_pfm((pfm / "rgb_3x2.pfm").string(), rgb.view());
  // A big-endian file (positive scale), which write_pfm never writes but read_pfm reads.
  std::string be = "Pf\n2 1\n1.0\n";
  for (float f : {1.5f, 2.0f}) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    for (int k = 3; k >= 0; --k) be += static_cast<char>((u >> (8 * k)) & 0xff);
  }
  write_text(pfm / "big_endian_2x1.pfm", be);
}

// The first byte of a calibration seed picks the format (0 = auto) and the
// OpenCV unit (bit 2: millimetres); see fuzz_calib.cpp.
void calib_seeds(const fs::path& dir) {
  write_text(dir / "middlebury.txt",
             std::string(1, '\0') +
                 "cam0=[1038.018 0 322.037; 0 1038.018 243.393; 0 0 1]\n"
                 "cam1=[1038.018 0 375.308; 0 1038.018 243.393; 0 0 1]\n"
                 "doffs=53.271\nbaseline=176.252\nwidth=718\nheight=496\nndisp=290\n");
  write_text(dir / "kitti.txt",
             std::string(1, '\0') +
                 "P0: 721.5377 0 609.5593 0 0 721.5377 172.854 0 0 0 1 0\n"
                 "P1: 721.5377 0 609.5593 -387.5744 0 721.5377 172.854 0 0 0 1 0\n"
                 "P2: 721.5377 0 609.5593 44.85728 0 721.5377 172.854 0.2163791 0 0 1 0.002745884\n"
                 "P3: 721.5377 0 609.5593 -339.5242 0 721.5377 172.854 2.199936 0 0 1 0.002729905\n");
  write_text(dir / "opencv.yml",
             std::string(1, '\4') +
                 "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                 "P1: !!opencv-matrix\n   rows: 3\n   cols: 4\n   dt: d\n"
                 "   data: [ 700., 0., 320., 0., 0., 700., 240., 0., 0., 0., 1., 0. ]\n"
                 "P2: !!opencv-matrix\n   rows: 3\n   cols: 4\n   dt: d\n"
                 "   data: [ 700., 0., 331.5, -84000., 0., 700., 240., 0., 0., 0., 1., 0. ]\n");
  write_text(dir / "opencv_q.yml",
             std::string(1, '\3') +
                 "%YAML:1.0\n---\nQ: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n"
                 "   data: [ 1., 0., 0., -320., 0., 1., 0., -240., 0., 0., 0., 700., 0., 0.,\n"
                 "       8.3333333333333332e-03, 9.5833333333333326e-02 ]\n");
  write_text(dir / "opencv.xml",
             std::string(1, '\4') +
                 "<?xml version=\"1.0\"?>\n<opencv_storage>\n<imageSize>\n  640 480</imageSize>\n"
                 "<P1 type_id=\"opencv-matrix\">\n  <rows>3</rows>\n  <cols>4</cols>\n  <dt>d</dt>\n"
                 "  <data>\n    700. 0. 320. 0. 0. 700. 240. 0. 0. 0. 1. 0.</data></P1>\n"
                 "<P2 type_id=\"opencv-matrix\">\n  <rows>3</rows>\n  <cols>4</cols>\n  <dt>d</dt>\n"
                 "  <data>\n    700. 0. 331.5 -84000. 0. 700. 240. 0. 0. 0. 1. 0.</data></P2>\n"
                 "</opencv_storage>\n");
}

// One argument per line; the names are the fixtures fuzz_cli.cpp creates.
void cli_seeds(const fs::path& dir) {
  const char* seeds[][2] = {
      {"match", "match\nleft.png\nright.png\n--ndisp\n8\n--disp\nd.pfm\n--mesh\nm.ply\n--stats\ns.json"},
      {"match_calib", "match\nleft.png\nright.png\n--ndisp\n8\n--calib\ncalib.txt\n--depth\nz.png\n--points\np.ply"},
      {"match_dense", "match\nleft.pgm\nright.png\n--ndisp\n8\n--dense\n--window\n3x5\n--weights\nadaptive\n--disp\nd.png\n--disp-format\nkitti"},
      {"match_samples", "match\nleft.png\nright.png\n--ndisp=8\n--dmin\n-2\n--samples\ns.csv\n--disp-color\nc.png\n--threads\n2"},
      {"verify", "verify\nleft.png\nright.png\n--ndisp\n8\n--thread-counts\n1,2"},
      {"eval", "eval\ndisp_left.pfm\ndisp_left.pfm\n--mask\nnonocc.png"},
      {"eval_kitti", "eval\ndisp_kitti.png\ndisp_left.pfm\n--disp-format\nkitti\n--json\ne.json"},
      {"synth", "synth\nout\n--width\n16\n--height\n16\n--ndisp\n8\n--seed\n4"},
      {"demo", "demo\nd\n--width\n32\n--height\n24\n--ndisp\n8\n--threads\n1"},
      {"profile", "profile\n--width\n32\n--height\n24\n--ndisp\n8\n--frames\n2\n--warmup\n1\n--json\np.json\n--csv\np.csv"},
      {"profile_pair", "profile\n--left\nleft.png\n--right\nright.png\n--frames\n1\n--mesh-output\n--quiet"},
      {"info", "info"},
      {"help", "match\n--help"},
  };
  for (const auto& s : seeds) write_text(dir / (std::string(s[0]) + ".args"), s[1]);
}

// Byte strings for fuzz_pipeline.cpp (which draws sizes, parameters and
// pixels from them in order); from a fixed generator, one per length.
void pipeline_seeds(const fs::path& dir) {
  std::uint32_t s = 12345;
  for (int len : {16, 48, 96, 200, 400, 800}) {
    std::string bytes;
    for (int i = 0; i < len; ++i) {
      s = s * 1103515245u + 12345u;
      bytes += static_cast<char>(s >> 23);
    }
    write_text(dir / ("random_" + std::to_string(len) + ".bin"), bytes);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR   (writes CORPUS_DIR/<harness>/...)\n", argv[0]);
    return 2;
  }
  const fs::path root = argv[1];
  for (const char* h : {"png", "pnm", "pfm", "disp_png", "calib", "cli", "pipeline"})
    fs::create_directories(root / h);
  image_seeds(root / "png", root / "pnm");
  disparity_seeds(root / "pfm", root / "disp_png");
  calib_seeds(root / "calib");
  cli_seeds(root / "cli");
  pipeline_seeds(root / "pipeline");
  std::printf("seed corpora written to %s\n", root.string().c_str());
  return 0;
}
