// Library errors in the words of the command line.
//
// The library names parameters by their fields (num_disp, cost.window_w): the
// right words for a C++ caller, the wrong ones for someone who typed
// --ndisp. The command line keeps the library's messages and translates
// them here, through one table from field to option, into UsageError
// (exit 2).
#pragma once

#include <functional>
#include <string>

#include "apps/cli_args.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

// "num_disp = 0 is out of range [1, 256]" -> "--ndisp 0 is out of range [1, 256]".
// A message naming no known field is kept, prefixed by "invalid parameter: ".
std::string option_message(const std::string& library_message);

// Runs `fn`; a tristereo::Error of kind kInvalidArgument it throws becomes a
// UsageError: with `option` ("--kernels") as prefix when given, else
// translated by option_message. Other errors pass unchanged.
void as_usage_error(const char* option, const std::function<void()>& fn);

// "write_disparity: negative disparity ..." -> "negative disparity ...": drops
// a leading library function name from a message.
std::string without_function_prefix(const std::string& message);

}  // namespace tristereo::cli
