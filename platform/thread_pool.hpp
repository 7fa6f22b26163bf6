// A fixed pool of worker threads, one per core, optionally pinned, that runs
// one task on every worker and waits for all of them (fork-join per stage).
//
// Threading model (docs/threads.md has the long version):
// - The thread that calls start() and run() is worker 0 and does its share of
//   every run(); start(n, ...) creates only n - 1 background threads. A pool
//   that was never started (or was stopped) has size() 1 and runs tasks
//   inline on the caller.
// - With pinning, worker i is pinned to cpus[i % cpus.size()] (cpus empty =
//   available_cpus()). That includes the calling thread, whose previous
//   affinity stop() restores (when stop() is called from the same thread).
// - run() performs no heap allocation: the task is a FunctionRef to a
//   callable on the caller's stack, and hand-off is a generation counter
//   (waiting threads spin, then block on a condition variable; see
//   spin_ns()).
// - Determinism is the caller's job and is easy: give worker i a fixed band of
//   the work (split_range) and write results to disjoint memory, then the
//   output does not depend on the worker count or on scheduling.
// - start/stop/run/set_realtime must all be called from one thread (the
//   owner); run() is not reentrant (a task must not call run()).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "platform/function_ref.hpp"
#include "platform/realtime.hpp"
#include "tristereo/trace.hpp"

namespace tristereo {

class ThreadPool {
 public:
  // Upper bound on num_workers; a typo like 10000 fails cleanly instead of
  // exhausting thread limits.
  static constexpr int kMaxWorkers = 1024;

  ThreadPool();
  ~ThreadPool();  // stop()
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  // Starts num_workers workers (0 = one per entry of `cpus`, or per available
  // CPU when `cpus` is empty). A running pool is stopped first, so restarting
  // with another size or CPU list is just another start().
  // Throws Error(kInvalidArgument) for num_workers outside 0..kMaxWorkers and
  // Error(kPlatform) when `pin` and a requested CPU is not in the allowed set;
  // both are checked before anything changes, so a running pool keeps running.
  // If the OS refuses a pin or a thread anyway, every thread is stopped (the
  // pool is left stopped, size 1) and Error(kPlatform) is thrown.
  // `cpus` is ignored when `pin` is false.
  void start(int num_workers, const std::vector<int>& cpus, bool pin);

  // Joins all workers and restores the owner thread's affinity and scheduling.
  // Idempotent; never throws.
  void stop() noexcept;

  // Calls task(i) once on every worker i in [0, size()) concurrently (task(0)
  // on the calling thread) and returns when all have returned. If tasks throw,
  // the exception of the lowest-numbered failing worker is rethrown here after
  // all workers finished. Throws Error(kInvalidArgument) when called from
  // inside a task or concurrently from another thread.
  void run(FunctionRef<void(int worker)> task);

  int size() const { return size_; }
  // Each run() records a kRun span on each worker's track of `trace` (null =
  // none; not owned), numbered from 0 after trace_new_frame().
  void set_trace(FrameTrace* trace) { trace_ = trace; }
  void trace_new_frame() { run_number_ = -1; }
  // How long a waiting thread (a worker between runs, the owner at the end of
  // a run) spins before it blocks: 0.5 ms when every worker has a core of its
  // own, so a frame's back-to-back runs never pay a wake-up; 20 us when
  // workers share cores (more workers than CPUs), so spinning does not take
  // the CPU from a worker that still has work.
  std::int64_t spin_ns() const { return spin_ns_; }
  bool pinned() const { return pinned_; }

  // CPU each worker was pinned to, -1 for unpinned workers; size() entries.
  std::vector<int> worker_cpus() const { return worker_cpus_; }

  // Each worker reads its own affinity (pthread_getaffinity_np) inside a
  // run(): proof that pinning took effect, for tests and `tristereo info`.
  std::vector<std::vector<int>> read_back_worker_affinity();

  // SCHED_FIFO at `priority` for every worker (the calling thread included,
  // see realtime.hpp for why enable_realtime() alone is not enough), then
  // mlockall. All or nothing: on Error every worker's previous scheduling is
  // restored. Lasts until stop(); a restarted pool is not real-time.
  void set_realtime(int priority);

  // The CPUs a pool started from the calling thread may use: allowed_cpus(),
  // except while pools owned by this thread have pinned it, when it is the
  // set the thread had before the first of them (its own affinity is then one
  // CPU). So a second pool (a second Pipeline) configured from the same
  // thread still gets every CPU. Pins nest: stop the pools in reverse order.
  static std::vector<int> available_cpus();

  // Contiguous, balanced, deterministic bands: splits [begin, end) into
  // `parts` bands and stores band `part` in [*b, *e). The first
  // (end - begin) % parts bands are one longer; bands may be empty when
  // there are more parts than items. Throws Error(kInvalidArgument) for
  // end < begin, parts < 1, part outside [0, parts) or null outputs.
  static void split_range(int begin, int end, int parts, int part, int* b, int* e);

 private:
  // Per-worker state, one cache line each so error reporting on one worker
  // never contends with another's.
  struct alignas(64) WorkerSlot {
    std::exception_ptr error;
    std::string start_error;
  };

  void worker_main(int index, int cpu, std::uint64_t start_generation);
  template <class Ready>
  bool spin_until(Ready ready) const;
  std::uint64_t wait_for_new_generation(std::uint64_t seen);
  void wait_until_all_done();
  void run_on_this_thread(int index) noexcept;

  std::vector<std::thread> threads_;
  std::unique_ptr<WorkerSlot[]> slots_;
  int size_ = 1;
  bool pinned_ = false;
  std::int64_t spin_ns_ = 0;  // set by start() before any worker exists
  std::vector<int> worker_cpus_{-1};

  // Hand-off. task_ is written by the owner before the release increment of
  // generation_ and read by workers after their acquire load of it.
  std::mutex mutex_;
  std::condition_variable wake_cv_;
  std::condition_variable done_cv_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> pending_{0};
  std::atomic<bool> stopping_{false};
  std::atomic<bool> in_run_{false};
  const FunctionRef<void(int)>* task_ = nullptr;
  FrameTrace* trace_ = nullptr;
  int run_number_ = -1;  // written by the owner before a run is published

  // What start()/set_realtime() changed on the owner thread, for stop().
  std::thread::id owner_;
  bool owner_affinity_changed_ = false;
  std::vector<int> owner_saved_affinity_;
  bool owner_scheduling_changed_ = false;
  ThreadScheduling owner_saved_scheduling_;
  bool memory_locked_ = false;
};

}  // namespace tristereo
