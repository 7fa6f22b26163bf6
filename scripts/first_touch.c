/* What a first touch of fresh anonymous memory costs, per page kind
 * (docs/performance.md, "Working memory"): 96 MiB mapped, then one byte
 * written per 4 KiB page, timed.
 *
 *   cc -O2 scripts/first_touch.c -o /tmp/first_touch
 *   /tmp/first_touch 4k | populate | huge     (right after another run)
 *   sleep 30; /tmp/first_touch huge           (after idle)
 *
 * 4k: ordinary faults; populate: MADV_POPULATE_WRITE first (Linux 5.14);
 * huge: MADV_HUGEPAGE (transparent huge pages, 2 MiB per fault). */
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23
#endif

static double now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

int main(int argc, char** argv) {
  const char* kind = argc > 1 ? argv[1] : "4k";
  const size_t bytes = (size_t)96 << 20;
  char* p = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return perror("mmap"), 1;
  const double t0 = now_ms();
  if (strcmp(kind, "huge") == 0 && madvise(p, bytes, MADV_HUGEPAGE) != 0) perror("madvise(MADV_HUGEPAGE)");
  if (strcmp(kind, "populate") == 0 && madvise(p, bytes, MADV_POPULATE_WRITE) != 0)
    perror("madvise(MADV_POPULATE_WRITE)");
  for (size_t i = 0; i < bytes; i += 4096) p[i] = 1;
  printf("%s: 96 MiB first touched in %.1f ms\n", kind, now_ms() - t0);
  return 0;
}
