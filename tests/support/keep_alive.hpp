// An optimisation barrier for tests that measure allocations or memory.
//
// Since C++14 a compiler may drop a new/delete pair whose memory is never
// observed, and clang does: a test that allocates 64 MiB, writes it and frees
// it, then checks the resident set size, measures nothing under clang -O2.
// keep_alive(p) tells the compiler that p (and the memory behind it) is used
// here, which costs nothing at run time.
#pragma once

namespace tristereo::test {

inline void keep_alive(const void* p) { asm volatile("" : : "r"(p) : "memory"); }

}  // namespace tristereo::test
