// Real-time options for the frame loop on a robot computer: SCHED_FIFO for the
// threads that process frames, and all memory locked so a page fault never
// lands inside a frame.
//
// Scheduling is per thread in Linux and a new thread inherits its creator's
// policy at creation only. Worker threads of a ThreadPool already exist when
// the caller decides to go real-time, so use ThreadPool::set_realtime() (which
// applies set_thread_realtime on every worker, the caller included) rather
// than enable_realtime() alone, which covers the calling thread only.
//
// Permission: SCHED_FIFO needs root, CAP_SYS_NICE or RLIMIT_RTPRIO >= priority;
// mlockall needs CAP_IPC_LOCK or an RLIMIT_MEMLOCK above the process size.
// Refusals throw Error(kPlatform) with the fix in the message.
#pragma once

namespace tristereo {

// A thread's scheduling policy and static priority, to restore it later.
struct ThreadScheduling {
  int policy = 0;    // SCHED_OTHER, SCHED_FIFO, ...
  int priority = 0;  // sched_priority (0 for SCHED_OTHER)
};

// Highest SCHED_FIFO priority (99 on Linux). Valid priorities are 1..this.
int max_realtime_priority();

// Throws Error(kInvalidArgument) unless 1 <= priority <= max_realtime_priority().
void validate_realtime_priority(int priority);

ThreadScheduling current_thread_scheduling();

// Puts the calling thread under SCHED_FIFO at `priority`. Throws
// Error(kInvalidArgument) for a bad priority, Error(kPlatform) when refused
// (then the thread's scheduling is unchanged).
void set_thread_realtime(int priority);

// Best effort: puts the calling thread back to `saved` (e.g. on an error path).
void restore_thread_scheduling(const ThreadScheduling& saved) noexcept;

// mlockall(MCL_CURRENT | MCL_FUTURE). Throws Error(kPlatform) when refused.
void lock_memory();

// munlockall(); best effort.
void unlock_memory() noexcept;

// set_thread_realtime(priority) for the calling thread, then lock_memory().
// If locking fails the thread's scheduling is restored before the Error
// propagates, so a refused call changes nothing.
void enable_realtime(int priority);

}  // namespace tristereo
