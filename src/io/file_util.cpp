#include "src/io/file_util.hpp"

#include <cctype>
#include <charconv>
#include <cerrno>
#include <cstring>
#include <memory>

#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace io_detail {

namespace {

std::string os_error(const std::string& what, const std::string& path, int err) {
  return what + " '" + path + "': " + std::strerror(err);
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

std::vector<std::uint8_t> read_file_bytes(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f) throw Error(ErrorCode::kIoError, os_error("cannot open", path, errno));
  std::vector<std::uint8_t> bytes;
  // Read in chunks rather than trusting a size from seek: works for pipes and
  // reports EISDIR for directories as a read error.
  constexpr std::size_t kChunk = 1 << 16;
  // Enough for the largest image the readers accept plus any header.
  constexpr std::size_t kMaxFileBytes = (std::size_t{1} << 28) * 4 * 3 + (1 << 20);
  for (;;) {
    const std::size_t old = bytes.size();
    if (old > kMaxFileBytes) {
      throw Error(ErrorCode::kUnsupportedFormat,
                  "'" + path + "' is larger than " + std::to_string(kMaxFileBytes) + " bytes");
    }
    bytes.resize(old + kChunk);
    const std::size_t got = std::fread(bytes.data() + old, 1, kChunk, f.get());
    bytes.resize(old + got);
    if (got < kChunk) {
      if (std::ferror(f.get())) throw Error(ErrorCode::kIoError, os_error("cannot read", path, errno));
      break;
    }
  }
  return bytes;
}

void check_read_size(std::int64_t width, std::int64_t height, const std::string& what) {
  if (width < 1 || height < 1) {
    throw Error(ErrorCode::kCorruptFile, what + ": image size " + std::to_string(width) + " x " +
                                             std::to_string(height) + " is empty");
  }
  if (width > kMaxReadSide || height > kMaxReadSide) {
    throw Error(ErrorCode::kUnsupportedFormat,
                what + ": image size " + std::to_string(width) + " x " + std::to_string(height) +
                    " exceeds the reader limit of " + std::to_string(kMaxReadSide) +
                    " pixels per side");
  }
  if (width * height > kMaxReadPixels) {
    throw Error(ErrorCode::kUnsupportedFormat,
                what + ": image size " + std::to_string(width) + " x " + std::to_string(height) +
                    " exceeds the reader limit of " + std::to_string(kMaxReadPixels) + " pixels");
  }
}

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void append_float_le(std::string& out, float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  for (int i = 0; i < 4; ++i) out += static_cast<char>((u >> (8 * i)) & 0xff);
}

void append_float_text(std::string& out, float f) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), f);
  out.append(buf, r.ptr);
}

OutputFile::OutputFile(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw Error(ErrorCode::kIoError, os_error("cannot create", path, errno));
}

OutputFile::~OutputFile() {
  if (file_) {
    std::fclose(file_);
    std::remove(path_.c_str());
  }
}

void OutputFile::write(const void* data, std::size_t n) {
  if (n == 0) return;
  if (std::fwrite(data, 1, n, file_) != n) {
    throw Error(ErrorCode::kIoError, os_error("cannot write", path_, errno));
  }
}

void OutputFile::commit() {
  std::FILE* f = file_;
  file_ = nullptr;
  const bool flushed = std::fflush(f) == 0 && !std::ferror(f);
  const int err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!flushed || !closed) {
    std::remove(path_.c_str());
    throw Error(ErrorCode::kIoError, os_error("cannot write", path_, flushed ? errno : err));
  }
}

[[noreturn]] void throw_view_error(const char* what, const std::string& detail) {
  throw Error(ErrorCode::kInvalidArgument, std::string(what) + ": " + detail);
}

}  // namespace io_detail
}  // namespace tristereo
