// Smoothness penalty of the sparse DP (docs/model.md section 3).
#pragma once

#include <cstdint>
#include <vector>

#include "tristereo/params.hpp"

namespace tristereo {

// P(g) = round(lambda_q4 * tau(g)), halves up, for a gap of g >= 1 pixels:
//   kInvSquare: floor((2 lambda + g^2) / (2 g^2))
//   kInverse:   floor((2 lambda + g)   / (2 g))
//   kConstant:  lambda
// Result in 0 .. lambda_q4 (Q4 cost units per disparity step).
std::uint32_t gap_penalty_q4(int lambda_q4, GapPolicy policy, int gap);

// table[g] = gap_penalty_q4(lambda_q4, policy, g) for g in 1..max_gap (table[0] = 0).
// Built once at configure; resizes `table` to max_gap + 1.
void fill_penalty_table(int lambda_q4, GapPolicy policy, int max_gap,
                        std::vector<std::uint32_t>& table);

}  // namespace tristereo
