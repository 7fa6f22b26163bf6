// One pause of a spin-wait loop: tells the core that this thread only polls
// (x86 PAUSE, ARM YIELD), so a sibling hyper-thread or the memory system is
// not starved by the loop.
#pragma once

namespace tristereo {

inline void cpu_relax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__) || defined(__arm__)
  asm volatile("yield" ::: "memory");
#endif
}

}  // namespace tristereo
