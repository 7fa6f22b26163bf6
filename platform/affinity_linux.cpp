#include <pthread.h>
#include <sched.h>

#include <cerrno>
#include <cstring>

#include "platform/affinity.hpp"
#include "platform/cpu_features.hpp"

namespace tristereo {

namespace {

// Owns a dynamically sized cpu_set_t (CPU_ALLOC), big enough for `max_cpu`.
class CpuMask {
 public:
  explicit CpuMask(int max_cpu) {
    bits_ = CPU_SETSIZE;
    while (bits_ <= max_cpu) bits_ *= 2;
    set_ = CPU_ALLOC(bits_);
    bytes_ = CPU_ALLOC_SIZE(bits_);
    if (set_ != nullptr) CPU_ZERO_S(bytes_, set_);
  }
  ~CpuMask() {
    if (set_ != nullptr) CPU_FREE(set_);
  }
  CpuMask(const CpuMask&) = delete;
  CpuMask& operator=(const CpuMask&) = delete;

  bool ok() const { return set_ != nullptr; }
  void add(int cpu) { CPU_SET_S(cpu, bytes_, set_); }
  cpu_set_t* set() { return set_; }
  size_t bytes() const { return bytes_; }

 private:
  int bits_ = 0;
  size_t bytes_ = 0;
  cpu_set_t* set_ = nullptr;
};

bool report(std::string* error, const std::string& what, const std::string& why) {
  if (error != nullptr) {
    *error = "cannot pin to " + what + ": " + why + " (allowed CPUs: " +
             format_cpu_list(current_thread_affinity()) + ")";
  }
  return false;
}

}  // namespace

bool set_current_thread_affinity(const std::vector<int>& cpus, std::string* error) {
  const std::string what = cpus.size() == 1 ? "CPU " + std::to_string(cpus[0])
                                            : "CPUs " + format_cpu_list(cpus);
  if (cpus.empty()) return report(error, what, "empty CPU set");
  int max_cpu = 0;
  for (int cpu : cpus) {
    // Beyond kMaxCpuIndex no machine has the CPU; refuse before sizing a mask for it.
    if (cpu < 0 || cpu > kMaxCpuIndex) {
      return report(error, what, "CPU index out of range 0.." + std::to_string(kMaxCpuIndex));
    }
    if (cpu > max_cpu) max_cpu = cpu;
  }
  CpuMask mask(max_cpu);
  if (!mask.ok()) return report(error, what, std::strerror(ENOMEM));
  for (int cpu : cpus) mask.add(cpu);
  const int rc = pthread_setaffinity_np(pthread_self(), mask.bytes(), mask.set());
  if (rc != 0) return report(error, what, std::strerror(rc));
  return true;
}

bool pin_current_thread(int cpu, std::string* error) {
  return set_current_thread_affinity(std::vector<int>{cpu}, error);
}

std::vector<int> current_thread_affinity() {
  std::vector<int> cpus;
  for (int bits = CPU_SETSIZE; bits <= (1 << 20); bits *= 2) {
    CpuMask mask(bits - 1);
    if (!mask.ok()) return {};
    const int rc = pthread_getaffinity_np(pthread_self(), mask.bytes(), mask.set());
    if (rc == 0) {
      for (int cpu = 0; cpu < bits; ++cpu) {
        if (CPU_ISSET_S(cpu, mask.bytes(), mask.set())) cpus.push_back(cpu);
      }
      return cpus;
    }
    if (rc != EINVAL) return {};
  }
  return {};
}

}  // namespace tristereo
