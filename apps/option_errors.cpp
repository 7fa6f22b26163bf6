#include "apps/option_errors.hpp"

#include <cctype>

#include "src/model/model_options.hpp"

namespace tristereo::cli {

// The fields' options come from the model's option table (src/model/model_options.cpp).
std::string option_message(const std::string& m) {
  const std::string named = name_options_in(m, OptionSpelling::kCommandLine);
  return named != m ? named : "invalid parameter: " + m;
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
