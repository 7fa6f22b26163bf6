#include "apps/cli_args.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace tristereo::cli {

Args::Args(int argc, char** argv, const std::set<std::string>& value_options,
           const std::set<std::string>& flag_options) {
  bool options_ended = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    // "--" ends the options, as in POSIX utilities: what follows is a path
    // even when it starts with "--".
    if (a == "--" && !options_ended) {
      options_ended = true;
      continue;
    }
    if (!options_ended && a.size() > 2 && a.compare(0, 2, "--") == 0) {
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
          // "--disp --stats s.json": --disp would take "--stats" as its file
          // and leave s.json as a stray path; name the real mistake instead.
          const std::string next_name = value.size() > 2 && value.compare(0, 2, "--") == 0
                                            ? value.substr(2, value.find('=') == std::string::npos
                                                                  ? std::string::npos
                                                                  : value.find('=') - 2)
                                            : std::string();
          if (!next_name.empty() && (value_options.count(next_name) || flag_options.count(next_name)))
            throw UsageError("option --" + name + " needs a value, but the option " + value +
                             " follows it (a value that starts with -- goes as --" + name + "=VALUE)");
        }
        // Given twice, one value would silently win: say so instead.
        if (values_.count(name)) throw UsageError("option --" + name + " given twice");
        values_[name] = value;
      } else if (flag_options.count(name) && !inline_value) {
        // Like a value given twice: a repeated flag is most likely a slip
        // (an edited command line), and README promises it is refused.
        if (!flags_.insert(name).second) throw UsageError("option --" + name + " given twice");
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

void check_option_needs(const Args& args, const std::vector<OptionNeed>& table) {
  for (const OptionNeed& n : table) {
    if (!args.has(n.option)) continue;
    bool met = false;
    std::string wanted;
    for (std::size_t i = 0; i < n.any_of.size(); ++i) {
      const std::string other = n.any_of[i];
      met = met || (args.has(other) && (n.value == nullptr || args.get(other, "") == n.value));
      wanted += (i == 0 ? "" : i + 1 == n.any_of.size() ? " or " : ", ") + ("--" + other) +
                (n.value ? std::string(" ") + n.value : std::string());
    }
    if (!met)
      throw UsageError("--" + std::string(n.option) + " has no effect without " + wanted + " (" + n.effect + ")");
  }
}

const char* exit_codes_help() {
  return R"(Exit status:
  0  success (warnings, if any, on stderr)
  1  bad input or failed check: unreadable, corrupt or unsupported file, images that do
     not fit together, an output that cannot be written (full disk, missing folder),
     verify finding a difference
  2  usage error: unknown option, an option given twice, missing or out-of-range value
     (--ndisp 0), an option that has no effect given the others (--mesh-ascii without
     --mesh), wrong number of paths, an output path that names an input or another
     output, or whose extension is not one the option writes
"--" ends the options: what follows is a path even if it starts with "--".
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
