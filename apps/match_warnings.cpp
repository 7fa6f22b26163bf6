#include "apps/match_warnings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

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

std::string threads_warning(int threads, int allowed_cpus, bool cpus_given) {
  if (threads <= allowed_cpus || allowed_cpus < 1) return "";
  return "warning: --threads " + std::to_string(threads) + " with only " + std::to_string(allowed_cpus) +
         (cpus_given ? " CPUs in --cpus" : " CPUs allowed for this process") +
         ": workers share CPUs, which is slower and gives the same result; --threads 0 starts one per CPU";
}

SwapVotes swap_votes(ImageView<const std::uint8_t> l, ImageView<const std::uint8_t> r, int d_max) {
  constexpr int kHalf = 4, kSide = 2 * kHalf + 1, kN = kSide * kSide;
  SwapVotes votes;
  if (d_max < 1 || l.width != r.width || l.height != r.height || l.channels != 1 || r.channels != 1) return votes;
  // About 400 blocks on the grid whatever the size (28 px apart on VGA), so the
  // check costs about 400 x 2 d_max block comparisons; at least 4 px apart.
  const int step = std::max(4, static_cast<int>(std::sqrt(l.width * 1.0 * l.height / 400)));
  std::vector<int> block(kN);
  for (int cy = kHalf; cy + kHalf < l.height; cy += step) {
    for (int cx = kHalf; cx + kHalf < l.width; cx += step) {
      int sum = 0;
      for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) sum += block[y * kSide + x] = l.row(cy - kHalf + y)[cx - kHalf + x];
      long long texture = 0;  // N * sum |v - mean|, integers only
      for (int v : block) texture += std::abs(v * kN - sum);
      if (texture < 4LL * kN * kN) continue;  // mean deviation < 4 gray levels: flat
      long long best_pos = -1, best_neg = -1;
      for (int d = -d_max; d <= d_max; ++d) {
        const int rx = cx - d;  // left x matches right x - d
        if (d == 0 || rx - kHalf < 0 || rx + kHalf >= r.width) continue;
        int rsum = 0;
        for (int y = 0; y < kSide; ++y)
          for (int x = 0; x < kSide; ++x) rsum += r.row(cy - kHalf + y)[rx - kHalf + x];
        long long cost = 0;  // zero-mean SAD, times N
        for (int y = 0; y < kSide; ++y)
          for (int x = 0; x < kSide; ++x)
            cost += std::abs((block[y * kSide + x] * kN - sum) - (r.row(cy - kHalf + y)[rx - kHalf + x] * kN - rsum));
        long long& best = d > 0 ? best_pos : best_neg;
        if (best < 0 || cost < best) best = cost;
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
