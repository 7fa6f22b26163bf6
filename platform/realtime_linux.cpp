#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "platform/realtime.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

int max_realtime_priority() {
  const int max = sched_get_priority_max(SCHED_FIFO);
  return max > 0 ? max : 99;
}

void validate_realtime_priority(int priority) {
  const int min = sched_get_priority_min(SCHED_FIFO) > 0 ? sched_get_priority_min(SCHED_FIFO) : 1;
  const int max = max_realtime_priority();
  if (priority < min || priority > max) {
    throw Error(ErrorCode::kInvalidArgument,
                "real-time priority " + std::to_string(priority) + " is outside " +
                    std::to_string(min) + ".." + std::to_string(max) + " (SCHED_FIFO)");
  }
}

ThreadScheduling current_thread_scheduling() {
  ThreadScheduling s;
  sched_param param{};
  if (pthread_getschedparam(pthread_self(), &s.policy, &param) == 0) {
    s.priority = param.sched_priority;
  }
  return s;
}

void set_thread_realtime(int priority) {
  validate_realtime_priority(priority);
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) return;
  std::string message = "cannot set SCHED_FIFO priority " + std::to_string(priority) + ": " +
                        std::strerror(rc);
  if (rc == EPERM) {
    message +=
        "; real-time scheduling needs root or CAP_SYS_NICE / RLIMIT_RTPRIO >= " +
        std::to_string(priority) +
        ": try `sudo setcap cap_sys_nice,cap_ipc_lock+ep build/tristereo` or `ulimit -r " +
        std::to_string(priority) +
        "` (rtprio in /etc/security/limits.conf); in a container add --cap-add=SYS_NICE, and "
        "with RT group scheduling the cgroup needs a cpu.rt_runtime_us budget";
  }
  throw Error(ErrorCode::kPlatform, message);
}

void restore_thread_scheduling(const ThreadScheduling& saved) noexcept {
  sched_param param{};
  param.sched_priority = saved.priority;
  pthread_setschedparam(pthread_self(), saved.policy, &param);
}

void lock_memory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return;
  const int err = errno;
  std::string message = std::string("cannot lock memory (mlockall): ") + std::strerror(err);
  if (err == EPERM || err == ENOMEM) {
    message +=
        "; locking needs root or CAP_IPC_LOCK, or an RLIMIT_MEMLOCK above the process size: "
        "try `sudo setcap cap_sys_nice,cap_ipc_lock+ep build/tristereo` or `ulimit -l unlimited` "
        "(memlock in /etc/security/limits.conf)";
  }
  throw Error(ErrorCode::kPlatform, message);
}

void unlock_memory() noexcept { munlockall(); }

void enable_realtime(int priority) {
  const ThreadScheduling saved = current_thread_scheduling();
  set_thread_realtime(priority);
  try {
    lock_memory();
  } catch (...) {
    restore_thread_scheduling(saved);
    throw;
  }
}

}  // namespace tristereo
