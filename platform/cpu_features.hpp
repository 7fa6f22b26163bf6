// CPU discovery: which CPUs this thread may run on, how many are online, what
// they are called, and the "0-1,4" CPU-list syntax used by taskset, cgroups
// (cpuset.cpus) and the command line.
//
// allowed_cpus() is the set to size and pin a worker pool against: it already
// reflects taskset, cpuset cgroups (docker --cpuset-cpus, Kubernetes static CPU
// manager) and isolcpus as seen by this process. online_cpu_count() is not.
#pragma once

#include <string>
#include <vector>

namespace tristereo {

// CPUs the calling thread may run on (sched_getaffinity), ascending. Never
// empty: if the query fails, falls back to 0 .. online_cpu_count() - 1.
std::vector<int> allowed_cpus();

// CPUs online in the machine (sysconf(_SC_NPROCESSORS_ONLN)), at least 1.
int online_cpu_count();

// Human-readable CPU name: /proc/cpuinfo "model name" (x86, some ARM kernels),
// else the ARM core decoded from "CPU implementer"/"CPU part" (e.g.
// "ARM Cortex-A72"), else "Hardware", else "unknown".
std::string cpu_model_name();

// The parser behind cpu_model_name(), exposed for tests: takes the text of a
// /proc/cpuinfo file.
std::string cpu_model_name_from_cpuinfo(const std::string& cpuinfo_text);

// Largest CPU index parse_cpu_list() accepts; bounds the vectors a typo like
// "0-2000000000" could otherwise make.
constexpr int kMaxCpuIndex = 65535;

// Parses a Linux CPU list ("2,3", "0-3", "0-1,4"; surrounding whitespace and a
// trailing newline as in /sys files are ignored) into ascending unique CPU
// indices. Throws Error(kInvalidArgument) naming the bad token on an empty
// list, an empty item, a non-digit, a negative number, a reversed range or an
// index above kMaxCpuIndex.
std::vector<int> parse_cpu_list(const std::string& text);

// The inverse of parse_cpu_list for messages: {0,1,2,5} -> "0-2,5"; {} -> "none".
// Input need not be sorted; duplicates are merged.
std::string format_cpu_list(std::vector<int> cpus);

}  // namespace tristereo
