#include "apps/cli_args.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace tristereo::cli {

Args::Args(int argc, char** argv, const std::set<std::string>& value_options,
           const std::set<std::string>& flag_options) {
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string name = a.substr(2), value;
      const auto eq = name.find('=');
      const bool inline_value = eq != std::string::npos;
      if (inline_value) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      if (value_options.count(name)) {
        if (!inline_value) {
          if (i + 1 >= argc) throw UsageError("option --" + name + " needs a value");
          value = argv[++i];
        }
        // Given twice, one value would silently win: say so instead.
        if (values_.count(name)) throw UsageError("option --" + name + " given twice");
        values_[name] = value;
      } else if (flag_options.count(name) && !inline_value) {
        flags_.insert(name);
      } else if (flag_options.count(name)) {
        throw UsageError("option --" + name + " takes no value (found '" + value + "')");
      } else {
        throw UsageError("unknown option --" + name + " (see --help)");
      }
    } else {
      positional_.push_back(a);
    }
  }
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

int Args::get_int(const std::string& name, int fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : parse_int("--" + name, it->second);
}

int Args::get_int_in(const std::string& name, int fallback, int lo, int hi) const {
  const int v = get_int(name, fallback);
  if (v < lo || v > hi)
    throw UsageError("--" + name + " " + std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
  return v;
}

double Args::get_double(const std::string& name, double fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : parse_double("--" + name, it->second);
}

const char* exit_codes_help() {
  return R"(Exit status:
  0  success (warnings, if any, on stderr)
  1  bad input or failed check: unreadable, corrupt or unsupported file, images that do
     not fit together, an output that cannot be written (full disk, missing folder),
     verify finding a difference
  2  usage error: unknown option, an option given twice, missing or out-of-range value
     (--ndisp 0), wrong number of paths, an output path that names an input or another
     output, or whose extension is not one the option writes
)";
}

int parse_int(const std::string& option, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || std::isspace(static_cast<unsigned char>(text[0])))
    throw UsageError(option + ": '" + text + "' is not an integer");
  // INT_MIN is refused too, so that no caller has to care about negating it.
  if (errno == ERANGE || v < -2147483647LL || v > 2147483647LL)
    throw UsageError(option + " " + text + " is out of range (far beyond what any option accepts)");
  return static_cast<int>(v);
}

double parse_double(const std::string& option, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v == v) || std::isspace(static_cast<unsigned char>(text[0])))
    throw UsageError(option + ": '" + text + "' is not a number");
  if (errno == ERANGE && (v > 1 || v < -1)) throw UsageError(option + " " + text + " is out of range");
  if (!std::isfinite(v)) throw UsageError(option + ": '" + text + "' is not a finite number");
  return v;
}

std::pair<int, int> parse_size(const std::string& option, const std::string& text) {
  const auto x = text.find('x');
  if (x != std::string::npos && (x == 0 || x + 1 == text.size() || text.find('x', x + 1) != std::string::npos))
    throw UsageError(option + ": '" + text + "' is not a size (W or WxH, e.g. 5x5)");
  if (x == std::string::npos) {
    const int s = parse_int(option, text);
    return {s, s};
  }
  return {parse_int(option, text.substr(0, x)), parse_int(option, text.substr(x + 1))};
}

}  // namespace tristereo::cli
