// The single dispatcher: resolves a KernelChoice to a KernelSet once.
#include <cstdlib>
#include <string>

#include "src/kernels/kernel_set.hpp"
#include "src/kernels/dispatch.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

const char* to_string(KernelChoice k) {
  switch (k) {
    case KernelChoice::kAuto: return "auto";
    case KernelChoice::kScalar: return "scalar";
    case KernelChoice::kSse2: return "sse2";
    case KernelChoice::kAvx2: return "avx2";
    case KernelChoice::kNeon: return "neon";
  }
  return "?";
}

KernelChoice parse_kernel_choice(const std::string& s) {
  for (KernelChoice k : {KernelChoice::kAuto, KernelChoice::kScalar, KernelChoice::kSse2,
                         KernelChoice::kAvx2, KernelChoice::kNeon}) {
    if (s == to_string(k)) return k;
  }
  throw Error(ErrorCode::kInvalidArgument,
              "unknown kernel set '" + s + "' (expected auto, scalar, sse2, avx2 or neon)");
}

std::vector<KernelChoice> compiled_kernel_sets() { return {KernelChoice::kScalar}; }
std::vector<KernelChoice> available_kernel_sets() { return {KernelChoice::kScalar}; }

KernelChoice resolve_kernel_choice(KernelChoice requested) {
  if (requested == KernelChoice::kAuto) {
    if (const char* env = std::getenv("TRISTEREO_KERNELS")) {
      if (*env) requested = parse_kernel_choice(env);
    }
  }
  if (requested == KernelChoice::kAuto) return available_kernel_sets().back();
  for (KernelChoice k : available_kernel_sets())
    if (k == requested) return k;
  throw Error(ErrorCode::kInvalidArgument,
              std::string("kernel set '") + to_string(requested) +
                  "' is not compiled into this build or not supported by this CPU");
}

const KernelSet& kernel_set_for(KernelChoice requested) {
  (void)resolve_kernel_choice(requested);
  return scalar_kernel_set();
}

}  // namespace tristereo
