// Image, disparity and mesh files.
//
// Readers detect the format from the first bytes (never the extension) and
// answer bad files with tristereo::Error, never a crash:
//   kIoError           the file cannot be opened or read (missing, a directory, ...)
//   kCorruptFile       empty, truncated or malformed contents (bad CRC, short data)
//   kUnsupportedFormat a valid file we do not read (16-bit PNG in read_image_u8,
//                      maxval != 255, unknown magic) or one larger than the reader
//                      limits below; sizes are checked before any pixel allocation.
// Writers validate everything before creating the file, then write atomically:
// into a hidden temporary in the same folder, every write, the flush, fsync,
// close and the final rename checked (kIoError naming the path and the OS
// reason, e.g. "No space left on device"). On failure only the temporary is
// removed: what was at the path before stays as it was. An existing device or
// FIFO at the path (/dev/null, a named pipe) is written in place, never removed.
#pragma once

#include "tristereo/export.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// Reader limits, checked before anything is allocated for the pixels:
//  - each side <= kMaxReadSide and width * height <= kMaxReadPixels;
//  - the file <= kMaxReadFileBytes (a regular file's size is checked before
//    it is read; a stream stops there), and its first 64 KiB must start like
//    the format asked for, so /dev/zero or a large file of another kind
//    costs one 64 KiB chunk;
//  - PNM and PFM: the header's size must fit in the bytes that follow it;
//  - PNG: every chunk's length is checked before the chunk is read: at most
//    kMaxPngChunkBytes, at most kMaxPngAncillaryChunkBytes for an ancillary
//    chunk (text, ICC profile, EXIF, unknown), and never beyond the end of
//    the file (kCorruptFile naming the chunk). Ancillary chunks are skipped
//    by seeking, never read into memory: none of them changes the pixels
//    returned. The header's pixel data must fit in kMaxPngExpansion times the
//    file's size (deflate cannot expand more), and rows are stored as they
//    decode, so a file claiming more pixels than it holds fails after
//    costing about what it really decoded.
// Memory for a read is therefore bounded by a small multiple of the file's
// size plus the decoded image (at most kMaxPngExpansion times the file).
constexpr int kMaxReadSide = 65535;                          // pixels per side
constexpr std::int64_t kMaxReadPixels = std::int64_t{1} << 28;  // width * height
// The largest image the limits allow (RGB, 16-bit would be 2x) plus headers.
constexpr std::uint64_t kMaxReadFileBytes = (std::uint64_t{1} << 28) * 4 * 3 + (1 << 20);
constexpr std::int64_t kMaxPngExpansion = 1032;
// The PNG specification's own limit on a chunk's length (2^31 - 1).
constexpr std::uint32_t kMaxPngChunkBytes = 0x7fffffffu;
// Ancillary chunks are skipped unread, but one claiming more than this is not
// metadata a camera or an image editor writes (ICC profiles and EXIF blocks
// are well under 1 MiB): the file is refused rather than walked on trust.
constexpr std::uint32_t kMaxPngAncillaryChunkBytes = 16u << 20;

// `contents` as the whole file at `path`, written atomically as above (for
// text outputs such as CSV and JSON).
TRISTEREO_API void write_text_file(const std::string& path, const std::string& contents);

// ---------------------------------------------------------------- 8-bit images
// PNG (libpng) or binary/ASCII PNM (P5/P6/P2/P3, maxval 255 only).
// Result: 1 channel (gray) or 3 channels (RGB). PNG conversions: palette ->
// RGB, 1/2/4-bit gray -> 8-bit (scaled to 0..255), alpha and tRNS dropped
// (no compositing). 16-bit PNG -> kUnsupportedFormat (use read_png_u16).
TRISTEREO_API ImageU8 read_image_u8(const std::string& path);

// 16-bit single-channel PNG (e.g. a disparity PNG from write_disparity);
// anything else -> kUnsupportedFormat.
TRISTEREO_API Image<std::uint16_t> read_png_u16(const std::string& path);

// 8-bit PNG, 1 (gray) or 3 (RGB) channels.
TRISTEREO_API void write_png_u8(const std::string& path, ImageView<const std::uint8_t> img);
// 16-bit gray PNG (1 channel).
TRISTEREO_API void write_png_u16(const std::string& path, ImageView<const std::uint16_t> img);
// Binary PGM (P5, 1 channel) / PPM (P6, 3 channels), maxval 255.
TRISTEREO_API void write_pgm(const std::string& path, ImageView<const std::uint8_t> img);
TRISTEREO_API void write_ppm(const std::string& path, ImageView<const std::uint8_t> img);

