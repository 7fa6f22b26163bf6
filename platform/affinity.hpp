// Pinning the calling thread to one CPU, and reading a thread's CPU set back.
//
// Failures are values, not exceptions: the thread pool turns them into
// tristereo::Error with context, other callers may just log and carry on.
#pragma once

#include <string>
#include <vector>

namespace tristereo {

// Restricts the calling thread to `cpu` (pthread_setaffinity_np). Returns
// false when the OS refuses (CPU offline, outside the cpuset cgroup or
// taskset mask, index out of range); then, if `error` is not null, it receives
// e.g. "cannot pin to CPU 7: Invalid argument (allowed CPUs: 0-1)" and the
// thread's affinity is unchanged.
bool pin_current_thread(int cpu, std::string* error);

// Restricts the calling thread to the set `cpus` (used to undo a pin).
// Same failure contract as pin_current_thread.
bool set_current_thread_affinity(const std::vector<int>& cpus, std::string* error);

// CPUs the calling thread may run on right now, ascending (empty on failure).
std::vector<int> current_thread_affinity();

}  // namespace tristereo
