#include "apps/match_warnings.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "tristereo/fixed_point.hpp"

namespace tristereo::cli {

std::string range_outside_image_warning(int width, int d_min, int num_disp) {
  const long long d_max = static_cast<long long>(d_min) + num_disp - 1;
  // Left pixel x matches right x - d: inside the image for some x iff
  // -(width - 1) <= d <= width - 1.
  if (d_min <= width - 1 && d_max >= -(static_cast<long long>(width) - 1)) return "";
  return "warning: the disparity range " + std::to_string(d_min) + ".." + std::to_string(d_max) +
         " leaves no match inside the " + std::to_string(width) +
         "-pixel-wide image (left x matches right x - d): every disparity found is meaningless; "
         "check --dmin and --ndisp";
}

std::string no_depth_warning(const CameraParams& camera, const std::string& source, int d_min, int num_disp) {
  const int d_max = d_min + num_disp - 1;
  // Z = f B / (d + doffs) is finite and positive only for d + doffs > 0; the
  // largest disparity searched is the best chance.
  if (d_max + camera.doffs > 0) return "";
  char text[512];
  std::snprintf(text, sizeof text,
                "warning: %s: with doffs %.6g px, no disparity searched (%d..%d) gives a finite positive depth "
                "(that needs disparity + doffs > 0): every depth, point and metric mesh vertex will be invalid; "
                "check the sign of doffs and --dmin",
                source.c_str(), camera.doffs, d_min, d_max);
  return text;
}

std::string threads_warning(int threads, int allowed_cpus, bool cpus_given) {
  if (threads <= allowed_cpus || allowed_cpus < 1) return "";
  return "warning: --threads " + std::to_string(threads) + " with only " + std::to_string(allowed_cpus) +
         (cpus_given ? " CPUs in --cpus" : " CPUs allowed for this process") +
         ": workers share CPUs, which is slower and gives the same result; --threads 0 starts one per CPU";
}

// Each block's costs are taken for all its shifts at once, by right column
// x = cx - d rather than by d: the inner loops then run over contiguous
// right columns, which the compiler vectorises (it was 3 ms of a one-shot
// KITTI match, scalar; tests/cli_warnings_test.cpp checks the votes against a
// literal per-shift transcription). Every sum fits int32: kN l - sum and
// kN r - rsum lie in [-kN 255, kN 255], so a cost is below kN 2 kN 255 < 2^22.
SwapVotes swap_votes(ImageView<const std::uint8_t> l, ImageView<const std::uint8_t> r, int d_max) {
  constexpr int kHalf = 4, kSide = 2 * kHalf + 1, kN = kSide * kSide;
  SwapVotes votes;
  if (d_max < 1 || l.width != r.width || l.height != r.height || l.channels != 1 || r.channels != 1) return votes;
  // About 400 blocks on the grid whatever the size (28 px apart on VGA), so the
  // check costs about 400 x 2 d_max block comparisons; at least 4 px apart.
  const int step = std::max(4, static_cast<int>(std::sqrt(l.width * 1.0 * l.height / 400)));
  const int w = r.width;
  std::array<int, kN> zero_mean{};  // kN l - sum, the block's zero-mean values
  // Per block, over the right columns its shifts reach: kN r by row, the
  // 9-row column sums, each shift's zero-mean offset (rsum) and cost.
  std::vector<int> right_kn(static_cast<std::size_t>(kSide) * w), column(w), rsum(w), cost(w);
  for (int cy = kHalf; cy + kHalf < l.height; cy += step) {
    bool strip_ready = false;
    for (int cx = kHalf; cx + kHalf < l.width; cx += step) {
      int sum = 0;
      for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) sum += l.row(cy - kHalf + y)[cx - kHalf + x];
      long long texture = 0;  // N * sum |v - mean|, integers only
      for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) {
          const int v = l.row(cy - kHalf + y)[cx - kHalf + x] * kN - sum;
          zero_mean[static_cast<std::size_t>(y * kSide + x)] = v;
          texture += std::abs(v);
        }
      if (texture < 4LL * kN * kN) continue;  // mean deviation < 4 gray levels: flat
      if (!strip_ready) {  // the block row's right strip, once per row of blocks
        for (int y = 0; y < kSide; ++y) {
          const std::uint8_t* row = r.row(cy - kHalf + y);
          int* kn = right_kn.data() + static_cast<std::size_t>(y) * w;
          for (int x = 0; x < w; ++x) kn[x] = row[x] * kN;
        }
        for (int x = 0; x < w; ++x) {
          int c = 0;
          for (int y = 0; y < kSide; ++y) c += r.row(cy - kHalf + y)[x];
          column[static_cast<std::size_t>(x)] = c;
        }
        strip_ready = true;
      }
      // Shifts -d_max .. d_max whose right block is inside: centre columns
      // rx = cx - d in [lo, hi].
      const long long lo_ll = std::max<long long>(kHalf, static_cast<long long>(cx) - d_max);
      const long long hi_ll = std::min<long long>(w - 1 - kHalf, static_cast<long long>(cx) + d_max);
      if (lo_ll > hi_ll) continue;
      const int lo = static_cast<int>(lo_ll), hi = static_cast<int>(hi_ll);
      for (int rx = lo; rx <= hi; ++rx) {
        int s = 0;
        for (int x = rx - kHalf; x <= rx + kHalf; ++x) s += column[static_cast<std::size_t>(x)];
        rsum[static_cast<std::size_t>(rx)] = s;
        cost[static_cast<std::size_t>(rx)] = 0;
      }
      // cost(rx) = sum |(kN l - sum) - (kN r - rsum(rx))|, zero-mean SAD times N.
      for (int y = 0; y < kSide; ++y) {
        const int* kn = right_kn.data() + static_cast<std::size_t>(y) * w;
        for (int x = 0; x < kSide; ++x) {
          const int a = zero_mean[static_cast<std::size_t>(y * kSide + x)];
          const int* rv = kn + x - kHalf;
          int* c = cost.data();
          const int* rs = rsum.data();
          for (int rx = lo; rx <= hi; ++rx) c[rx] += std::abs(a + rs[rx] - rv[rx]);
        }
      }
      long long best_pos = -1, best_neg = -1;
      for (int rx = lo; rx <= hi; ++rx) {
        const int d = cx - rx;
        if (d == 0) continue;
        long long& best = d > 0 ? best_pos : best_neg;
        const long long c = cost[static_cast<std::size_t>(rx)];
        if (best < 0 || c < best) best = c;
      }
      if (best_pos < 0 || best_neg < 0) continue;  // one sign cannot be tried here
      // Decisive: the winning sign is better by a quarter.
      if (4 * best_pos < 3 * best_neg) ++votes.positive;
      else if (4 * best_neg < 3 * best_pos) ++votes.negative;
    }
  }
  return votes;
}

std::string swapped_warning(ImageView<const std::uint8_t> l, ImageView<const std::uint8_t> r, int d_min,
                            int num_disp) {
  if (d_min < 0) return "";
  const SwapVotes v = swap_votes(l, r, d_min + num_disp - 1);
  if (v.positive + v.negative < kSwapMinBlocks || v.negative < kSwapRatio * v.positive) return "";
  return "warning: LEFT and RIGHT look swapped: " + std::to_string(v.negative) + " of " +
         std::to_string(v.positive + v.negative) +
         " textured blocks of LEFT match RIGHT better at x + d than at x - d; LEFT must be the left "
         "camera's image (its pixel x matches RIGHT's x - d): check the order of the paths";
}

}  // namespace tristereo::cli
