// What every tristereo fuzz harness shares: a private scratch folder for the
// file readers (they take paths), and the rule that a library call may fail
// only with tristereo::Error. Anything else (another exception, a sanitizer
// report, a failed check) aborts, which libFuzzer reports as a crash.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "tristereo/status.hpp"

namespace tristereo::fuzz {

// A folder of this process alone, removed with everything in it at exit:
// mkdtemp under $TRISTEREO_FUZZ_TMPDIR if set, else /dev/shm if writable,
// else $TMPDIR or /tmp.
const std::string& scratch_dir();

// Writes bytes to scratch_dir()/name (replacing it) and returns the path.
std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size);
inline std::string write_scratch(const std::string& name, const std::vector<std::uint8_t>& b) {
  return write_scratch(name, b.data(), b.size());
}

// Prints "fuzz check failed: <what>" and aborts.
[[noreturn]] void fail(const std::string& what);
#define TRISTEREO_FUZZ_CHECK(cond, what)                       \
  do {                                                          \
    if (!(cond)) ::tristereo::fuzz::fail(std::string(#cond ": ") + (what)); \
  } while (0)

// Runs fn(); returns true when it returned, false when it threw
// tristereo::Error; aborts on any other exception.
template <typename Fn>
bool library_call(const char* what, Fn&& fn) {
  try {
    fn();
    return true;
  } catch (const Error&) {
    return false;
  } catch (const std::exception& e) {
    fail(std::string(what) + " threw a non-library exception: " + e.what());
  } catch (...) {
    fail(std::string(what) + " threw an unknown exception");
  }
}

}  // namespace tristereo::fuzz
