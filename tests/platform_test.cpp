// CPU discovery, CPU lists, pinning of the calling thread, clocks, real-time
// options and FunctionRef.
#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "platform/affinity.hpp"
#include "platform/clock.hpp"
#include "platform/cpu_features.hpp"
#include "platform/function_ref.hpp"
#include "platform/huge_pages.hpp"
#include "platform/realtime.hpp"
#include "support/keep_alive.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The value of "Key:" in /proc/self/status.
std::string proc_status_field(const std::string& key) {
  std::istringstream in(read_file("/proc/self/status"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size() + 1, key + ":") == 0) {
      std::string value = line.substr(key.size() + 1);
      return value.substr(value.find_first_not_of(" \t"));
    }
  }
  return "";
}

TEST(CpuList, ParsesTheLinuxSyntax) {
  EXPECT_EQ(parse_cpu_list("2,3"), (std::vector<int>{2, 3}));
  EXPECT_EQ(parse_cpu_list("0-3"), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(parse_cpu_list("0-1,4"), (std::vector<int>{0, 1, 4}));
  EXPECT_EQ(parse_cpu_list("7"), (std::vector<int>{7}));
  EXPECT_EQ(parse_cpu_list("5,1-2,2,0\n"), (std::vector<int>{0, 1, 2, 5}));
  EXPECT_EQ(parse_cpu_list(" 3 - 4 , 9 "), (std::vector<int>{3, 4, 9}));
  EXPECT_EQ(parse_cpu_list("6-6"), (std::vector<int>{6}));
}

TEST(CpuList, RejectsGarbageWithTheBadToken) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "empty"},       {"  \n", "empty"},        {"1,,2", "empty item"},
      {"1,", "empty item"}, {",1", "empty item"},     {"-1", "negative"},
      {"2--1", "negative"}, {"a", "'a'"},             {"1-x", "'x'"},
      {"3-1", "reversed"},  {"0-99999999", "exceeds"}, {"1.5", "'1.5'"},
      {"1-", "empty CPU number"}};
  for (const auto& c : cases) {
    try {
      parse_cpu_list(c.first);
      FAIL() << "accepted '" << c.first << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      EXPECT_NE(std::string(e.what()).find(c.second), std::string::npos)
          << "'" << c.first << "': " << e.what();
    }
  }
}

TEST(CpuList, FormatIsTheInverseOfParse) {
  EXPECT_EQ(format_cpu_list({0, 1, 2, 5}), "0-2,5");
  EXPECT_EQ(format_cpu_list({5, 1, 0, 1}), "0-1,5");
  EXPECT_EQ(format_cpu_list({}), "none");
  EXPECT_EQ(format_cpu_list({3}), "3");
  for (const char* text : {"0", "0-3", "0-1,4", "1,3,5-9,11"}) {
    EXPECT_EQ(format_cpu_list(parse_cpu_list(text)), text);
  }
}

TEST(CpuFeatures, AllowedCpusMatchTheKernelsView) {
  const std::vector<int> cpus = allowed_cpus();
  ASSERT_FALSE(cpus.empty());
  // /proc/self/status describes the main thread, which runs this test.
  EXPECT_EQ(cpus, parse_cpu_list(proc_status_field("Cpus_allowed_list")));
}

TEST(CpuFeatures, OnlineCountMatchesSysfs) {
  const std::string online = read_file("/sys/devices/system/cpu/online");
  if (online.empty()) GTEST_SKIP() << "no /sys/devices/system/cpu/online";
  EXPECT_EQ(online_cpu_count(), static_cast<int>(parse_cpu_list(online).size()));
}

TEST(CpuFeatures, ModelNameFromCpuinfoSamples) {
  EXPECT_EQ(cpu_model_name_from_cpuinfo("processor\t: 0\nvendor_id\t: AuthenticAMD\n"
                                        "model name\t: AMD EPYC 7B13\nflags\t: sse2\n"),
            "AMD EPYC 7B13");
  // Raspberry Pi 4, 64-bit kernel: no model name, decode implementer/part.
  const char* pi4 =
      "processor\t: 0\nBogoMIPS\t: 108.00\nFeatures\t: fp asimd\nCPU implementer\t: 0x41\n"
      "CPU architecture: 8\nCPU variant\t: 0x0\nCPU part\t: 0xd08\nCPU revision\t: 3\n\n"
      "Hardware\t: BCM2835\nModel\t: Raspberry Pi 4 Model B Rev 1.4\n";
  EXPECT_EQ(cpu_model_name_from_cpuinfo(pi4), "ARM Cortex-A72 (BCM2835)");
  EXPECT_EQ(cpu_model_name_from_cpuinfo("CPU implementer\t: 0x4e\nCPU part\t: 0x004\n"),
            "NVIDIA Carmel");
  EXPECT_EQ(cpu_model_name_from_cpuinfo("CPU implementer\t: 0x51\nCPU part\t: 0x802\n"),
            "ARM implementer 0x51 part 0x802");
  EXPECT_EQ(cpu_model_name_from_cpuinfo("Hardware\t: Freescale i.MX8\n"), "Freescale i.MX8");
  EXPECT_EQ(cpu_model_name_from_cpuinfo(""), "unknown");
  EXPECT_EQ(cpu_model_name_from_cpuinfo("model name\t:\n"), "unknown");
}

