// Outputs written atomically and readers bounded by what a file holds
// (include/tristereo/io.hpp): a failed write never touches what was at the
// path, a hostile header never buys memory its file cannot fill.
#include <gtest/gtest.h>
#include <png.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

namespace fs = std::filesystem;

ErrorCode code_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.code();
  }
  ADD_FAILURE() << "no tristereo::Error thrown";
  return ErrorCode::kPlatform;
}

class IoBoundsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("tristereo_bounds_" + std::string(info->name()) + "_" +
                                        std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

std::string slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

void spit(const std::string& p, const std::vector<std::uint8_t>& b) {
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

// A file-size limit for this process, as a full disk would answer: writes past
// it fail with EFBIG (SIGXFSZ ignored). Restored on scope exit.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit r = old_;
    r.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &r);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit old_{};
  void (*old_handler_)(int) = nullptr;
};

TEST_F(IoBoundsTest, AWriteReplacesTheFileWholeAndLeavesNoTemporary) {
  write_text_file(path("a.csv"), "first\n");
  write_text_file(path("a.csv"), "second\n");
  EXPECT_EQ(slurp(path("a.csv")), "second\n");
  EXPECT_EQ(listing(), std::vector<std::string>{"a.csv"});
  // The mode is what fopen would have given (not mkstemp's 0600).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  struct stat st {};
  ASSERT_EQ(::stat(path("a.csv").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0666 & ~mask);
}

TEST_F(IoBoundsTest, ALinkKeepsPointingAtTheFileItNames) {
  fs::create_directories(path("real"));
  write_text_file(path("real/a.csv"), "old\n");
  fs::create_symlink("real/a.csv", path("link.csv"));
  write_text_file(path("link.csv"), "new\n");
  EXPECT_TRUE(fs::is_symlink(path("link.csv")));
  EXPECT_EQ(slurp(path("real/a.csv")), "new\n");
  EXPECT_EQ(listing(), (std::vector<std::string>{"link.csv", "real"}));
}

TEST_F(IoBoundsTest, AFailedWriteKeepsWhatWasAtThePath) {
  write_text_file(path("old.pgm"), "previous results\n");
  ImageU8 img(200, 200, 1);  // 40 kB, and noise so that the PNG stays larger than 4 kB
  std::uint32_t state = 12345;
  for (std::uint8_t& v : img.pixels) v = static_cast<std::uint8_t>((state = state * 1664525u + 1013904223u) >> 24);
  {
    const FileSizeLimit limit(4096);
    EXPECT_EQ(code_of([&] { write_pgm(path("old.pgm"), img.view()); }), ErrorCode::kIoError);
    EXPECT_EQ(code_of([&] { write_png_u8(path("new.png"), img.view()); }), ErrorCode::kIoError);
    EXPECT_EQ(code_of([&] { write_text_file(path("new.csv"), std::string(10000, 'x')); }), ErrorCode::kIoError);
  }
  EXPECT_EQ(slurp(path("old.pgm")), "previous results\n");
  EXPECT_EQ(listing(), std::vector<std::string>{"old.pgm"});  // no temporary, no partial new file
}

TEST_F(IoBoundsTest, AFullDeviceIsAnErrorAndIsNeverRemoved) {
  // The reproducer without root: a name for /dev/full in our folder.
  fs::create_symlink("/dev/full", path("x.ply"));
  try {
    write_text_file(path("x.ply"), "data");
    ADD_FAILURE() << "writing to /dev/full succeeded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kIoError);
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_symlink(path("x.ply")));
  struct stat st {};
  ASSERT_EQ(::stat("/dev/full", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  EXPECT_EQ(listing(), std::vector<std::string>{"x.ply"});
  // A device that takes the bytes is written in place, not replaced.
  write_text_file("/dev/null", "discarded");
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
}

TEST_F(IoBoundsTest, AFolderOrAMissingFolderIsAnError) {
  fs::create_directories(path("d.csv"));
  EXPECT_EQ(code_of([&] { write_text_file(path("d.csv"), "x"); }), ErrorCode::kIoError);
  EXPECT_TRUE(fs::is_directory(path("d.csv")));
  EXPECT_EQ(code_of([&] { write_text_file(path("nodir/a.csv"), "x"); }), ErrorCode::kIoError);
}

// ------------------------------------------------------------------ readers

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) | b[at + 3];
}

void put_be32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
}

