#include "apps/option_errors.hpp"

#include <cctype>

namespace tristereo::cli {

namespace {

struct FieldOption {
  const char* field;   // as validate_params names it
  const char* option;  // as the user types it, with what part of it
};

// One row per StereoParams field that an option sets (apps/stereo_options.cpp).
constexpr FieldOption kFieldOptions[] = {
    {"num_disp", "--ndisp"},
    {"d_min", "--dmin"},
    {"tritree.psnr_deci_db", "--psnr (in 0.1 dB)"},
    {"tritree.max_area_px2", "--max-area"},
    {"tritree.min_area_px2", "--min-area"},
    {"cost.window_w", "--window width"},
    {"cost.window_h", "--window height"},
    {"cost.truncation", "--truncation"},
    {"cost.asw_gamma_color", "--gamma-color"},
    {"cost.asw_gamma_proximity", "--gamma-proximity"},
    {"dp.lambda_q4", "--lambda"},
    {"cost.weights", "--weights"},
    {"cost.census_w", "--census width"},
    {"cost.census_h", "--census height"},
    {"cost.ad_weight_q4", "--ad-weight"},
    {"paths.directions", "--paths"},
    {"paths.p1_q4", "--p1"},
    {"paths.p2_q4", "--p2"},
    {"paths.p2_edge_scale", "--p2-edge"},
    {"validity.lr_max_diff_q4", "--lr-max-diff"},
    {"validity.uniqueness_pct", "--uniqueness"},
    {"validity.lr_source", "--lr-source"},
};

}  // namespace

std::string option_message(const std::string& m) {
  const std::size_t eq = m.find(" = ");
  if (eq != std::string::npos) {
    const std::string field = m.substr(0, eq);
    for (const FieldOption& f : kFieldOptions) {
      if (field != f.field) continue;
      std::string out = std::string(f.option) + " " + m.substr(eq + 3);
      if (field == "d_min") out += " (|--dmin| + --ndisp must be at most 2048)";
      return out;
    }
  }
  return "invalid parameter: " + m;
}

void as_usage_error(const char* option, const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidArgument) throw;
    if (option) throw UsageError(std::string(option) + ": " + without_function_prefix(e.what()));
    throw UsageError(option_message(e.what()));
  }
}

std::string without_function_prefix(const std::string& m) {
  // identifier[ (detail)]: rest
  std::size_t i = 0;
  while (i < m.size() && (std::islower(static_cast<unsigned char>(m[i])) || m[i] == '_' ||
                          std::isdigit(static_cast<unsigned char>(m[i]))))
    ++i;
  if (i == 0 || m.find('_') > i) return m;  // a function name has an underscore
  if (m.compare(i, 2, " (") == 0) {
    const std::size_t close = m.find(')', i);
    if (close == std::string::npos) return m;
    i = close + 1;
  }
  if (m.compare(i, 2, ": ") != 0) return m;
  return m.substr(i + 2);
}

}  // namespace tristereo::cli
