#include "platform/text_util.hpp"
#include "platform/cpu_features.hpp"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "tristereo/status.hpp"

namespace tristereo {

namespace {

// The kernel accepts any mask size that covers its nr_cpu_ids; start with the
// glibc default and grow on EINVAL so machines with > 1024 CPUs still work.
bool query_affinity(std::vector<int>* out) {
  for (int bits = CPU_SETSIZE; bits <= (1 << 20); bits *= 2) {
    cpu_set_t* set = CPU_ALLOC(bits);
    if (set == nullptr) return false;
    const size_t bytes = CPU_ALLOC_SIZE(bits);
    CPU_ZERO_S(bytes, set);
    if (sched_getaffinity(0, bytes, set) == 0) {
      out->clear();
      for (int cpu = 0; cpu < bits; ++cpu) {
        if (CPU_ISSET_S(cpu, bytes, set)) out->push_back(cpu);
      }
      CPU_FREE(set);
      return true;
    }
    CPU_FREE(set);
    if (errno != EINVAL) return false;
  }
  return false;
}

[[noreturn]] void throw_bad_list(const std::string& text, const std::string& why) {
  throw Error(ErrorCode::kInvalidArgument,
              "invalid CPU list '" + text + "': " + why +
                  " (expected e.g. \"2,3\", \"0-3\" or \"0-1,4\")");
}

int parse_cpu_index(const std::string& token, const std::string& text) {
  if (token.empty()) throw_bad_list(text, "empty CPU number");
  if (token[0] == '-') throw_bad_list(text, "negative CPU number '" + token + "'");
  long value = 0;
  for (char c : token) {
    if (!std::isdigit(static_cast<unsigned char>(c))) {
      throw_bad_list(text, "'" + token + "' is not a CPU number");
    }
    value = value * 10 + (c - '0');
    if (value > kMaxCpuIndex) {
      throw_bad_list(text, "CPU " + token + " exceeds the limit " + std::to_string(kMaxCpuIndex));
    }
  }
  return static_cast<int>(value);
}

// Decodes the cores robot boards actually ship (Raspberry Pi, Jetson, Rockchip,
// i.MX); anything else is printed as raw implementer/part numbers.
std::string arm_core_name(unsigned long implementer, unsigned long part) {
  struct Core {
    unsigned long implementer;
    unsigned long part;
    const char* name;
  };
  static const Core kCores[] = {
      {0x41, 0xb76, "ARM1176"},          {0x41, 0xc07, "ARM Cortex-A7"},
      {0x41, 0xc08, "ARM Cortex-A8"},    {0x41, 0xc09, "ARM Cortex-A9"},
      {0x41, 0xc0f, "ARM Cortex-A15"},   {0x41, 0xd03, "ARM Cortex-A53"},
      {0x41, 0xd04, "ARM Cortex-A35"},   {0x41, 0xd05, "ARM Cortex-A55"},
      {0x41, 0xd07, "ARM Cortex-A57"},   {0x41, 0xd08, "ARM Cortex-A72"},
      {0x41, 0xd09, "ARM Cortex-A73"},   {0x41, 0xd0a, "ARM Cortex-A75"},
      {0x41, 0xd0b, "ARM Cortex-A76"},   {0x41, 0xd0c, "ARM Neoverse-N1"},
      {0x41, 0xd41, "ARM Cortex-A78"},   {0x41, 0xd42, "ARM Cortex-A78AE"},
      {0x41, 0xd44, "ARM Cortex-X1"},    {0x41, 0xd46, "ARM Cortex-A510"},
      {0x41, 0xd47, "ARM Cortex-A710"},  {0x41, 0xd4b, "ARM Cortex-A78C"},
      {0x4e, 0x003, "NVIDIA Denver 2"},  {0x4e, 0x004, "NVIDIA Carmel"},
  };
  for (const Core& c : kCores) {
    if (c.implementer == implementer && c.part == part) return c.name;
  }
  std::ostringstream os;
  os << "ARM implementer 0x" << std::hex << implementer << " part 0x" << part;
  return os.str();
}

}  // namespace

std::vector<int> allowed_cpus() {
  std::vector<int> cpus;
  if (query_affinity(&cpus) && !cpus.empty()) return cpus;
  cpus.clear();
  for (int i = 0; i < online_cpu_count(); ++i) cpus.push_back(i);
  return cpus;
}

int online_cpu_count() {
  const long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? static_cast<int>(n) : 1;
}

std::string cpu_model_name_from_cpuinfo(const std::string& cpuinfo_text) {
  std::istringstream in(cpuinfo_text);
  std::string line;
  std::string hardware;
  long implementer = -1;
  long part = -1;
  while (std::getline(in, line)) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = trim_spaces(line.substr(0, colon));
    const std::string value = trim_spaces(line.substr(colon + 1));
    if (value.empty()) continue;
    if (key == "model name") return value;  // first CPU is enough
    if (key == "Hardware" && hardware.empty()) hardware = value;
    // strtol base 0 reads the "0x41" form the kernel prints.
    if (key == "CPU implementer" && implementer < 0) implementer = std::strtol(value.c_str(), nullptr, 0);
    if (key == "CPU part" && part < 0) part = std::strtol(value.c_str(), nullptr, 0);
  }
  if (implementer >= 0 && part >= 0) {
    std::string name = arm_core_name(static_cast<unsigned long>(implementer),
                                     static_cast<unsigned long>(part));
    return hardware.empty() ? name : name + " (" + hardware + ")";
  }
  if (!hardware.empty()) return hardware;
  return "unknown";
}

