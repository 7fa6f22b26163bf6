// Which kernel set (scalar or a SIMD instruction set) the integer path uses.
//
// The choice is made once, at Pipeline::configure. kAuto takes the best set
// the running CPU supports (run-time detection on x86, compile-time on ARM);
// the environment variable TRISTEREO_KERNELS (scalar|sse2|avx2|neon) overrides
// kAuto, and an explicit choice overrides both. Asking for a set that is not
// compiled in or not supported by this CPU throws Error(kInvalidArgument).
#pragma once

#include "tristereo/export.hpp"

#include <string>
#include <vector>

namespace tristereo {

enum class KernelChoice { kAuto, kScalar, kSse2, kAvx2, kNeon };

TRISTEREO_API const char* to_string(KernelChoice k);
TRISTEREO_API KernelChoice parse_kernel_choice(const std::string& s);  // "auto", "scalar", ...

// Sets compiled into this binary, best last (always starts with "scalar").
TRISTEREO_API std::vector<KernelChoice> compiled_kernel_sets();
// Compiled sets this CPU can run.
TRISTEREO_API std::vector<KernelChoice> available_kernel_sets();
// What kAuto resolves to here (after TRISTEREO_KERNELS).
TRISTEREO_API KernelChoice resolve_kernel_choice(KernelChoice requested);

}  // namespace tristereo