TEST(CpuFeatures, ModelNameOfThisMachine) {
  EXPECT_EQ(cpu_model_name(), cpu_model_name_from_cpuinfo(read_file("/proc/cpuinfo")));
  EXPECT_FALSE(cpu_model_name().empty());
}

TEST(Affinity, PinsTheCallingThreadToEachAllowedCpu) {
  const std::vector<int> allowed = allowed_cpus();
  for (int cpu : allowed) {
    std::vector<int> seen;
    bool ok = false;
    std::string error;
    // In a helper thread, so the test runner's own affinity is untouched.
    std::thread([&] {
      ok = pin_current_thread(cpu, &error);
      seen = current_thread_affinity();
    }).join();
    EXPECT_TRUE(ok) << error;
    EXPECT_EQ(seen, std::vector<int>{cpu});
  }
  EXPECT_EQ(current_thread_affinity(), allowed);
}

TEST(Affinity, RefusedPinExplainsAndChangesNothing) {
  const std::vector<int> allowed = allowed_cpus();
  const std::string allowed_text = "(allowed CPUs: " + format_cpu_list(allowed) + ")";
  struct Case {
    int cpu;
    std::string reason;
  };
  const Case cases[] = {{allowed.back() + 1, std::strerror(EINVAL)},
                        {1000000, "out of range"},
                        {-1, "out of range"}};
  for (const Case& c : cases) {
    std::string error;
    EXPECT_FALSE(pin_current_thread(c.cpu, &error));
    EXPECT_EQ(error.rfind("cannot pin to CPU " + std::to_string(c.cpu) + ": ", 0), 0u) << error;
    EXPECT_NE(error.find(c.reason), std::string::npos) << error;
    EXPECT_NE(error.find(allowed_text), std::string::npos) << error;
    EXPECT_EQ(current_thread_affinity(), allowed);
  }
  EXPECT_FALSE(pin_current_thread(-1, nullptr));  // no error text wanted
}

TEST(Affinity, SetAndRestoreASet) {
  const std::vector<int> allowed = allowed_cpus();
  std::vector<int> during;
  std::vector<int> after;
  std::thread([&] {
    EXPECT_TRUE(set_current_thread_affinity({allowed.front()}, nullptr));
    during = current_thread_affinity();
    EXPECT_TRUE(set_current_thread_affinity(allowed, nullptr));
    after = current_thread_affinity();
  }).join();
  EXPECT_EQ(during, std::vector<int>{allowed.front()});
  EXPECT_EQ(after, allowed);
  std::string error;
  EXPECT_FALSE(set_current_thread_affinity({}, &error));
  EXPECT_NE(error.find("empty"), std::string::npos) << error;
}

TEST(Clock, MonotonicAndCpuClocksAdvance) {
  const std::int64_t wall0 = monotonic_ns();
  const std::int64_t thread0 = thread_cpu_ns();
  const std::int64_t process0 = process_cpu_ns();
  ASSERT_GT(wall0, 0);
  // Burn CPU until the wall clock has moved 2 ms (a loop bound, not an assertion).
  volatile std::uint64_t sink = 0;
  std::int64_t previous = wall0;
  while (monotonic_ns() - wall0 < 2000000) {
    for (int i = 0; i < 1000; ++i) sink = sink + static_cast<std::uint64_t>(i);
    const std::int64_t now = monotonic_ns();
    ASSERT_GE(now, previous);
    previous = now;
  }
  const std::int64_t thread1 = thread_cpu_ns();
  EXPECT_GT(thread1, thread0);
  EXPECT_GT(process_cpu_ns(), process0);
  // The process has spent at least what this thread spent. The thread clock is
  // read first, in its own statement: the order in which a compiler evaluates
  // the arguments of one call is unspecified (clang reads left to right, GCC
  // right to left), and the clock read second has run longer.
  const std::int64_t thread2 = thread_cpu_ns();
  const std::int64_t process2 = process_cpu_ns();
  EXPECT_GE(process2, thread2);
}

