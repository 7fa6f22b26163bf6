// Private helpers shared by the file readers and writers in src/io/.
#pragma once

#include <cstdint>
#include <cstdio>
#include <new>
#include <string>
#include <vector>

#include "tristereo/image.hpp"

namespace tristereo {
namespace io_detail {

// Throws (kUnsupportedFormat naming what the file starts with) unless the
// first bytes of a file are a format the caller reads.
using HeadCheck = void (*)(const std::vector<std::uint8_t>& head, const std::string& path);

// Whole file in memory, read in chunks so that memory follows what the file
// really holds: kIoError if it cannot be opened or read (missing, a
// directory), kCorruptFile if empty, kUnsupportedFormat if larger than
// kMaxReadFileBytes (a regular file's size is checked before reading). After
// the first chunk (64 KiB, or the whole file if shorter) `check_head` sees it,
// so a device like /dev/zero or a huge file of another kind costs one chunk.
// Readers parse from memory so that "header claims more data than the file
// holds" is a size comparison, not a short read halfway through a decoder.
std::vector<std::uint8_t> read_file_head(const std::string& path, std::size_t n);
std::vector<std::uint8_t> read_file_bytes(const std::string& path, HeadCheck check_head);

// A file opened for reading with read_file_bytes' checks done (kIoError if it
// cannot be opened or is a directory, kUnsupportedFormat if a regular file is
// larger than kMaxReadFileBytes). For readers that look at the first bytes
// before deciding how to read the rest (a PNG's chunks are walked, not slurped).
class InputFile {
 public:
  explicit InputFile(const std::string& path);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  const std::string& path() const { return path_; }
  bool regular() const { return regular_; }
  std::uint64_t size() const { return size_; }  // of a regular file, else 0
  std::uint64_t position() const { return position_; }
  // Up to n more bytes appended to `out`; fewer only at the end of the file.
  // kIoError on a read error.
  std::size_t read(std::vector<std::uint8_t>& out, std::size_t n);
  // Moves n bytes forward without keeping them: a seek on a regular file, a
  // bounded read into a small buffer on a stream. Returns false if the file
  // ends first.
  bool skip(std::uint64_t n);
  // read_file_bytes from here: the rest of the file appended to `bytes`
  // (which holds what was read so far), check_head run on the first chunk.
  std::vector<std::uint8_t> read_rest(std::vector<std::uint8_t> bytes, HeadCheck check_head);

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  bool regular_ = false;
  std::uint64_t size_ = 0;
  std::uint64_t position_ = 0;
};

[[noreturn]] void throw_out_of_memory(const std::string& path);

// Runs a public reader's body: std::bad_alloc (a valid file too large for the
// memory this process may use) becomes kPlatform naming the file, so callers
// see a tristereo::Error like for every other bad input.
template <typename Fn>
auto guard_memory(const std::string& path, Fn&& fn) -> decltype(fn()) {
  try {
    return fn();
  } catch (const std::bad_alloc&) {
    throw_out_of_memory(path);
  }
}

// kUnsupportedFormat when width/height/pixels exceed the reader limits,
// kCorruptFile when a side is < 1. `what` prefixes the message.
void check_read_size(std::int64_t width, std::int64_t height, const std::string& what);

// PLY payload helpers: a float as 4 little-endian bytes; the shortest text
// that reads back to the same float, independent of the locale.
void append_float_le(std::string& out, float f);
void append_float_text(std::string& out, float f);

// Lower-case extension including the dot ("" when none).
std::string lower_extension(const std::string& path);

// A file being written atomically: the bytes go to a hidden temporary in the
// same folder, and commit() flushes, syncs, closes and renames it over the
// path, checking each step (kIoError naming the path and the OS reason). If
// anything fails, or commit() is never reached, the temporary is removed and
// whatever was at the path before is left as it was. An existing device or
// FIFO (/dev/null, /dev/full, a pipe) is written in place instead, and never
// removed. A symbolic link at the path keeps pointing at the file it names,
// which is the one replaced. A directory at the path is kIoError.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path);  // kIoError if it cannot be created
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::FILE* get() const { return file_; }
  void write(const void* data, std::size_t n);  // kIoError on a short write
  void write(const std::string& s) { write(s.data(), s.size()); }
  void commit();                                // flush + close, kIoError on failure

 private:
  std::string path_;
  std::string target_;     // path_, or the file a symbolic link at path_ names
  std::string temp_path_;  // empty when writing in place
  std::FILE* file_ = nullptr;
};

// Throws kInvalidArgument unless the view is non-null, non-empty, has
// `channels` in the allowed set and a stride covering a row.
template <typename T>
void check_write_view(const ImageView<T>& v, int channels_a, int channels_b, const char* what);

[[noreturn]] void throw_view_error(const char* what, const std::string& detail);

template <typename T>
void check_write_view(const ImageView<T>& v, int channels_a, int channels_b, const char* what) {
  if (v.data == nullptr) throw_view_error(what, "null data");
  if (v.width < 1 || v.height < 1) {
    throw_view_error(what, "size " + std::to_string(v.width) + " x " + std::to_string(v.height) +
                               " is empty");
  }
  if (v.width > 0x7fffffff / 8 || v.height > 0x7fffffff / 8) {
    throw_view_error(what, "size " + std::to_string(v.width) + " x " + std::to_string(v.height) +
                               " is too large");
  }
  if (v.channels != channels_a && v.channels != channels_b) {
    throw_view_error(what, std::to_string(v.channels) + " channels, expected " +
                               std::to_string(channels_a) +
                               (channels_b != channels_a ? " or " + std::to_string(channels_b)
                                                         : std::string()));
  }
  const std::ptrdiff_t row_bytes =
      static_cast<std::ptrdiff_t>(v.width) * v.channels * static_cast<std::ptrdiff_t>(sizeof(T));
  if (v.stride_bytes < row_bytes) {
    throw_view_error(what, "stride_bytes " + std::to_string(v.stride_bytes) +
                               " is shorter than a row (" + std::to_string(row_bytes) + ")");
  }
}

inline bool host_is_little_endian() {
  const std::uint16_t one = 1;
  std::uint8_t b;
  static_assert(sizeof(one) == 2, "");
  __builtin_memcpy(&b, &one, 1);
  return b == 1;
}

}  // namespace io_detail
}  // namespace tristereo
