// The single dispatcher: resolves a KernelChoice to a KernelSet once.
//
// Compiled into the main library without arch flags. The per-arch tables are
// filled by simd/arch_<arch>.cpp (built with their flags) the first time any
// set is asked for; which of them this CPU can run is decided here:
//   x86-64: SSE2 is the baseline of the ABI; AVX2 when xsimd's CPUID probe
//           reports it and the OS saves the YMM state (xsimd 8.1 does not look
//           at XGETBV, the compiler runtime's probe does);
//   AArch64: NEON (Advanced SIMD) is mandatory, decided at compile time;
//   ARMv7:  NEON is optional hardware: AT_HWCAP says whether this CPU has it.
// TRISTEREO_KERNELS (scalar|sse2|avx2|neon) overrides kAuto, an explicit
// choice overrides both (README.md in this folder).
#include <cstdlib>
#include <string>
#include <vector>

#if defined(TRISTEREO_SIMD_HAVE_AVX2)
#include <xsimd/xsimd.hpp>
#endif
#if defined(TRISTEREO_SIMD_HAVE_NEON) && defined(__linux__)
#include <sys/auxv.h>
#endif

#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace simd {
// Defined in simd/arch_<arch>.cpp.
void fill_kernel_set_sse2(KernelSet& set);
void fill_kernel_set_avx2(KernelSet& set);
void fill_kernel_set_neon64(KernelSet& set);
void fill_kernel_set_neon(KernelSet& set);
}  // namespace simd

namespace {

struct CompiledSet {
  KernelChoice choice;
  bool runnable;  // this CPU can execute it
  KernelSet set;
};

#if defined(TRISTEREO_SIMD_HAVE_AVX2)
bool cpu_has_avx2() {
  return xsimd::available_architectures().avx2 && __builtin_cpu_supports("avx2");
}
#endif

#if defined(TRISTEREO_SIMD_HAVE_NEON)
bool cpu_has_neon_armv7() {
#if defined(__linux__)
  constexpr unsigned long kHwcapNeon = 1ul << 12;  // HWCAP_NEON in asm/hwcap.h (ARM)
  return (getauxval(AT_HWCAP) & kHwcapNeon) != 0;
#else
  return false;  // no portable probe: keep the scalar set
#endif
}
#endif

// Best last, scalar first; built once, before any thread can race on it.
const std::vector<CompiledSet>& compiled_sets() {
  static const std::vector<CompiledSet> sets = [] {
    std::vector<CompiledSet> v;
    v.push_back({KernelChoice::kScalar, true, scalar_kernel_set()});
    auto add = [&v](KernelChoice choice, bool runnable, void (*fill)(KernelSet&)) {
      CompiledSet c{choice, runnable, KernelSet{}};
      fill(c.set);
      v.push_back(c);
    };
#if defined(TRISTEREO_SIMD_HAVE_SSE2)
    add(KernelChoice::kSse2, true, simd::fill_kernel_set_sse2);
#endif
#if defined(TRISTEREO_SIMD_HAVE_AVX2)
    add(KernelChoice::kAvx2, cpu_has_avx2(), simd::fill_kernel_set_avx2);
#endif
#if defined(TRISTEREO_SIMD_HAVE_NEON64)
    add(KernelChoice::kNeon, true, simd::fill_kernel_set_neon64);
#endif
#if defined(TRISTEREO_SIMD_HAVE_NEON)
    add(KernelChoice::kNeon, cpu_has_neon_armv7(), simd::fill_kernel_set_neon);
#endif
    (void)add;
    return v;
  }();
  return sets;
}

}  // namespace

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

std::vector<KernelChoice> compiled_kernel_sets() {
  std::vector<KernelChoice> out;
  for (const CompiledSet& c : compiled_sets()) out.push_back(c.choice);
  return out;
}

std::vector<KernelChoice> available_kernel_sets() {
  std::vector<KernelChoice> out;
  for (const CompiledSet& c : compiled_sets())
    if (c.runnable) out.push_back(c.choice);
  return out;
}

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
  const KernelChoice resolved = resolve_kernel_choice(requested);
  for (const CompiledSet& c : compiled_sets())
    if (c.choice == resolved) return c.set;
  return scalar_kernel_set();  // unreachable: resolve only returns compiled sets
}

}  // namespace tristereo
