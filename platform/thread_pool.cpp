#include "platform/thread_pool.hpp"

#include <algorithm>
#include <system_error>

#include "platform/affinity.hpp"
#include "platform/clock.hpp"
#include "platform/cpu_relax.hpp"
#include "platform/cpu_features.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

// How long a waiting thread spins before it blocks on a condition variable.
// Blocking costs a futex wake-up on the next run(): tens of microseconds on
// bare metal, and up to hundreds in a VM, where the idle vCPU halts and must
// be woken by the host. Inside one frame the stages and the tritree's rounds
// follow each other with serial gaps of at most ~0.2 ms (docs/threads.md), so
// a worker that owns its core spins long enough to bridge them. A worker that
// shares its core (more workers than CPUs) spins only briefly: there its
// spinning would take the CPU from a worker that still has work.
constexpr std::int64_t kSpinOwnCoreNs = 500'000;
constexpr std::int64_t kSpinSharedCoreNs = 20'000;
// Pauses between two clock reads while spinning (a clock read costs about as
// much as a few pauses, and the deadline needs no better resolution).
constexpr int kPausesPerClockRead = 64;

// Pools pin their owner thread. What that thread could use before the first
// of its pools pinned it, and how many of its pools have it pinned now; see
// available_cpus().
thread_local std::vector<int> t_affinity_before_pools;
thread_local int t_pools_pinning_this_thread = 0;

}  // namespace

ThreadPool::ThreadPool() = default;

ThreadPool::~ThreadPool() { stop(); }

std::vector<int> ThreadPool::available_cpus() {
  return t_pools_pinning_this_thread > 0 ? t_affinity_before_pools : allowed_cpus();
}

void ThreadPool::split_range(int begin, int end, int parts, int part, int* b, int* e) {
  if (b == nullptr || e == nullptr) {
    throw Error(ErrorCode::kInvalidArgument, "split_range: null output pointer");
  }
  if (end < begin) {
    throw Error(ErrorCode::kInvalidArgument, "split_range: end " + std::to_string(end) +
                                                 " is below begin " + std::to_string(begin));
  }
  if (parts < 1 || part < 0 || part >= parts) {
    throw Error(ErrorCode::kInvalidArgument,
                "split_range: part " + std::to_string(part) + " of " + std::to_string(parts) +
                    " parts (need parts >= 1 and 0 <= part < parts)");
  }
  // 64-bit so that ranges near INT_MAX cannot overflow the products.
  const std::int64_t length = static_cast<std::int64_t>(end) - begin;
  const std::int64_t base = length / parts;
  const std::int64_t extra = length % parts;
  const std::int64_t first = begin + part * base + std::min<std::int64_t>(part, extra);
  *b = static_cast<int>(first);
  *e = static_cast<int>(first + base + (part < extra ? 1 : 0));
}

