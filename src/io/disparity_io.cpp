// Disparity map files (PFM, 16-bit PNG) and the colour visualisation.
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "src/io/file_util.hpp"
#include "src/io/png_codec.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

using namespace io_detail;

Image<float> disp_q4_to_float(ImageView<const std::int16_t> disp_q4) {
  check_write_view(disp_q4, 1, 1, "disp_q4_to_float");
  Image<float> out(disp_q4.width, disp_q4.height, 1);
  for (int y = 0; y < disp_q4.height; ++y) {
    const std::int16_t* in = disp_q4.row(y);
    float* o = out.row(y);
    for (int x = 0; x < disp_q4.width; ++x) {
      // value / 16 is exact in float for every int16.
      o[x] = in[x] == kInvalidDispQ4 ? std::numeric_limits<float>::infinity()
                                     : static_cast<float>(in[x]) / static_cast<float>(kDispOne);
    }
  }
  return out;
}

void write_disparity(const std::string& path, ImageView<const std::int16_t> disp_q4,
                     DispPngScale png_scale) {
  check_write_view(disp_q4, 1, 1, "write_disparity");
  const std::string ext = lower_extension(path);
  if (ext == ".pfm") {
    const Image<float> f = disp_q4_to_float(disp_q4);
    write_pfm(path, f.view());
    return;
  }
  if (ext != ".png") {
    throw Error(ErrorCode::kInvalidArgument,
                "write_disparity: extension '" + ext + "' of '" + path +
                    "' is not supported (use .pfm or .png)");
  }
  Image<std::uint16_t> u(disp_q4.width, disp_q4.height, 1);
  for (int y = 0; y < disp_q4.height; ++y) {
    const std::int16_t* in = disp_q4.row(y);
    for (int x = 0; x < disp_q4.width; ++x) {
      if (in[x] == kInvalidDispQ4) {
        u.at(x, y) = 0;
      } else if (in[x] < 0) {
        throw Error(ErrorCode::kInvalidArgument,
                    "write_disparity: negative disparity " + std::to_string(in[x]) +
                        " (Q4) at (" + std::to_string(x) + ", " + std::to_string(y) +
                        ") cannot be stored in a 16-bit PNG (minimum 0); use .pfm");
      } else if (png_scale == DispPngScale::kKitti) {
        // value = 256 d = 16 * Q4: exact, and at most 65535 below 256 px.
        const std::int32_t v = std::int32_t{in[x]} * 16;
        if (v > 65535) {
          throw Error(ErrorCode::kInvalidArgument,
                      "write_disparity: disparity " + std::to_string(in[x] / 16.0) + " px at (" +
                          std::to_string(x) + ", " + std::to_string(y) +
                          ") does not fit a KITTI PNG (value = 256 d, at most 65535); use .pfm");
        }
        u.at(x, y) = static_cast<std::uint16_t>(v);
      } else {
        u.at(x, y) = static_cast<std::uint16_t>(in[x]);
      }
    }
  }
  write_png_u16(path, std::as_const(u).view());
}

Image<std::int16_t> read_disparity(const std::string& path, DispPngScale png_scale) {
  const std::vector<std::uint8_t> head = read_file_head(path, 8);
  Image<std::int16_t> out;
  if (is_png(head)) {
    const Image<std::uint16_t> u = read_png_u16(path);
    out = Image<std::int16_t>(u.width, u.height, 1);
    for (std::size_t i = 0; i < u.pixels.size(); ++i) {
      const std::uint16_t v = u.pixels[i];
      if (v == 0) {
        out.pixels[i] = kInvalidDispQ4;
      } else if (png_scale == DispPngScale::kKitti) {
        out.pixels[i] = static_cast<std::int16_t>((v + 8) / 16);  // 256 d -> 16 d, half up
      } else if (v > 32767) {
        throw Error(ErrorCode::kCorruptFile,
                    "disparity PNG '" + path + "' holds " + std::to_string(v) +
                        ", above the Q4 maximum 32767 (a KITTI PNG? read it as value / 256)");
      } else {
        out.pixels[i] = static_cast<std::int16_t>(v);
      }
    }
    return out;
  }
  const Image<float> f = read_pfm(path);
  if (f.channels != 1) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "disparity PFM '" + path + "' has 3 channels; expected 1 (Pf)");
  }
  out = Image<std::int16_t>(f.width, f.height, 1);
  for (std::size_t i = 0; i < f.pixels.size(); ++i) {
    const float d = f.pixels[i];
    if (!std::isfinite(d)) {
      out.pixels[i] = kInvalidDispQ4;
      continue;
    }
    const double q = std::round(static_cast<double>(d) * kDispOne);
    if (q <= INT16_MIN || q > INT16_MAX) {
      throw Error(ErrorCode::kCorruptFile, "disparity PFM '" + path + "' holds " +
                                               std::to_string(d) +
                                               " px, outside the Q4 int16 range");
    }
    out.pixels[i] = static_cast<std::int16_t>(q);
  }
  return out;
}

void disparity_color(int t_q10, std::uint8_t rgb[3]) {
  // Five stops at t = 0, 1/4, 1/2, 3/4, 1. BT.601 luma at the stops is
  // 23, 66, 109, 168, 239, and linear in between.
  static const std::uint8_t kStops[5][3] = {
      {16, 16, 80}, {100, 30, 160}, {210, 60, 90}, {250, 150, 40}, {252, 245, 170}};
  if (t_q10 < 0) t_q10 = 0;
  if (t_q10 > 1024) t_q10 = 1024;
  const int seg = t_q10 >= 1024 ? 3 : t_q10 >> 8;
  const int f = t_q10 - (seg << 8);  // 0..256 inside the segment
  for (int c = 0; c < 3; ++c) {
    const int a = kStops[seg][c], b = kStops[seg + 1][c];
    rgb[c] = static_cast<std::uint8_t>((a * (256 - f) + b * f + 128) >> 8);
  }
}

void write_disparity_color(const std::string& path, ImageView<const std::int16_t> disp_q4,
                           int d_min, int num_disp) {
  check_write_view(disp_q4, 1, 1, "write_disparity_color");
  if (num_disp < 1 || num_disp > 4096) {
    throw Error(ErrorCode::kInvalidArgument, "write_disparity_color: num_disp " +
                                                 std::to_string(num_disp) +
                                                 " is outside 1..4096");
  }
  if (d_min < -4096 || d_min > 4096) {
    throw Error(ErrorCode::kInvalidArgument,
                "write_disparity_color: d_min " + std::to_string(d_min) + " is outside -4096..4096");
  }
  const std::int64_t lo = static_cast<std::int64_t>(d_min) * kDispOne;
  const std::int64_t span = static_cast<std::int64_t>(num_disp - 1) * kDispOne;
  ImageU8 rgb(disp_q4.width, disp_q4.height, 3);
  for (int y = 0; y < disp_q4.height; ++y) {
    const std::int16_t* in = disp_q4.row(y);
    std::uint8_t* out = rgb.row(y);
    for (int x = 0; x < disp_q4.width; ++x) {
      if (in[x] == kInvalidDispQ4) {
        out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = 0;
        continue;
      }
      std::int64_t t = 1024;
      if (span > 0) t = floor_div((in[x] - lo) * 1024, span);
      disparity_color(static_cast<int>(t < 0 ? 0 : (t > 1024 ? 1024 : t)), out + 3 * x);
    }
  }
  write_png_u8(path, std::as_const(rgb).view());
}

}  // namespace tristereo