TEST(Clock, PeakRssSeesTouchedMemory) {
  constexpr size_t kBytes = 64u << 20;
  std::vector<char> block(kBytes);
  for (size_t i = 0; i < kBytes; i += 4096) block[i] = static_cast<char>(i);
  test::keep_alive(block.data());  // else clang drops the unobserved block
  EXPECT_GE(peak_rss_bytes(), static_cast<std::int64_t>(kBytes));
  // Same high-water mark the kernel shows as VmHWM (KiB), give or take the
  // kernel's batched RSS accounting.
  const std::int64_t hwm = std::stoll(proc_status_field("VmHWM")) * 1024;
  EXPECT_NEAR(static_cast<double>(peak_rss_bytes()), static_cast<double>(hwm), 4.0 * (1 << 20));
}

TEST(Realtime, PriorityRange) {
  EXPECT_EQ(max_realtime_priority(), sched_get_priority_max(SCHED_FIFO));
  EXPECT_NO_THROW(validate_realtime_priority(1));
  EXPECT_NO_THROW(validate_realtime_priority(max_realtime_priority()));
  for (int bad : {0, -1, max_realtime_priority() + 1}) {
    try {
      validate_realtime_priority(bad);
      FAIL() << bad;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      const std::string message = e.what();
      EXPECT_NE(message.find("priority " + std::to_string(bad) + " is outside 1.." +
                             std::to_string(max_realtime_priority())),
                std::string::npos)
          << message;
    }
  }
  EXPECT_THROW(set_thread_realtime(0), Error);
  EXPECT_THROW(enable_realtime(1000), Error);
}

#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

TEST(Realtime, EnableRealtimeSucceedsOrExplains) {
  if (kSanitized) GTEST_SKIP() << "mlockall would try to lock the sanitizer's shadow memory";
  ThreadScheduling before;
  ThreadScheduling after;
  bool applied = false;
  std::string message;
  // In a helper thread so the runner's main thread keeps its scheduling.
  std::thread([&] {
    before = current_thread_scheduling();
    try {
      enable_realtime(5);
      applied = true;
    } catch (const Error& e) {
      message = e.what();
      EXPECT_EQ(e.code(), ErrorCode::kPlatform);
    }
    after = current_thread_scheduling();
    if (applied) restore_thread_scheduling(before);
  }).join();
  unlock_memory();
  if (applied) {
    EXPECT_EQ(after.policy, SCHED_FIFO);
    EXPECT_EQ(after.priority, 5);
  } else {
    EXPECT_TRUE(message.find("CAP_SYS_NICE") != std::string::npos ||
                message.find("CAP_IPC_LOCK") != std::string::npos)
        << message;
    EXPECT_EQ(after.policy, before.policy);
    EXPECT_EQ(after.priority, before.priority);
  }
}

int add_one(int x) { return x + 1; }

TEST(FunctionRef, CallsWithoutCopyingTheCallable) {
  int calls = 0;
  auto counter = [&calls](int x) { return x + ++calls; };
  FunctionRef<int(int)> ref(counter);
  EXPECT_EQ(ref(10), 11);
  EXPECT_EQ(ref(10), 12);
  EXPECT_EQ(calls, 2);
  FunctionRef<int(int)> copy = ref;  // refers to the same lambda
  EXPECT_EQ(copy(0), 3);
  FunctionRef<int(int)> fn(&add_one);
  EXPECT_EQ(fn(41), 42);
  struct Mutable {
    int state = 0;
    void operator()(int x) { state += x; }
  } m;
  FunctionRef<void(int)> mutating(m);
  mutating(4);
  mutating(5);
  EXPECT_EQ(m.state, 9);
}

// The huge-page default reads the balloon's feature bits: only bit 5 (free
// page reporting) of a bound virtio balloon device turns huge pages off.
TEST(HugePages, OffOnlyForABalloonThatReportsFreePages) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("tristereo_sysfs_" + std::to_string(::getpid()));
  fs::remove_all(root);
  EXPECT_FALSE(balloon_reports_free_pages(root.string()));  // no /sys at all
  const fs::path driver = root / "bus" / "virtio" / "drivers" / "virtio_balloon";
  fs::create_directories(driver / "virtio3");
  std::ofstream(driver / "bind") << "";
  EXPECT_FALSE(balloon_reports_free_pages(root.string()));  // a device without features
  const auto features = [&](const std::string& bits) { std::ofstream(driver / "virtio3" / "features") << bits << "\n"; };
  features("0110000000000000000000000000000010000000000000000000000000000000");  // stats, deflate on OOM
  EXPECT_FALSE(balloon_reports_free_pages(root.string()));
  features("0110010100000000000000000000000010000000000000000000000000000000");  // + free page reporting
  EXPECT_TRUE(balloon_reports_free_pages(root.string()));
  features("01100");  // too short to hold bit 5
  EXPECT_FALSE(balloon_reports_free_pages(root.string()));
  fs::remove_all(root);
  // This process's own policy says why, whichever it is.
  EXPECT_FALSE(huge_page_policy().reason.empty());
}

}  // namespace
}  // namespace tristereo
