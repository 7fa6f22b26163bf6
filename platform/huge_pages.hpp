// Whether the large working buffers (src/memory/large_array.hpp) are advised
// for transparent huge pages.
//
// On bare metal a 2 MiB fault zeroes its page about 4.5x faster than 512
// faults of 4 KiB (96 MiB: 8 ms against 37 ms, docs/performance.md "Working
// memory"). Inside a virtual machine whose virtio balloon does free page
// reporting, the host takes back every free 2 MiB block a few seconds after it
// is freed, and a huge page fault on such a block waits for the host to back
// it again: the same 96 MiB took 171-222 ms after 20-30 s of idle, 4-6x the
// 4 KiB faults, which that reporting leaves alone (scripts/first_touch.c). So the default is huge pages
// unless such a balloon is bound; TRISTEREO_HUGE_PAGES=1 or =0 in the
// environment decides instead.
#pragma once

#include <string>

namespace tristereo {

struct HugePagePolicy {
  bool advise = false;
  std::string reason;  // one line, for `tristereo info`
};

// Decided once per process (environment, then /sys).
const HugePagePolicy& huge_page_policy();

// The rule behind the default, for tests: true when a virtio balloon device
// bound under `sysfs_root`/bus/virtio/drivers/virtio_balloon offers free page
// reporting (feature bit 5 of its `features` string of 0s and 1s).
bool balloon_reports_free_pages(const std::string& sysfs_root);

}  // namespace tristereo
