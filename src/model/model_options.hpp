// The model's options, one table for every interface.
//
// The command line (`tristereo match --model-option ...`) and the Python
// module (`Pipeline(..., keyword=...)`) both build their StereoParams from
// this table: the same names (the keyword is the option with '-' -> '_'),
// the same parsing of values, the same defaults and range checks
// (validate_params()), the same dependent defaults and the same messages,
// each naming the option as that interface spells it. The command line's
// help text for these options is generated from it too, so no interface can
// offer an option, a default or a range the others do not.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "tristereo/params.hpp"

namespace tristereo {

enum class ModelOptionKind {
  kInt,      // an integer
  kDecimal,  // a decimal number stored in tenths (psnr)
  kSize,     // "W" or "WxH" (Python: an int or a (w, h) pair)
  kChoice,   // one of `choices`
  kFlag,     // present or not (Python: a bool)
};

struct ModelOption {
  const char* name;     // the command line's option without "--": "lr-max-diff"
  const char* keyword;  // the Python keyword: "lr_max_diff" ("lambda_q4": `lambda` is reserved in Python)
  ModelOptionKind kind;
  const char* metavar;  // in the help: "Q4", "WxH", "ad|census|ad_census"
  // The accepted values: kInt the value, kSize each side, kDecimal in tenths.
  // Where other options narrow it (min-area, dmin, p2), this is the widest
  // and `narrowed` says so; validate_params() applies the narrower bound.
  long long lo, hi;
  bool narrowed;
  const char* choices;  // kChoice: "a|b|c"
  const char* help;     // what it does; the range, default and paper value are appended
  // Set only in some models: the option named here has one of these values
  // ("dp", "ad|ad_census", or "!-1" for any value but -1). nullptr: always.
  const char* needs_option;
  const char* needs_values;
  // The validate_params() fields this option sets, with the part each is:
  // "cost.window_w=width;cost.window_h=height" (messages name the option).
  const char* fields;
  // The value in `p` as text, as the command line takes it ("3x3", "44.5",
  // "census"; flags "1" or "0").
  std::string (*get)(const StereoParams& p);
  // Parses the text into `p`; throws Error(kInvalidArgument) naming `shown`.
  void (*set)(StereoParams& p, const std::string& text, const std::string& shown);
};

// Every model option, in the order the help lists them (mode first: it sets
// the starting point of the others).
const std::vector<ModelOption>& model_options();
const ModelOption* find_model_option(const std::string& name);          // by command-line name
const ModelOption* find_model_option_keyword(const std::string& keyword);  // by Python keyword

// How messages spell an option: "--lambda" or "lambda_q4".
enum class OptionSpelling { kCommandLine, kPython };
std::string option_shown(const ModelOption& o, OptionSpelling s);

struct GivenOption {
  const ModelOption* option;
  std::string text;  // the value as the command line takes it ("" for a flag)
};

// The parameters the given options describe: `mode` first, then the others
// over it; the left-right source defaults to mirror with the row DP (it keeps
// no summed costs); validate_params() last. With `refuse_without_effect`, an
// option that the chosen model does not use (lambda with the path optimizer,
// census with the ad cost...) is an error instead of doing nothing. Throws
// Error(kInvalidArgument) with the option named as `spelling` spells it.
StereoParams model_params(const std::vector<GivenOption>& given, OptionSpelling spelling,
                          bool refuse_without_effect);

// A validate_params() message ("dp.lambda_q4 = -1 is out of range [0, 32000]")
// with the field replaced by the option ("--lambda -1 is out of range ...");
// messages naming no option's field are returned unchanged.
std::string name_options_in(const std::string& message, OptionSpelling spelling);

// The "  --name METAVAR   help, range (default X; paper Y)" lines of the
// command line's help, one entry per option of the table.
std::string model_options_help();

}  // namespace tristereo
