# Dependencies, all from Debian packages (scripts/install-deps.sh installs them).
# In a cross build, compiled libraries come from the target's multiarch dir
# (CMAKE_LIBRARY_ARCHITECTURE); header-only ones (Eigen, xsimd) from the host.

if(CMAKE_CROSSCOMPILING)
  # Header-only and arch-neutral: take the host's Eigen, searched outside the
  # target roots so that a board sysroot without Eigen still works.
  find_package(Eigen3 3.3 REQUIRED NO_MODULE PATHS /usr/share/eigen3/cmake
               NO_DEFAULT_PATH NO_CMAKE_FIND_ROOT_PATH)
else()
  find_package(Eigen3 3.3 REQUIRED NO_MODULE)
endif()

find_package(xsimd QUIET)
if(NOT TARGET xsimd)
  # The xsimd CMake config lives in the host multiarch dir; in a cross build it
  # is not searched, and xsimd is header-only and arch-neutral anyway.
  find_path(TRISTEREO_XSIMD_INCLUDE xsimd/xsimd.hpp PATHS /usr/include NO_CMAKE_FIND_ROOT_PATH)
  if(TRISTEREO_XSIMD_INCLUDE)
    set(_xsimd_include ${TRISTEREO_XSIMD_INCLUDE})
    if(CMAKE_CROSSCOMPILING)
      # Never put the host's /usr/include on the target's path (it would shadow
      # a sysroot's libc headers, or be dropped as implicit): expose xsimd alone.
      set(_xsimd_include ${CMAKE_BINARY_DIR}/host-include)
      file(MAKE_DIRECTORY ${_xsimd_include})
      file(CREATE_LINK ${TRISTEREO_XSIMD_INCLUDE}/xsimd ${_xsimd_include}/xsimd SYMBOLIC)
    endif()
    add_library(xsimd INTERFACE IMPORTED)
    set_target_properties(xsimd PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${_xsimd_include})
  endif()
endif()

# Debian's xsimd 8.1 config names "xtl" as an interface link library although
# xsimd only needs it for optional xtensor interop; without libxtl-dev that
# turns into a bogus -lxtl on every executable. Drop it when xtl is absent.
if(TARGET xsimd AND NOT TARGET xtl)
  get_target_property(_xsimd_libs xsimd INTERFACE_LINK_LIBRARIES)
  if(_xsimd_libs)
    list(REMOVE_ITEM _xsimd_libs xtl)
    set_target_properties(xsimd PROPERTIES INTERFACE_LINK_LIBRARIES "${_xsimd_libs}")
  endif()
endif()

find_package(PNG REQUIRED)

set(TRISTEREO_HAVE_GPIOD OFF)
if(NOT TRISTEREO_WITH_GPIOD STREQUAL "OFF")
  find_path(TRISTEREO_GPIOD_INCLUDE gpiod.h)
  find_library(TRISTEREO_GPIOD_LIBRARY gpiod)
  if(TRISTEREO_GPIOD_INCLUDE AND TRISTEREO_GPIOD_LIBRARY)
    file(STRINGS ${TRISTEREO_GPIOD_INCLUDE}/gpiod.h _gpiod_v1 REGEX "gpiod_chip_open_by_name")
    if(_gpiod_v1)
      set(TRISTEREO_HAVE_GPIOD ON)
      add_library(tristereo::gpiod UNKNOWN IMPORTED)
      set_target_properties(tristereo::gpiod PROPERTIES IMPORTED_LOCATION ${TRISTEREO_GPIOD_LIBRARY}
                            INTERFACE_INCLUDE_DIRECTORIES ${TRISTEREO_GPIOD_INCLUDE})
    endif()
  endif()
  if(TRISTEREO_WITH_GPIOD STREQUAL "ON" AND NOT TRISTEREO_HAVE_GPIOD)
    message(FATAL_ERROR "TRISTEREO_WITH_GPIOD=ON but libgpiod v1 (libgpiod-dev 1.x) was not found")
  endif()
endif()
message(STATUS "tristereo: GPIO frame markers (libgpiod v1): ${TRISTEREO_HAVE_GPIOD}")
