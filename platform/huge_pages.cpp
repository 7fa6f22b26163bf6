#include "platform/huge_pages.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace tristereo {

namespace {
constexpr std::size_t kBalloonFreePageReporting = 5;  // VIRTIO_BALLOON_F_REPORTING
}  // namespace

bool balloon_reports_free_pages(const std::string& sysfs_root) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path driver = fs::path(sysfs_root) / "bus" / "virtio" / "drivers" / "virtio_balloon";
  for (fs::directory_iterator it(driver, ec), end; !ec && it != end; it.increment(ec)) {
    // The driver's directory holds bind, unbind, uevent and one link per device (virtioN).
    if (it->path().filename().string().rfind("virtio", 0) != 0) continue;
    std::ifstream in(it->path() / "features");
    std::string bits;
    if (in >> bits && bits.size() > kBalloonFreePageReporting && bits[kBalloonFreePageReporting] == '1')
      return true;
  }
  return false;
}

const HugePagePolicy& huge_page_policy() {
  static const HugePagePolicy policy = [] {
    HugePagePolicy p;
    if (const char* v = std::getenv("TRISTEREO_HUGE_PAGES"); v != nullptr && (std::string(v) == "0" || std::string(v) == "1")) {
      p.advise = std::string(v) == "1";
      p.reason = std::string("TRISTEREO_HUGE_PAGES=") + v;
#if defined(__linux__)
    } else if (balloon_reports_free_pages("/sys")) {
      p.advise = false;
      p.reason = "a virtio balloon with free page reporting: the host takes back free 2 MiB blocks";
    } else {
      p.advise = true;
      p.reason = "default (transparent huge pages where the kernel offers them)";
#else
    } else {
      p.advise = false;
      p.reason = "not Linux";
#endif
    }
    return p;
  }();
  return policy;
}

}  // namespace tristereo