// ---------------------------------------------------------------- PFM (float)
// Middlebury convention: "Pf" (1 channel) or "PF" (3 channels), then
// "width height", then the scale (negative = little endian), rows stored
// bottom-to-top. write_pfm always writes scale -1 (little endian); read_pfm
// reads either endianness, returns rows top-to-bottom, and rejects data
// shorter than width * height * channels floats (kCorruptFile).
TRISTEREO_API void write_pfm(const std::string& path, ImageView<const float> img);
TRISTEREO_API Image<float> read_pfm(const std::string& path);

// ---------------------------------------------------------------- disparity maps
// Q4 (value / 16 = pixels) -> float pixels; kInvalidDispQ4 -> +infinity (the
// Middlebury "unknown" value in PFM files). 1 channel only.
TRISTEREO_API Image<float> disp_q4_to_float(ImageView<const std::int16_t> disp_q4);

// How a 16-bit disparity PNG encodes d (both: 0 = invalid):
//  kQ4     value = 16 d, the Q4 value itself (OpenCV's CV_16S convention);
//  kKitti  value = 256 d (the KITTI benchmark's disparity PNGs).
enum class DispPngScale { kQ4 = 16, kKitti = 256 };

// Chooses the format by extension (case-insensitive):
//  .pfm  float disparity in pixels, invalid = +infinity;
//  .png  16-bit gray, value = d * png_scale (see DispPngScale), 0 = invalid.
//        A valid disparity of exactly 0 is therefore read back as invalid;
//        negative disparities, and with kKitti disparities of 256 px or more,
//        cannot be stored (kInvalidArgument naming the pixel).
// Other extensions -> kInvalidArgument.
TRISTEREO_API void write_disparity(const std::string& path, ImageView<const std::int16_t> disp_q4,
                     DispPngScale png_scale = DispPngScale::kQ4);
// Reads what write_disparity wrote (.png: 0 -> kInvalidDispQ4, else
// value * 16 / png_scale rounded half away from zero, which must fit in int16
// or kCorruptFile; .pfm: non-finite -> kInvalidDispQ4, else round(16 d) half
// away from zero, likewise). Format from the magic bytes; png_scale says how
// to read a PNG, which cannot tell by itself.
TRISTEREO_API Image<std::int16_t> read_disparity(const std::string& path, DispPngScale png_scale = DispPngScale::kQ4);

// 8-bit RGB PNG visualisation: disparities d_min .. d_min + num_disp - 1 map
// (clamped) onto disparity_color(); invalid pixels are black.
TRISTEREO_API void write_disparity_color(const std::string& path, ImageView<const std::int16_t> disp_q4,
                           int d_min, int num_disp);
// The colour map: t_q10 in 0..1024 (clamped) -> RGB. Piecewise linear through
// five hand-picked stops, dark blue -> violet -> red -> orange -> pale yellow,
// with BT.601 luma 23, 66, 109, 168, 239 at the stops (linear between them up
// to per-channel rounding), so near = bright even in gray print.
TRISTEREO_API void disparity_color(int t_q10, std::uint8_t rgb[3]);

// ---------------------------------------------------------------- PLY mesh
// Pinhole camera of the left view (Middlebury calib.txt conventions).
struct CameraParams {
  double focal_px;   // focal length, pixels
  double baseline;   // distance between the optical centres (output unit, e.g. mm)
  double cx;         // principal point, pixels
  double cy;
  double doffs = 0;  // x-difference of the principal points (right - left), pixels
};

// Writes the 2.5D mesh as PLY ("binary_little_endian 1.0" or "ascii 1.0").
// Vertex: float x, y, z + uchar red, green, blue (colour from the left image,
// gray or RGB, which must have the mesh's size). Face: "list uchar int
// vertex_indices", the mesh's orientation (counter-clockwise with y down).
//  camera == nullptr: (x, y, d) in pixels, d = disp_q4 / 16.
//  camera given:      Z = baseline * f / (d + doffs), X = (x - cx) Z / f,
//                     Y = (y - cy) Z / f (camera frame, y down).
// A vertex whose disparity is kInvalidDispQ4 (or, with a camera, whose
// d + doffs <= 0) is still written, so indices stay those of the mesh, at
// (x, y, 0) in pixel mode or (0, 0, 0) in metric mode; every face touching
// it is dropped, and counted in the report. Throws kSizeMismatch /
// kInvalidArgument on inconsistent input, and kInvalidArgument when a camera
// puts a vertex beyond float range (inf/nan coordinates are never written).
struct MeshWriteReport {
  std::size_t faces_written = 0;
  std::size_t faces_without_disparity = 0;  // a corner's disparity is invalid
  std::size_t faces_behind_camera = 0;      // metric: a corner has d + doffs <= 0
};
TRISTEREO_API MeshWriteReport write_mesh_ply(const std::string& path, const Mesh& mesh,
                                             const std::vector<std::int16_t>& vertex_disp_q4,
                                             ImageView<const std::uint8_t> left_gray_or_rgb,
                                             const CameraParams* camera, bool binary);

}  // namespace tristereo