void ThreadPool::start(int num_workers, const std::vector<int>& cpus, bool pin) {
  if (in_run_.load()) {
    throw Error(ErrorCode::kInvalidArgument, "ThreadPool::start called while a run() is active");
  }
  if (num_workers < 0 || num_workers > kMaxWorkers) {
    throw Error(ErrorCode::kInvalidArgument,
                "ThreadPool: num_workers " + std::to_string(num_workers) + " is outside 0.." +
                    std::to_string(kMaxWorkers) + " (0 = one per CPU)");
  }
  // Not allowed_cpus(): while a pool's pin is in place, this thread's own
  // affinity is a single CPU.
  const std::vector<int> allowed = available_cpus();
  const std::vector<int>& requested = (pin && !cpus.empty()) ? cpus : allowed;
  if (num_workers == 0) {
    num_workers = std::min<int>(static_cast<int>(requested.size()), kMaxWorkers);
  }
  std::vector<int> plan(static_cast<size_t>(num_workers), -1);
  if (pin) {
    // Checked up front: a worker that fails to pin after others started is
    // the messy path (stop everything); most mistakes are caught here.
    for (int cpu : requested) {
      if (!std::binary_search(allowed.begin(), allowed.end(), cpu)) {
        throw Error(ErrorCode::kPlatform,
                    "ThreadPool: cannot pin a worker to CPU " + std::to_string(cpu) +
                        ": not in the CPUs this process may use (allowed CPUs: " +
                        format_cpu_list(allowed) +
                        "; set by taskset, a cpuset cgroup or the container). Pick CPUs from "
                        "that set or disable pinning");
      }
    }
    for (int i = 0; i < num_workers; ++i) plan[i] = requested[i % requested.size()];
  }

  stop();
  owner_ = std::this_thread::get_id();
  // Own core: pinned to distinct CPUs, or unpinned and no more workers than CPUs.
  std::vector<int> cores = pin ? requested : allowed;
  std::sort(cores.begin(), cores.end());
  cores.erase(std::unique(cores.begin(), cores.end()), cores.end());
  spin_ns_ = static_cast<std::size_t>(num_workers) <= cores.size() ? kSpinOwnCoreNs : kSpinSharedCoreNs;
  slots_.reset(new WorkerSlot[static_cast<size_t>(num_workers)]);

  if (pin) {
    owner_saved_affinity_ = current_thread_affinity();
    std::string error;
    if (!pin_current_thread(plan[0], &error)) {
      throw Error(ErrorCode::kPlatform, "ThreadPool: worker 0 (the calling thread): " + error);
    }
    owner_affinity_changed_ = true;
    if (t_pools_pinning_this_thread++ == 0) t_affinity_before_pools = owner_saved_affinity_;
  }

  // Workers report in (pinned or not) by counting pending_ down; start()
  // returns only when every worker is parked, so pin failures surface here.
  pending_.store(num_workers - 1);
  const std::uint64_t generation = generation_.load();
  threads_.reserve(static_cast<size_t>(num_workers - 1));
  std::string failure;
  for (int i = 1; i < num_workers; ++i) {
    try {
      threads_.emplace_back(&ThreadPool::worker_main, this, i, plan[i], generation);
    } catch (const std::system_error& e) {
      failure = "ThreadPool: cannot create worker thread " + std::to_string(i) + " of " +
                std::to_string(num_workers) + ": " + e.what();
      break;
    }
  }
  if (failure.empty()) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_cv_.wait(lock, [&] { return pending_.load() == 0; });
    for (int i = 1; i < num_workers && failure.empty(); ++i) {
      if (!slots_[i].start_error.empty()) {
        failure = "ThreadPool: worker " + std::to_string(i) + ": " + slots_[i].start_error;
      }
    }
  }
  size_ = num_workers;
  pinned_ = pin;
  worker_cpus_ = plan;
  if (!failure.empty()) {
    stop();
    throw Error(ErrorCode::kPlatform, failure);
  }
}

void ThreadPool::worker_main(int index, int cpu, std::uint64_t start_generation) {
  // Pin from the worker itself, before it touches any memory, so first-touch
  // pages of per-worker buffers land near its core.
  if (cpu >= 0) {
    std::string error;
    if (!pin_current_thread(cpu, &error)) slots_[index].start_error = error;
  }
  if (pending_.fetch_sub(1) == 1) {
    std::lock_guard<std::mutex> lock(mutex_);
    done_cv_.notify_one();
  }
  std::uint64_t seen = start_generation;
  for (;;) {
    seen = wait_for_new_generation(seen);
    if (stopping_.load(std::memory_order_acquire)) return;
    run_on_this_thread(index);
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      // Taking the mutex orders this notify after the owner's predicate check,
      // so the wake-up cannot be lost.
      std::lock_guard<std::mutex> lock(mutex_);
      done_cv_.notify_one();
    }
  }
}

template <class Ready>
bool ThreadPool::spin_until(Ready ready) const {
  const std::int64_t deadline = monotonic_ns() + spin_ns_;
  for (;;) {
    for (int i = 0; i < kPausesPerClockRead; ++i) {
      if (ready()) return true;
      cpu_relax();
    }
    if (monotonic_ns() >= deadline) return false;
  }
}

std::uint64_t ThreadPool::wait_for_new_generation(std::uint64_t seen) {
  if (spin_until([&] { return generation_.load(std::memory_order_acquire) != seen; })) {
    return generation_.load(std::memory_order_acquire);
  }
  std::unique_lock<std::mutex> lock(mutex_);
  wake_cv_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
  return generation_.load(std::memory_order_acquire);
}

void ThreadPool::wait_until_all_done() {
  if (spin_until([&] { return pending_.load(std::memory_order_acquire) == 0; })) return;
  std::unique_lock<std::mutex> lock(mutex_);
  done_cv_.wait(lock, [&] { return pending_.load(std::memory_order_acquire) == 0; });
}

