#include "src/io/file_util.hpp"

#include <cctype>
#include <charconv>
#include <cerrno>
#include <cstring>
#include <atomic>
#include <climits>
#include <algorithm>
#include <memory>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

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

InputFile::InputFile(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) throw Error(ErrorCode::kIoError, os_error("cannot open", path, errno));
  struct stat st {};
  if (::fstat(::fileno(file_), &st) != 0) {
    const int err = errno;
    std::fclose(file_);
    throw Error(ErrorCode::kIoError, os_error("cannot read", path, err));
  }
  std::string refusal;
  ErrorCode code = ErrorCode::kIoError;
  if (S_ISDIR(st.st_mode)) {
    refusal = "cannot read '" + path + "': it is a directory";
  } else if (S_ISREG(st.st_mode) && static_cast<std::uint64_t>(st.st_size) > kMaxReadFileBytes) {
    code = ErrorCode::kUnsupportedFormat;
    refusal = "'" + path + "' is " + std::to_string(st.st_size) + " bytes, larger than the reader limit of " +
              std::to_string(kMaxReadFileBytes) + " bytes";
  }
  if (!refusal.empty()) {
    std::fclose(file_);
    throw Error(code, refusal);
  }
  regular_ = S_ISREG(st.st_mode);
  size_ = regular_ ? static_cast<std::uint64_t>(st.st_size) : 0;
}

InputFile::~InputFile() { std::fclose(file_); }

std::size_t InputFile::read(std::vector<std::uint8_t>& out, std::size_t n) {
  const std::size_t old = out.size();
  out.resize(old + n);
  const std::size_t got = std::fread(out.data() + old, 1, n, file_);
  out.resize(old + got);
  position_ += got;
  if (got < n && std::ferror(file_)) throw Error(ErrorCode::kIoError, os_error("cannot read", path_, errno));
  return got;
}

bool InputFile::skip(std::uint64_t n) {
  if (regular_) {
    // A seek past the end succeeds silently; the size says whether the bytes
    // are there (a file that shrank since fstat shows up as a short read later).
    if (n > size_ - std::min(size_, position_)) return false;
    if (::fseeko(file_, static_cast<off_t>(n), SEEK_CUR) != 0)
      throw Error(ErrorCode::kIoError, os_error("cannot read", path_, errno));
    position_ += n;
    return true;
  }
  // A stream cannot seek: read through it in small pieces, kept nowhere.
  std::uint8_t buffer[4096];
  while (n > 0) {
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(n, sizeof buffer));
    const std::size_t got = std::fread(buffer, 1, want, file_);
    position_ += got;
    n -= got;
    if (got < want) {
      if (std::ferror(file_)) throw Error(ErrorCode::kIoError, os_error("cannot read", path_, errno));
      return false;
    }
  }
  return true;
}

std::vector<std::uint8_t> InputFile::read_rest(std::vector<std::uint8_t> bytes, HeadCheck check_head) {
  // The first chunk alone decides whether this is a format the caller reads:
  // a stream such as /dev/zero or a large file of another kind costs one chunk.
  constexpr std::size_t kChunk = std::size_t{1} << 16;
  bool head_checked = false;
  for (;;) {
    if (head_checked && bytes.size() >= kMaxReadFileBytes) {
      throw Error(ErrorCode::kUnsupportedFormat,
                  "'" + path_ + "' is larger than the reader limit of " + std::to_string(kMaxReadFileBytes) + " bytes");
    }
    if (head_checked && regular_ && bytes.capacity() < size_ + kChunk) {
      // The size is known and bounded: one allocation, with room for the last
      // (short) chunk's read and for a file that grew since fstat.
      bytes.reserve(static_cast<std::size_t>(size_) + kChunk);
    }
    // The first read tops up to one chunk, counting what the caller already read.
    const std::size_t want = head_checked ? kChunk : kChunk - std::min(kChunk, bytes.size());
    const bool at_end = read(bytes, want) < want;
    if (!head_checked) {
      if (bytes.empty()) throw Error(ErrorCode::kCorruptFile, "'" + path_ + "' is empty");
      if (check_head) check_head(bytes, path_);
      head_checked = true;
    }
    if (at_end) break;
  }
  return bytes;
}

