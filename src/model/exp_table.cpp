// Compile-time regression guard for the integer exp tables: the tables are
// part of the model (docs/model.md section 2), so a change to their bytes must
// be deliberate. tests/cost_test.cpp checks them against std::exp at run time.
#include "src/model/exp_table.hpp"

#include <array>

namespace tristereo {
namespace {

template <int Gamma, int Count>
constexpr std::array<std::uint8_t, Count> exp_table_array() {
  std::array<std::uint8_t, Count> t{};
  exp_decay_table_u8(Gamma, Count, t.data());
  return t;
}

// 255 e^{-t/10}: 255, 231, ..., 94 at t = 10 (255/e = 93.8), 0 from t = 63.
constexpr auto kColour10 = exp_table_array<10, 64>();
static_assert(kColour10[0] == 255 && kColour10[1] == 231 && kColour10[10] == 94 &&
                  kColour10[20] == 35 && kColour10[62] == 1 && kColour10[63] == 0,
              "exp_decay_table_u8 changed for gamma = 10");
constexpr auto kProximity50 = exp_table_array<50, 64>();
static_assert(kProximity50[1] == 250 && kProximity50[50] == 94 && kProximity50[63] == 72,
              "exp_decay_table_u8 changed for gamma = 50");

}  // namespace
}  // namespace tristereo