std::string cpu_model_name() {
  std::ifstream file("/proc/cpuinfo");
  if (!file) return "unknown";
  std::stringstream buffer;
  buffer << file.rdbuf();
  return cpu_model_name_from_cpuinfo(buffer.str());
}

std::vector<int> parse_cpu_list(const std::string& text) {
  const std::string body = trim_spaces(text);
  if (body.empty()) throw_bad_list(text, "the list is empty");
  std::vector<int> cpus;
  size_t start = 0;
  while (start <= body.size()) {
    size_t comma = body.find(',', start);
    if (comma == std::string::npos) comma = body.size();
    const std::string item = trim_spaces(body.substr(start, comma - start));
    if (item.empty()) throw_bad_list(text, "empty item");
    // A leading '-' is a negative number, not a range separator.
    const size_t dash = item.find('-', 1);
    if (dash == std::string::npos) {
      cpus.push_back(parse_cpu_index(item, text));
    } else {
      const int first = parse_cpu_index(trim_spaces(item.substr(0, dash)), text);
      const int last = parse_cpu_index(trim_spaces(item.substr(dash + 1)), text);
      if (last < first) throw_bad_list(text, "reversed range '" + item + "'");
      for (int cpu = first; cpu <= last; ++cpu) cpus.push_back(cpu);
    }
    start = comma + 1;
  }
  std::sort(cpus.begin(), cpus.end());
  cpus.erase(std::unique(cpus.begin(), cpus.end()), cpus.end());
  return cpus;
}

std::string format_cpu_list(std::vector<int> cpus) {
  if (cpus.empty()) return "none";
  std::sort(cpus.begin(), cpus.end());
  cpus.erase(std::unique(cpus.begin(), cpus.end()), cpus.end());
  std::string out;
  size_t i = 0;
  while (i < cpus.size()) {
    size_t j = i;
    while (j + 1 < cpus.size() && cpus[j + 1] == cpus[j] + 1) ++j;
    if (!out.empty()) out += ',';
    out += std::to_string(cpus[i]);
    if (j > i) out += '-' + std::to_string(cpus[j]);
    i = j + 1;
  }
  return out;
}

}  // namespace tristereo