std::vector<std::uint8_t> read_file_bytes(const std::string& path, HeadCheck check_head) {
  InputFile f(path);
  return f.read_rest({}, check_head);
}

std::vector<std::uint8_t> read_file_head(const std::string& path, std::size_t n) {
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f) throw Error(ErrorCode::kIoError, os_error("cannot open", path, errno));
  std::vector<std::uint8_t> head(n);
  head.resize(std::fread(head.data(), 1, n, f.get()));
  if (std::ferror(f.get())) throw Error(ErrorCode::kIoError, os_error("cannot read", path, errno));
  return head;
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

namespace {

// The folder a path lives in ("." for a bare name), and its last component.
std::string parent_dir(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string base_name(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

OutputFile::OutputFile(const std::string& path) : path_(path) {
  struct stat st {};
  const bool exists = ::stat(path.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) {
    throw Error(ErrorCode::kIoError, "cannot create '" + path + "': it is a directory");
  }
  if (exists && !S_ISREG(st.st_mode)) {
    // A device or a FIFO (/dev/null, /dev/stdout, a named pipe): written in
    // place. Renaming a file over it would replace the node itself, and as
    // root that destroys e.g. /dev/full; it is never removed either.
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) throw Error(ErrorCode::kIoError, os_error("cannot open", path, errno));
    return;
  }
  // A symbolic link to a file: the file it names is replaced, the link kept.
  struct stat lst {};
  if (exists && ::lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
    char target[PATH_MAX];
    if (::realpath(path.c_str(), target)) target_ = target;
  }
  if (target_.empty()) target_ = path;
  // A regular file, or none yet: a hidden temporary in the same folder (the
  // rename must not cross file systems), renamed over the path by commit().
  // Created with mode 0666 like fopen, so the umask applies as usual; a file
  // it replaces keeps its mode.
  const std::string dir = parent_dir(target_);
  static std::atomic<unsigned> counter{0};
  int fd = -1;
  std::string temp;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp = dir + "/." + base_name(target_) + ".tmp-" + std::to_string(::getpid()) + "-" +
           std::to_string(counter.fetch_add(1));
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    const int err = errno;
    throw Error(ErrorCode::kIoError,
                "cannot create '" + path + "': " + std::strerror(err) + " (in folder '" + dir + "')");
  }
  if (exists) ::fchmod(fd, st.st_mode & 07777);  // best effort: the default mode otherwise
  file_ = ::fdopen(fd, "wb");
  if (!file_) {
    const int err = errno;
    ::close(fd);
    ::unlink(temp.c_str());
    throw Error(ErrorCode::kIoError, os_error("cannot create", path, err));
  }
  temp_path_ = temp;
}

OutputFile::~OutputFile() {
  // Not committed: discard what was written. Only our own temporary is ever
  // removed; whatever was at path_ before stays untouched.
  if (file_) std::fclose(file_);
  if (!temp_path_.empty()) ::unlink(temp_path_.c_str());
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
  int err = 0;
  if (std::fflush(f) != 0 || std::ferror(f)) err = errno ? errno : EIO;
  // The data must be on disk before the rename makes it visible under the
  // final name, or a crash could leave an empty file there.
  if (err == 0 && !temp_path_.empty() && ::fsync(::fileno(f)) != 0) err = errno;
  if (std::fclose(f) != 0 && err == 0) err = errno ? errno : EIO;
  if (err == 0 && !temp_path_.empty() && std::rename(temp_path_.c_str(), target_.c_str()) != 0) {
    err = errno;
  }
  if (err != 0) throw Error(ErrorCode::kIoError, os_error("cannot write", path_, err));
  temp_path_.clear();  // renamed: nothing left to remove
}

[[noreturn]] void throw_out_of_memory(const std::string& path) {
  throw Error(ErrorCode::kPlatform, "cannot read '" + path +
                                        "': not enough memory for it (the process's memory limit, or the machine's)");
}

[[noreturn]] void throw_view_error(const char* what, const std::string& detail) {
  throw Error(ErrorCode::kInvalidArgument, std::string(what) + ": " + detail);
}

}  // namespace io_detail
void write_text_file(const std::string& path, const std::string& contents) {
  io_detail::OutputFile f(path);
  f.write(contents);
  f.commit();
}

}  // namespace tristereo