void ThreadPool::run_on_this_thread(int index) noexcept {
  try {
    if (trace_ == nullptr) {
      (*task_)(index);
    } else {
      const std::int64_t t0 = monotonic_ns();
      (*task_)(index);
      trace_->record(index, TraceKind::kRun, t0, monotonic_ns(), run_number_);
    }
  } catch (...) {
    // Copying the exception_ptr may allocate; only on this error path.
    slots_[index].error = std::current_exception();
  }
}

void ThreadPool::run(FunctionRef<void(int worker)> task) {
  if (in_run_.exchange(true, std::memory_order_acquire)) {
    throw Error(ErrorCode::kInvalidArgument,
                "ThreadPool::run called from inside a task or from two threads at once "
                "(runs cannot nest)");
  }
  struct ClearFlag {
    std::atomic<bool>* flag;
    ~ClearFlag() { flag->store(false, std::memory_order_release); }
  } clear{&in_run_};

  ++run_number_;
  if (threads_.empty()) {
    const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
    task(0);
    if (trace_ != nullptr) trace_->record(0, TraceKind::kRun, t0, monotonic_ns(), run_number_);
    return;
  }
  task_ = &task;
  pending_.store(size_ - 1, std::memory_order_relaxed);
  {
    // Under the mutex so a worker between its predicate check and its wait
    // cannot miss the increment.
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_cv_.notify_all();
  run_on_this_thread(0);
  wait_until_all_done();
  task_ = nullptr;

  std::exception_ptr first;
  for (int i = 0; i < size_; ++i) {
    if (slots_[i].error && !first) first = slots_[i].error;
    slots_[i].error = nullptr;
  }
  if (first) std::rethrow_exception(first);
}

std::vector<std::vector<int>> ThreadPool::read_back_worker_affinity() {
  std::vector<std::vector<int>> result(static_cast<size_t>(size_));
  run([&](int worker) { result[worker] = current_thread_affinity(); });
  return result;
}

void ThreadPool::set_realtime(int priority) {
  validate_realtime_priority(priority);
  std::vector<ThreadScheduling> saved(static_cast<size_t>(size_));
  std::vector<std::string> errors(static_cast<size_t>(size_));
  std::vector<char> changed(static_cast<size_t>(size_), 0);
  run([&](int worker) {
    saved[worker] = current_thread_scheduling();
    try {
      set_thread_realtime(priority);
      changed[worker] = 1;
    } catch (const Error& e) {
      errors[worker] = e.what();
    }
  });
  auto undo = [&] {
    run([&](int worker) {
      if (changed[worker]) restore_thread_scheduling(saved[worker]);
    });
  };
  for (int i = 0; i < size_; ++i) {
    if (!errors[i].empty()) {
      undo();
      throw Error(ErrorCode::kPlatform, "ThreadPool worker " + std::to_string(i) + ": " + errors[i]);
    }
  }
  try {
    lock_memory();
  } catch (...) {
    undo();
    throw;
  }
  // An unstarted pool ran the task inline: the caller is the owner to restore.
  if (owner_ == std::thread::id()) owner_ = std::this_thread::get_id();
  if (!owner_scheduling_changed_) {
    owner_saved_scheduling_ = saved[0];
    owner_scheduling_changed_ = true;
  }
  memory_locked_ = true;
}

void ThreadPool::stop() noexcept {
  if (!threads_.empty()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_.store(true, std::memory_order_release);
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_cv_.notify_all();
    for (std::thread& t : threads_) t.join();
    threads_.clear();
    stopping_.store(false);
  }
  // Another thread cannot restore the owner's settings; they are per thread.
  const bool is_owner = std::this_thread::get_id() == owner_;
  if (owner_affinity_changed_ && is_owner) {
    if (!owner_saved_affinity_.empty()) set_current_thread_affinity(owner_saved_affinity_, nullptr);
    if (--t_pools_pinning_this_thread == 0) t_affinity_before_pools.clear();
  }
  if (owner_scheduling_changed_ && is_owner) restore_thread_scheduling(owner_saved_scheduling_);
  if (memory_locked_) unlock_memory();
  owner_affinity_changed_ = false;
  owner_scheduling_changed_ = false;
  memory_locked_ = false;
  size_ = 1;
  pinned_ = false;
  worker_cpus_.assign(1, -1);
}

}  // namespace tristereo
