# Shared part of the ARM Linux (GNU, Debian) toolchain files. A per-target file
# sets TRISTEREO_TRIPLE, CMAKE_SYSTEM_PROCESSOR, TRISTEREO_QEMU,
# TRISTEREO_CPU_DEFAULT and (optionally) TRISTEREO_ABI_FLAGS, then includes this file.
#
# Where target libraries are searched, first match wins:
#   TRISTEREO_SYSROOT set: only that sysroot (a copy of the board's / made by
#     rsync or debootstrap); it becomes CMAKE_SYSROOT.
#   otherwise: TRISTEREO_CROSS_DEPS (Debian's target .debs unpacked by
#     scripts/install-cross-deps.sh), /usr/<triple> (the cross libc) and / for
#     Debian multiarch packages (/usr/lib/<triple>), with the host's own
#     library directories ignored.
# Eigen and xsimd are header-only and taken from the host by
# cmake/TristereoDeps.cmake, which searches for them outside these roots.
#
# CMAKE_CROSSCOMPILING_EMULATOR makes ctest (and gtest test discovery) run the
# target binaries through qemu-user on the build machine.

if(NOT TRISTEREO_TRIPLE OR NOT CMAKE_SYSTEM_PROCESSOR)
  message(FATAL_ERROR "linux-gnu-common.cmake is included by a per-target toolchain file "
                      "(toolchains/aarch64-linux-gnu.cmake, toolchains/arm-linux-gnueabihf.cmake)")
endif()

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_C_COMPILER ${TRISTEREO_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${TRISTEREO_TRIPLE}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${TRISTEREO_TRIPLE})

set(TRISTEREO_SYSROOT "" CACHE PATH
    "Root file system of the target (e.g. rsync'ed from the board); empty: Debian cross packages on this host")
set(TRISTEREO_CROSS_DEPS /opt/tristereo/cross-deps/${TRISTEREO_TRIPLE} CACHE PATH
    "Target libraries unpacked by scripts/install-cross-deps.sh (ignored when TRISTEREO_SYSROOT is set)")
set(TRISTEREO_CPU "${TRISTEREO_CPU_DEFAULT}" CACHE STRING
    "Target CPU: an architecture (armv8-a, armv7-a: runs on every core of it) or a core (cortex-a53, cortex-a72, cortex-a76, cortex-a7: tuned for it)")
# try_compile() projects re-read this file without the cache: hand them our settings.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES TRISTEREO_SYSROOT TRISTEREO_CROSS_DEPS TRISTEREO_CPU)

# An architecture name selects the instruction set only (-march); a core name
# (-mcpu) also lets GCC schedule for that core, and the binary needs that core
# or a later one.
if(TRISTEREO_CPU MATCHES "^armv")
  set(_tristereo_cpu_flags "-march=${TRISTEREO_CPU}")
else()
  set(_tristereo_cpu_flags "-mcpu=${TRISTEREO_CPU}")
endif()
string(STRIP "${_tristereo_cpu_flags} ${TRISTEREO_ABI_FLAGS}" _tristereo_cpu_flags)
set(CMAKE_C_FLAGS_INIT "${_tristereo_cpu_flags}")
set(CMAKE_CXX_FLAGS_INIT "${_tristereo_cpu_flags}")

if(TRISTEREO_SYSROOT)
  if(NOT IS_DIRECTORY "${TRISTEREO_SYSROOT}")
    message(FATAL_ERROR "TRISTEREO_SYSROOT='${TRISTEREO_SYSROOT}' is not a directory")
  endif()
  set(CMAKE_SYSROOT "${TRISTEREO_SYSROOT}")
  set(CMAKE_FIND_ROOT_PATH "${TRISTEREO_SYSROOT}")
  set(_tristereo_qemu_prefix "${TRISTEREO_SYSROOT}")
  set(_tristereo_target_libdirs
      "${TRISTEREO_SYSROOT}/lib/${TRISTEREO_TRIPLE}" "${TRISTEREO_SYSROOT}/usr/lib/${TRISTEREO_TRIPLE}")
else()
  set(CMAKE_FIND_ROOT_PATH "${TRISTEREO_CROSS_DEPS}" /usr/${TRISTEREO_TRIPLE} /)
  set(_tristereo_qemu_prefix /usr/${TRISTEREO_TRIPLE})
  set(_tristereo_target_libdirs
      "${TRISTEREO_CROSS_DEPS}/lib/${TRISTEREO_TRIPLE}" "${TRISTEREO_CROSS_DEPS}/usr/lib/${TRISTEREO_TRIPLE}")
  # The root "/" is there for multiarch packages; never let it yield the
  # build machine's own libraries.
  foreach(_dir /lib/x86_64-linux-gnu /usr/lib/x86_64-linux-gnu /usr/lib/x86_64-linux-gnu/cmake
          /usr/local/lib /usr/lib64 /lib64)
    list(APPEND CMAKE_IGNORE_PATH ${_dir})
  endforeach()
endif()
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# The target binaries run under qemu-user: its -L prefix supplies the target's
# dynamic loader and libc; -E hands the target (only, not the host processes)
# the directories of the unpacked libraries (libz.so.1 lives in /lib/<triple>,
# which the binaries' RUNPATH does not name).
find_program(TRISTEREO_QEMU_PROGRAM NAMES ${TRISTEREO_QEMU} ${TRISTEREO_QEMU}-static NO_CMAKE_FIND_ROOT_PATH)
if(TRISTEREO_QEMU_PROGRAM)
  string(REPLACE ";" ":" _tristereo_ld_path "${_tristereo_target_libdirs}")
  set(CMAKE_CROSSCOMPILING_EMULATOR
      "${TRISTEREO_QEMU_PROGRAM};-L;${_tristereo_qemu_prefix};-E;LD_LIBRARY_PATH=${_tristereo_ld_path}")
else()
  message(STATUS "tristereo: ${TRISTEREO_QEMU} not found (Debian package qemu-user): "
                 "the ${CMAKE_SYSTEM_PROCESSOR} tests can be built here but only run on the board")
endif()
