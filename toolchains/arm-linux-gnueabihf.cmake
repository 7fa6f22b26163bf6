# 32-bit ARM Linux, hard-float ABI (Debian armhf; Raspberry Pi OS 32-bit on
# Pi 2/3/4, i.MX 6/7, older Rockchip). Usage:
#   cmake -S . -B build-armhf --toolchain toolchains/arm-linux-gnueabihf.cmake
# Default: ARMv7-A with NEON (Debian's compiler alone assumes VFPv3-D16 and no
# NEON). Variants, see docs/cross-compiling.md:
#   -DTRISTEREO_CPU=cortex-a7                                   Pi 2
#   -DTRISTEREO_CPU=cortex-a53 -DTRISTEREO_ARM_FPU=neon-fp-armv8  Pi 3 on a 32-bit OS
#   -DTRISTEREO_ARM_FPU=vfpv3-d16 -DTRISTEREO_WITH_SIMD=OFF     cores without NEON
set(TRISTEREO_TRIPLE arm-linux-gnueabihf)
set(CMAKE_SYSTEM_PROCESSOR armv7l)
set(TRISTEREO_QEMU qemu-arm)
set(TRISTEREO_CPU_DEFAULT armv7-a)
set(TRISTEREO_ARM_FPU neon-vfpv4 CACHE STRING
    "-mfpu value: neon-vfpv4 (Cortex-A7/A15/A17), neon-fp-armv8 (Cortex-A53/A72 in 32-bit mode), vfpv3-d16 (no NEON)")
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES TRISTEREO_ARM_FPU)
# armhf is the hard-float ABI: every object and library on the board uses it.
set(TRISTEREO_ABI_FLAGS "-mfpu=${TRISTEREO_ARM_FPU} -mfloat-abi=hard")
include(${CMAKE_CURRENT_LIST_DIR}/linux-gnu-common.cmake)