// A valid 8x8 PNG whose IHDR then claims w x h (CRC fixed, data unchanged).
std::vector<std::uint8_t> png_claiming(int color_type, std::uint32_t w, std::uint32_t h, const std::string& p) {
  const ImageU8 img(8, 8, color_type == PNG_COLOR_TYPE_RGB ? 3 : 1);
  write_png_u8(p, img.view());
  const std::string s = slurp(p);
  std::vector<std::uint8_t> b(s.begin(), s.end());
  EXPECT_EQ(be32(b, 12), 0x49484452u);  // "IHDR" right after the signature
  put_be32(b, 16, w);
  put_be32(b, 20, h);
  put_be32(b, 29, static_cast<std::uint32_t>(crc32(0L, &b[12], 17)));
  return b;
}

// A chunk as the PNG specification lays it out: length, type, data, CRC-32.
std::vector<std::uint8_t> png_chunk(const char* type, const std::vector<std::uint8_t>& data) {
  std::vector<std::uint8_t> c;
  c.reserve(data.size() + 12);
  auto push_be32 = [&c](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) c.push_back(static_cast<std::uint8_t>(v >> (24 - 8 * i)));
  };
  push_be32(static_cast<std::uint32_t>(data.size()));
  for (int i = 0; i < 4; ++i) c.push_back(static_cast<std::uint8_t>(type[i]));
  for (std::uint8_t v : data) c.push_back(v);
  push_be32(static_cast<std::uint32_t>(crc32(0L, c.data() + 4, static_cast<uInt>(c.size() - 4))));
  return c;
}

TEST_F(IoBoundsTest, APngHeaderClaimingMoreThanItsFileCanHoldIsRefusedBeforeAllocating) {
  const std::vector<std::uint8_t> b = png_claiming(PNG_COLOR_TYPE_RGB, 16384, 16384, path("tmp.png"));
  spit(path("huge.png"), b);
  try {
    read_image_u8(path("huge.png"));
    ADD_FAILURE() << "read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorruptFile);
    EXPECT_NE(std::string(e.what()).find("more than a " + std::to_string(b.size()) + "-byte file can hold"),
              std::string::npos)
        << e.what();
  }
  // Metadata buys no pixels: the same claim behind a 1 MiB text chunk.
  {
    std::vector<std::uint8_t> padded(b.begin(), b.begin() + 33);
    const std::vector<std::uint8_t> text = png_chunk("tEXt", std::vector<std::uint8_t>(1 << 20, 'x'));
    padded.insert(padded.end(), text.begin(), text.end());
    padded.insert(padded.end(), b.begin() + 33, b.end());
    spit(path("padded.png"), padded);
    try {
      read_image_u8(path("padded.png"));
      ADD_FAILURE() << "read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("more than the " + std::to_string(b.size()) + " bytes of its image chunks (of " +
                                           std::to_string(padded.size()) + ") can hold"),
                std::string::npos)
          << e.what();
    }
  }
  // A claim the file could hold (deflate's ratio) but whose data stops early:
  // decoded row by row, it fails on the missing rows.
  spit(path("tall.png"), png_claiming(PNG_COLOR_TYPE_GRAY, 8, 8000, path("tmp2.png")));
  EXPECT_EQ(code_of([&] { read_image_u8(path("tall.png")); }), ErrorCode::kCorruptFile);
}

