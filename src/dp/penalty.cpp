#include "src/dp/penalty.hpp"

namespace tristereo {

std::uint32_t gap_penalty_q4(int lambda_q4, GapPolicy policy, int gap) {
  const std::int64_t lambda = lambda_q4;
  const std::int64_t g = gap;
  switch (policy) {
    case GapPolicy::kInvSquare:
      return static_cast<std::uint32_t>((2 * lambda + g * g) / (2 * g * g));
    case GapPolicy::kInverse:
      return static_cast<std::uint32_t>((2 * lambda + g) / (2 * g));
    case GapPolicy::kConstant:
      break;
  }
  return static_cast<std::uint32_t>(lambda);
}

void fill_penalty_table(int lambda_q4, GapPolicy policy, int max_gap,
                        std::vector<std::uint32_t>& table) {
  table.assign(static_cast<std::size_t>(max_gap) + 1, 0);
  for (int g = 1; g <= max_gap; ++g) table[g] = gap_penalty_q4(lambda_q4, policy, g);
}

}  // namespace tristereo
