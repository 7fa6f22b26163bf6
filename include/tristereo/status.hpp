// Errors of the public API.
//
// Every public entry point and file reader reports bad input by throwing
// tristereo::Error (never by crashing or returning garbage). The message names
// the offending value and the limit it broke; code() lets programs branch.
// Nothing the caller owns is modified when an Error is thrown.
#pragma once

#include "tristereo/export.hpp"

#include <stdexcept>
#include <string>

namespace tristereo {

enum class ErrorCode {
  kInvalidArgument,   // a parameter outside its documented range
  kSizeMismatch,      // left/right (or image/mask) sizes differ
  kUnsupportedFormat, // bit depth, channel count or file type we do not read
  kCorruptFile,       // truncated or malformed file contents
  kIoError,           // open/read/write failed at the OS level
  kNotConfigured,     // process() before configure()
  kPlatform,          // affinity, scheduling or GPIO request refused by the OS
};

TRISTEREO_API const char* error_code_name(ErrorCode code) noexcept;

class TRISTEREO_API Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace tristereo
