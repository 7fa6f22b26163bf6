// PFM (portable float map), Middlebury convention.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "src/io/file_util.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

using namespace io_detail;

namespace {

bool is_space(std::uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// One whitespace-separated header token (PFM headers have no comments).
std::string next_token(const std::vector<std::uint8_t>& b, std::size_t& pos) {
  while (pos < b.size() && is_space(b[pos])) ++pos;
  std::string tok;
  while (pos < b.size() && !is_space(b[pos]) && tok.size() < 64) tok += static_cast<char>(b[pos++]);
  return tok;
}

[[noreturn]] void corrupt(const std::string& path, const std::string& why) {
  throw Error(ErrorCode::kCorruptFile, "corrupt PFM '" + path + "': " + why);
}

std::int64_t parse_dim(const std::string& tok, const std::string& path, const char* field) {
  if (tok.empty() || tok.size() > 12 || tok.find_first_not_of("0123456789") != std::string::npos) {
    corrupt(path, std::string("bad ") + field + " '" + tok + "'");
  }
  return std::stoll(tok);
}

void check_pfm_head(const std::vector<std::uint8_t>& b, const std::string& path) {
  if (b.size() < 2 || b[0] != 'P' || (b[1] != 'f' && b[1] != 'F')) {
    throw Error(ErrorCode::kUnsupportedFormat, "'" + path + "' is not a PFM file (no Pf/PF magic)");
  }
}

}  // namespace

void write_pfm(const std::string& path, ImageView<const float> img) {
  check_write_view(img, 1, 3, "write_pfm");
  const std::string header = std::string(img.channels == 3 ? "PF" : "Pf") + "\n" +
                             std::to_string(img.width) + " " + std::to_string(img.height) +
                             "\n-1\n";
  const std::size_t n = static_cast<std::size_t>(img.width) * img.channels;
  std::vector<std::uint8_t> row(n * 4);
  const bool swap = !host_is_little_endian();
  OutputFile f(path);
  f.write(header);
  for (int y = img.height - 1; y >= 0; --y) {  // bottom row first
    std::memcpy(row.data(), img.row(y), row.size());
    if (swap) {
      for (std::size_t i = 0; i < row.size(); i += 4) {
        std::swap(row[i], row[i + 3]);
        std::swap(row[i + 1], row[i + 2]);
      }
    }
    f.write(row.data(), row.size());
  }
  f.commit();
}

static Image<float> read_pfm_unguarded(const std::string& path);

// std::bad_alloc never leaves a reader (file_util.hpp).
Image<float> read_pfm(const std::string& path) {
  return guard_memory(path, [&] { return read_pfm_unguarded(path); });
}

Image<float> read_pfm_unguarded(const std::string& path) {
  const std::vector<std::uint8_t> b = read_file_bytes(path, check_pfm_head);
  const int channels = b[1] == 'F' ? 3 : 1;
  std::size_t pos = 2;
  if (pos >= b.size() || !is_space(b[pos])) corrupt(path, "missing whitespace after the magic");
  const std::int64_t w = parse_dim(next_token(b, pos), path, "width");
  const std::int64_t h = parse_dim(next_token(b, pos), path, "height");
  const std::string scale_tok = next_token(b, pos);
  char* end = nullptr;
  // strtod is locale-dependent in theory; PFM scales are plain "-1"/"1.0" which
  // every C locale parses alike.
  const double scale = std::strtod(scale_tok.c_str(), &end);
  if (scale_tok.empty() || *end != '\0' || !std::isfinite(scale) || scale == 0.0) {
    corrupt(path, "bad scale '" + scale_tok + "' (must be a non-zero number)");
  }
  if (pos >= b.size() || !is_space(b[pos])) corrupt(path, "missing whitespace after the header");
  ++pos;
  check_read_size(w, h, "PFM '" + path + "'");
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * channels;
  if (b.size() - pos < n * 4) {
    corrupt(path, "truncated: " + std::to_string(w) + " x " + std::to_string(h) + " x " +
                      std::to_string(channels) + " floats need " + std::to_string(n * 4) +
                      " bytes, file has " + std::to_string(b.size() - pos));
  }
  const bool file_le = scale < 0;
  const bool swap = file_le != host_is_little_endian();
  Image<float> img(static_cast<int>(w), static_cast<int>(h), channels);
  const std::size_t row_bytes = static_cast<std::size_t>(w) * channels * 4;
  std::vector<std::uint8_t> row(row_bytes);
  for (int y = 0; y < img.height; ++y) {
    // Row y of the file is image row h - 1 - y.
    std::memcpy(row.data(), b.data() + pos + row_bytes * y, row_bytes);
    if (swap) {
      for (std::size_t i = 0; i < row_bytes; i += 4) {
        std::swap(row[i], row[i + 3]);
        std::swap(row[i + 1], row[i + 2]);
      }
    }
    std::memcpy(img.row(img.height - 1 - y), row.data(), row_bytes);
  }
  return img;
}

}  // namespace tristereo