// The issue-41 reproducer: signature, a 4 x 4 gray IHDR, then a `type` chunk
// whose length field claims 2^31 - 16 bytes, of which 11 follow: 52 bytes.
std::vector<std::uint8_t> png_with_claiming_chunk(const char* type) {
  std::vector<std::uint8_t> b = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  const std::vector<std::uint8_t> ihdr = png_chunk("IHDR", {0, 0, 0, 4, 0, 0, 0, 4, 8, 0, 0, 0, 0});
  b.insert(b.end(), ihdr.begin(), ihdr.end());
  b.resize(b.size() + 4);
  put_be32(b, b.size() - 4, 0x7ffffff0u);
  b.insert(b.end(), type, type + 4);
  const char text[] = "Comment\0abc";
  b.insert(b.end(), text, text + 11);
  return b;
}

TEST_F(IoBoundsTest, AChunkClaimingMoreThanItsFileIsRefusedBeforeItIsRead) {
  // libpng alone allocates what the length field claims (2 GB, 8-15 s before
  // this check): every chunk is now measured against the file first.
  for (const char* type : {"tEXt", "zTXt", "iTXt", "iCCP", "prIv", "IDAT"}) {
    const std::vector<std::uint8_t> b = png_with_claiming_chunk(type);
    ASSERT_EQ(b.size(), 52u);
    const std::string p = path(std::string(type) + ".png");
    spit(p, b);
    for (const bool u16 : {false, true}) {
      const auto t0 = std::chrono::steady_clock::now();
      try {
        if (u16) read_png_u16(p); else read_image_u8(p);
        ADD_FAILURE() << "read " << type;
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::kCorruptFile);
        EXPECT_EQ(std::string(e.what()), "corrupt PNG '" + p + "': chunk '" + type +
                                             "' at byte 33 claims 2147483632 bytes, but the 52-byte file ends "
                                             "11 bytes after its header");
      }
      // Milliseconds; a generous bound so that sanitizers and qemu pass.
      EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1)) << type;
    }
  }
}

// Reads `bytes` through a named pipe, a stream whose size nobody knows: only
// the caps on chunk lengths can refuse a claim there.
std::string read_through_fifo(const std::string& fifo, const std::vector<std::uint8_t>& bytes) {
  std::signal(SIGPIPE, SIG_IGN);  // a reader that stops early must not kill the writer's process
  EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] {
    std::FILE* f = std::fopen(fifo.c_str(), "wb");  // blocks until the reader opens it
    if (!f) return;
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
  });
  std::string message;
  try {
    read_image_u8(fifo);
    message = "read";
  } catch (const Error& e) {
    message = e.what();
    EXPECT_EQ(e.code(), ErrorCode::kCorruptFile) << message;
  }
  writer.join();
  return message;
}

TEST_F(IoBoundsTest, ChunkLengthsBeyondTheCapsAreRefusedOnAStream) {
  std::vector<std::uint8_t> b = png_with_claiming_chunk("IDAT");
  put_be32(b, 33, 0x80000000u);  // beyond the PNG limit of 2^31 - 1
  EXPECT_EQ(read_through_fifo(path("idat.fifo"), b),
            "corrupt PNG '" + path("idat.fifo") +
                "': chunk 'IDAT' at byte 33 claims 2147483648 bytes, more than the 2147483647-byte limit on a "
                "chunk (include/tristereo/io.hpp)");
  b = png_with_claiming_chunk("tEXt");
  put_be32(b, 33, kMaxPngAncillaryChunkBytes + 1);
  EXPECT_EQ(read_through_fifo(path("text.fifo"), b),
            "corrupt PNG '" + path("text.fifo") +
                "': chunk 'tEXt' at byte 33 claims 16777217 bytes, more than the 16777216-byte limit on an "
                "ancillary chunk (include/tristereo/io.hpp)");
  // Within the cap, a stream's ancillary chunk is read through and dropped;
  // this one ends early, which libpng then reports.
  put_be32(b, 33, 1000);
  EXPECT_EQ(read_through_fifo(path("short.fifo"), b), "corrupt PNG '" + path("short.fifo") + "': file is truncated");
}

