// Disparity maps and ground truths as float pixels, whichever encoding they
// come in (PFM, 8-bit PNG / scale, 16-bit PNG / 16 or / 256).
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "tristereo/eval.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

// What the first bytes say: PFM, or a PNG with its IHDR bit depth and colour type.
struct FileHead {
  bool empty = false, pfm = false, png = false;
  int png_bit_depth = 0, png_color_type = 0;
};

FileHead read_head(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error(ErrorCode::kIoError, "'" + path + "' is a directory, not a disparity file");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorCode::kIoError, "cannot open '" + path + "'");
  unsigned char b[26] = {};
  f.read(reinterpret_cast<char*>(b), sizeof b);
  const std::streamsize n = f.gcount();
  FileHead h;
  h.empty = n <= 0;
  if (n >= 2 && b[0] == 'P' && (b[1] == 'f' || b[1] == 'F')) h.pfm = true;
  static const unsigned char kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n >= 8 && std::memcmp(b, kPngMagic, 8) == 0) {
    h.png = true;
    if (n >= 26) {  // IHDR: length, type, width, height, then bit depth and colour type
      h.png_bit_depth = b[24];
      h.png_color_type = b[25];
    }
  }
  return h;
}

std::string what_it_holds(const FileHead& h) {
  if (h.empty) return "empty";
  if (h.pfm) return "a PFM file";
  if (h.png) {
    return std::to_string(h.png_bit_depth) + "-bit " +
           (h.png_color_type == 0 ? std::string("gray") : std::string("colour")) + " PNG";
  }
  return "neither PFM nor PNG";
}

[[noreturn]] void wrong_format(const std::string& path, DispFileFormat want, const FileHead& h) {
  throw Error(ErrorCode::kUnsupportedFormat, "'" + path + "' is " + what_it_holds(h) +
                                                 ", not a " + to_string(want) + " disparity file");
}

}  // namespace

const char* to_string(DispFileFormat f) {
  switch (f) {
    case DispFileFormat::kPfm: return "pfm";
    case DispFileFormat::kPng8: return "png8";
    case DispFileFormat::kQ4: return "q4";
    case DispFileFormat::kKitti: return "kitti";
  }
  return "?";
}

bool parse_disp_file_format(const std::string& name, DispFileFormat* out) {
  for (DispFileFormat f : {DispFileFormat::kPfm, DispFileFormat::kPng8, DispFileFormat::kQ4,
                           DispFileFormat::kKitti}) {
    if (name == to_string(f)) {
      *out = f;
      return true;
    }
  }
  return false;
}

DispFileFormat detect_disp_file_format(const std::string& path, DispFileFormat png16) {
  const FileHead h = read_head(path);
  if (h.pfm) return DispFileFormat::kPfm;
  if (h.png && h.png_bit_depth == 16) return png16;
  if (h.png && h.png_bit_depth > 0) return DispFileFormat::kPng8;
  throw Error(ErrorCode::kUnsupportedFormat,
              "'" + path + "' is " + what_it_holds(h) + ": expected a PFM or PNG disparity file");
}

Image<float> read_disparity_px(const std::string& path, DispFileFormat format, int png8_scale) {
  if (format == DispFileFormat::kPng8 && (png8_scale < 1 || png8_scale > 255)) {
    throw Error(ErrorCode::kInvalidArgument,
                "8-bit disparity scale " + std::to_string(png8_scale) + " is outside 1..255");
  }
  const FileHead h = read_head(path);
  constexpr float kNone = std::numeric_limits<float>::infinity();
  if (format == DispFileFormat::kPfm) {
    if (!h.pfm) wrong_format(path, format, h);
    Image<float> img = read_pfm(path);
    if (img.channels != 1) {
      throw Error(ErrorCode::kUnsupportedFormat,
                  "'" + path + "' is a colour PFM (PF); a disparity map has one channel (Pf)");
    }
    for (float& v : img.pixels)
      if (!std::isfinite(v)) v = kNone;  // NaN and -inf mean "none" too
    return img;
  }
  if (format == DispFileFormat::kPng8) {
    if (!h.png || h.png_bit_depth > 8 || h.png_color_type != 0) wrong_format(path, format, h);
    const ImageU8 raw = read_image_u8(path);
    Image<float> img(raw.width, raw.height, 1);
    for (std::size_t i = 0; i < raw.pixels.size(); ++i)
      img.pixels[i] = static_cast<float>(raw.pixels[i]) / static_cast<float>(png8_scale);
    return img;
  }
  if (!h.png || h.png_bit_depth != 16 || h.png_color_type != 0) wrong_format(path, format, h);
  const Image<std::uint16_t> raw = read_png_u16(path);
  const float scale = format == DispFileFormat::kKitti ? 256.f : 16.f;
  Image<float> img(raw.width, raw.height, 1);
  for (std::size_t i = 0; i < raw.pixels.size(); ++i)
    img.pixels[i] = raw.pixels[i] == 0 ? kNone : static_cast<float>(raw.pixels[i]) / scale;
  return img;
}

Image<float> load_middlebury_gt(const std::string& png_path, int gt_scale) {
  return read_disparity_px(png_path, DispFileFormat::kPng8, gt_scale);
}

}  // namespace tristereo
