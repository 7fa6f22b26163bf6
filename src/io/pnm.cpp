// Netpbm PGM/PPM: binary (P5/P6) and ASCII (P2/P3), maxval 255 only.
#include "src/io/pnm.hpp"

#include <cstring>
#include <string>

#include "src/io/file_util.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace io_detail {

namespace {

bool is_space(std::uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

class HeaderParser {
 public:
  HeaderParser(const std::vector<std::uint8_t>& bytes, const std::string& path)
      : b_(bytes), path_(path) {}

  // Skips whitespace and '#' comments, then reads a decimal number. Values
  // beyond 10^12 are clamped there: they are rejected by the size checks anyway.
  std::int64_t number(const char* field) {
    skip_space_and_comments();
    if (pos_ >= b_.size()) fail(std::string("file ends before the ") + field);
    if (b_[pos_] < '0' || b_[pos_] > '9') {
      fail(std::string("expected a number for the ") + field + ", found byte " +
           std::to_string(b_[pos_]));
    }
    std::int64_t v = 0;
    while (pos_ < b_.size() && b_[pos_] >= '0' && b_[pos_] <= '9') {
      if (v < 1000000000000LL) v = v * 10 + (b_[pos_] - '0');
      ++pos_;
    }
    return v;
  }

  // After the last header field of a binary file: exactly one whitespace byte.
  void single_space() {
    if (pos_ >= b_.size() || !is_space(b_[pos_])) fail("missing whitespace after the header");
    ++pos_;
  }

  std::size_t pos() const { return pos_; }
  void set_pos(std::size_t p) { pos_ = p; }

  [[noreturn]] void fail(const std::string& why) const {
    throw Error(ErrorCode::kCorruptFile, "corrupt PNM '" + path_ + "': " + why);
  }

 private:
  void skip_space_and_comments() {
    while (pos_ < b_.size()) {
      if (is_space(b_[pos_])) {
        ++pos_;
      } else if (b_[pos_] == '#') {
        while (pos_ < b_.size() && b_[pos_] != '\n' && b_[pos_] != '\r') ++pos_;
      } else {
        break;
      }
    }
  }

  const std::vector<std::uint8_t>& b_;
  const std::string& path_;
  std::size_t pos_ = 2;  // after the magic
};

}  // namespace

bool is_pnm(const std::vector<std::uint8_t>& bytes) {
  return bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '7';
}

ImageU8 decode_pnm(const std::vector<std::uint8_t>& bytes, const std::string& path) {
  const char kind = static_cast<char>(bytes[1]);
  if (kind != '2' && kind != '3' && kind != '5' && kind != '6') {
    throw Error(ErrorCode::kUnsupportedFormat,
                std::string("PNM '") + path + "' is type P" + kind +
                    "; only P2/P5 (gray) and P3/P6 (RGB) are read");
  }
  const bool ascii = kind == '2' || kind == '3';
  const int channels = (kind == '3' || kind == '6') ? 3 : 1;
  HeaderParser p(bytes, path);
  const std::int64_t w = p.number("width");
  const std::int64_t h = p.number("height");
  const std::int64_t maxval = p.number("maxval");
  check_read_size(w, h, "PNM '" + path + "'");
  if (maxval < 1 || maxval > 65535) p.fail("maxval " + std::to_string(maxval) + " is outside 1..65535");
  if (maxval != 255) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "PNM '" + path + "' has maxval " + std::to_string(maxval) +
                    "; only maxval 255 (8-bit) is read");
  }
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * channels;
  if (!ascii) {
    p.single_space();
    const std::size_t have = bytes.size() - p.pos();
    if (have < n) {
      p.fail("truncated: header promises " + std::to_string(n) + " bytes of pixels, file has " +
             std::to_string(have));
    }
    ImageU8 img(static_cast<int>(w), static_cast<int>(h), channels);
    std::memcpy(img.pixels.data(), bytes.data() + p.pos(), n);
    return img;
  }
  // Each ASCII sample takes at least one digit plus a separator: reject a short
  // file before allocating for a size it cannot hold.
  if (bytes.size() - p.pos() < 2 * n - 1) {
    p.fail("truncated: header promises " + std::to_string(n) + " samples, file has only " +
           std::to_string(bytes.size() - p.pos()) + " bytes left");
  }
  ImageU8 img(static_cast<int>(w), static_cast<int>(h), channels);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t v = p.number("pixel values");
    if (v > maxval) p.fail("sample " + std::to_string(v) + " exceeds maxval " + std::to_string(maxval));
    img.pixels[i] = static_cast<std::uint8_t>(v);
  }
  return img;
}

void encode_pnm(const std::string& path, ImageView<const std::uint8_t> img, int channels) {
  const std::string header = std::string(channels == 3 ? "P6" : "P5") + "\n" +
                             std::to_string(img.width) + " " + std::to_string(img.height) +
                             "\n255\n";
  OutputFile f(path);
  f.write(header);
  for (int y = 0; y < img.height; ++y) {
    f.write(img.row(y), static_cast<std::size_t>(img.width) * channels);
  }
  f.commit();
}

}  // namespace io_detail
}  // namespace tristereo
