// A small command-line parser: positionals, "--key value" options and flags.
// Unknown options and missing values are errors, reported with the option name.
#pragma once

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace tristereo::cli {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  // value_options take a value; flag_options do not. argv[0] is the subcommand.
  Args(int argc, char** argv, const std::set<std::string>& value_options,
       const std::set<std::string>& flag_options);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& name) const { return values_.count(name) || flags_.count(name); }
  std::string get(const std::string& name, const std::string& fallback) const;
  int get_int(const std::string& name, int fallback) const;
  double get_double(const std::string& name, double fallback) const;
  // get_int, and UsageError "--name V is out of range [lo, hi]" outside.
  int get_int_in(const std::string& name, int fallback, int lo, int hi) const;
  bool flag(const std::string& name) const { return flags_.count(name) != 0; }
  // A value option set or removed after parsing: the per-frame copies of a
  // sequence's arguments (each output pattern expanded for the frame).
  void set(const std::string& name, const std::string& value) { values_[name] = value; }
  void unset(const std::string& name) { values_.erase(name); }

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_;
};

// One row of a command's table of options that act only beside another:
// `option` given without any of `any_of` (or, with `value`, without one of
// them set to that value) does nothing, and silently doing nothing hides a
// mistake, so it is a usage error: "--mesh-ascii has no effect without
// --mesh or --points (it writes their PLY files as ASCII)".
struct OptionNeed {
  const char* option;
  std::vector<const char*> any_of;
  const char* value;   // nullptr: any value, or a flag
  const char* effect;  // what the option does when it applies
};
void check_option_needs(const Args& args, const std::vector<OptionNeed>& table);

// The exit status paragraph of every --help.
const char* exit_codes_help();

int parse_int(const std::string& option, const std::string& text);
double parse_double(const std::string& option, const std::string& text);
// "7x5" or "7" (square) -> {w, h}.
std::pair<int, int> parse_size(const std::string& option, const std::string& text);

}  // namespace tristereo::cli
