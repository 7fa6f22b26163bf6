// Tritree configuration: parameter validation and the one-time allocation of
// every buffer a build can need.
#include <algorithm>
#include <string>

#include "src/model/psnr_threshold.hpp"
#include "src/tritree/tritree.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

void check_range(const char* what, long long value, long long lo, long long hi) {
  if (value < lo || value > hi) {
    throw Error(ErrorCode::kInvalidArgument,
                std::string("tritree: ") + what + " = " + std::to_string(value) +
                    " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  }
}

// Every leaf but the two roots of a 2x2 image has area2 >= 2, and the leaves
// tile the (W-1) x (H-1) rectangle, so there are at most (W-1)(H-1) of them.
std::size_t max_leaves(int w, int h) {
  const std::size_t cells = static_cast<std::size_t>(w - 1) * static_cast<std::size_t>(h - 1);
  return cells < 2 ? 2 : cells;
}

}  // namespace

void Tritree::configure(int max_width, int max_height, const TritreeParams& params) {
  max_width_ = 0;  // unconfigured until everything below succeeded
  check_range("max_width", max_width, 2, kMaxImageSide);
  check_range("max_height", max_height, 2, kMaxImageSide);
  check_range("max_area_px2", params.max_area_px2, 1, kMaxAreaLimitPx2);
  check_range("psnr_deci_db", params.psnr_deci_db, kMinPsnrDeciDb, kMaxPsnrDeciDb);

  const std::size_t leaves = max_leaves(max_width, max_height);
  const std::size_t pixels = static_cast<std::size_t>(max_width) * max_height;
  // An eighth more node slots than leaves: the spare that partition() shares
  // out among the regions.
  const std::size_t slots = leaves + leaves / 8 + kMaxRegions;
  nodes_.assign(slots, Node{});
  spare_limit_ = slots;
  regions_.assign(kMaxRegions, Region{});
  // Per round, each bisection adds one slot of its region and creates two
  // entries there; the region lists are carved from these (see partition()).
  pending_.assign(2 * slots, Pending{});
  created_.assign(2 * slots, Pending{});
  vertex_id_.assign(pixels, -1);
  bucket_.assign(pixels + 1, 0);
  tri_banded_.assign(leaves, Triangle{});
  new_vertices_.assign(slots, Vertex{});
  band_of_row_.assign(static_cast<std::size_t>(max_height), 0);
  band_fill_.assign(static_cast<std::size_t>(kMaxRegions) * kMaxRegions, 0);

  params_ = params;
  mse_q8_ = mse_threshold_q8(params.psnr_deci_db);
  max_height_ = max_height;
  max_width_ = max_width;
}

void Tritree::reserve(Mesh& mesh) const {
  if (!configured()) throw Error(ErrorCode::kNotConfigured, "tritree: reserve() before configure()");
  mesh.vertices.reserve(static_cast<std::size_t>(max_width_) * max_height_);
  mesh.triangles.reserve(max_leaves(max_width_, max_height_));
  mesh.row_start.reserve(static_cast<std::size_t>(max_height_) + 1);
}

void Tritree::validate_image(ImageView<const std::uint8_t> gray) const {
  if (!configured()) throw Error(ErrorCode::kNotConfigured, "tritree: build() before configure()");
  if (gray.data == nullptr) throw Error(ErrorCode::kInvalidArgument, "tritree: image data is null");
  if (gray.channels != 1) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "tritree: image has " + std::to_string(gray.channels) +
                    " channels, expected 1 (gray)");
  }
  check_range("image width", gray.width, 2, max_width_);
  check_range("image height", gray.height, 2, max_height_);
  if (gray.stride_bytes < gray.width) {
    throw Error(ErrorCode::kInvalidArgument,
                "tritree: stride_bytes = " + std::to_string(gray.stride_bytes) +
                    " is smaller than the width " + std::to_string(gray.width));
  }
}

}  // namespace tristereo
