#include "apps/cli_args.hpp"

#include <cerrno>
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
        values_[name] = value;
      } else if (flag_options.count(name) && !inline_value) {
        flags_.insert(name);
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

double Args::get_double(const std::string& name, double fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : parse_double("--" + name, it->second);
}

int parse_int(const std::string& option, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < -2147483647L || v > 2147483647L)
    throw UsageError(option + ": '" + text + "' is not an integer");
  return static_cast<int>(v);
}

double parse_double(const std::string& option, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !(v == v))
    throw UsageError(option + ": '" + text + "' is not a number");
  return v;
}

std::pair<int, int> parse_size(const std::string& option, const std::string& text) {
  const auto x = text.find('x');
  if (x == std::string::npos) {
    const int s = parse_int(option, text);
    return {s, s};
  }
  return {parse_int(option, text.substr(0, x)), parse_int(option, text.substr(x + 1))};
}

}  // namespace tristereo::cli