TEST_F(IoBoundsTest, AChunkTypeMustBeFourLetters) {
  const ImageU8 img(8, 8, 1);
  write_png_u8(path("base.png"), img.view());
  const std::string base = slurp(path("base.png"));
  std::vector<std::uint8_t> bad(base.begin(), base.end());
  bad[12] = '1';  // "IHDR" -> "1HDR"
  spit(path("type.png"), bad);
  try {
    read_image_u8(path("type.png"));
    ADD_FAILURE() << "read";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "corrupt PNG '" + path("type.png") +
                                         "': chunk '1HDR' at byte 8 has an invalid type (a chunk type is four ASCII "
                                         "letters)");
  }
}

TEST_F(IoBoundsTest, AncillaryChunksAreSkippedAndChangeNoPixel) {
  // Text, compressed text, an ICC profile, an unknown private chunk (with a
  // wrong CRC: it is never read, so never checked) and a tRNS between the
  // header and the pixels: the pixels are those of the file without them.
  ImageU8 img(7, 5, 3);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = static_cast<std::uint8_t>(i * 37);
  write_png_u8(path("plain.png"), img.view());
  const std::string plain = slurp(path("plain.png"));
  std::vector<std::uint8_t> b(plain.begin(), plain.begin() + 33);
  std::vector<std::vector<std::uint8_t>> extra = {
      png_chunk("tEXt", std::vector<std::uint8_t>(1 << 20, 'x')),
      png_chunk("zTXt", {'k', 0, 0, 1, 2, 3}),
      png_chunk("iCCP", {'p', 0, 0, 9, 9, 9}),
      png_chunk("prIv", {1, 2, 3}),
      png_chunk("tRNS", {0, 1, 0, 2, 0, 3}),
  };
  extra[3].back() ^= 0xff;  // the CRC of prIv
  for (const auto& c : extra) b.insert(b.end(), c.begin(), c.end());
  b.insert(b.end(), plain.begin() + 33, plain.end());
  spit(path("meta.png"), b);
  const ImageU8 got = read_image_u8(path("meta.png"));
  EXPECT_EQ(got.width, 7);
  EXPECT_EQ(got.height, 5);
  EXPECT_EQ(got.channels, 3);
  EXPECT_EQ(got.pixels, img.pixels);
}

TEST_F(IoBoundsTest, PaletteIndicesBeyondThePaletteAreCorrupt) {
  for (const bool interlace : {false, true}) {
    const std::string p = path(interlace ? "i.png" : "p.png");
    std::FILE* f = std::fopen(p.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_set_check_for_invalid_index(png, 0);  // let the writer store the bad index
    png_init_io(png, f);
    png_set_IHDR(png, info, 4, 2, 8, PNG_COLOR_TYPE_PALETTE,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_color pal[2] = {{1, 2, 3}, {4, 5, 6}};
    png_set_PLTE(png, info, pal, 2);
    png_write_info(png, info);
    std::uint8_t r0[4] = {0, 1, 0, 1}, r1[4] = {1, 0, 7, 0};
    png_bytep rows[2] = {r0, r1};
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    try {
      read_image_u8(p);
      ADD_FAILURE() << "read " << p;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorruptFile);
      EXPECT_NE(std::string(e.what()).find("pixel (2, 1) has palette index 7 but the palette has 2 entries"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST_F(IoBoundsTest, AnEndlessStreamCostsOneChunk) {
  // /dev/zero never ends: the first 64 KiB already say it is no image.
  EXPECT_EQ(code_of([] { read_image_u8("/dev/zero"); }), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([] { read_png_u16("/dev/zero"); }), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([] { read_pfm("/dev/zero"); }), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(code_of([] { read_disparity("/dev/zero"); }), ErrorCode::kUnsupportedFormat);
}

}  // namespace
}  // namespace tristereo
