# 64-bit ARM Linux (Debian arm64): Raspberry Pi 3/4/5 with a 64-bit OS, Jetson
# CPUs, Rockchip RK35xx, i.MX 8. Usage:
#   cmake -S . -B build-aarch64 --toolchain toolchains/aarch64-linux-gnu.cmake
# The default code runs on any ARMv8-A core. Tune for one board with
#   -DTRISTEREO_CPU=cortex-a53 (Pi 3, Pi Zero 2), cortex-a72 (Pi 4),
#   cortex-a76 (Pi 5), cortex-a57 (Jetson Nano), cortex-a78ae (Jetson Orin).
set(TRISTEREO_TRIPLE aarch64-linux-gnu)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(TRISTEREO_QEMU qemu-aarch64)
# NEON (Advanced SIMD) is part of the ARMv8-A baseline: no flag needed for it.
set(TRISTEREO_CPU_DEFAULT armv8-a)
include(${CMAKE_CURRENT_LIST_DIR}/linux-gnu-common.cmake)
