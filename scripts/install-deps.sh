#!/bin/sh
# Installs the Debian 12 packages a job needs, then checks that everything it
# promises is there (exit 1 naming what is missing). Works on a minimal root
# (debootstrap --variant=minbase): it brings the compiler, make, CMake and
# pkg-config too. Runs as root, or through sudo.
#
# Usage: scripts/install-deps.sh [PROFILE...]     (default: main)
#   main   building the library and the tristereo program (scripts/demo.sh):
#          g++, make, CMake, pkg-config, Eigen, xsimd, libpng, zlib, libgpiod
#   test   main + what scripts/test.sh builds and runs: GoogleTest, Google
#          Benchmark (the benchmarks are built so they cannot rot), shellcheck,
#          pybind11, NumPy and pytest (the Python bindings and their tests),
#          OpenCV's Python module (the tests feed it cv2.imread's BGR arrays;
#          python/bench_overhead.py times cv2's matchers beside the module),
#          and everything of the profile fuzz
#   fuzz   main + clang 14 with its sanitizer and libFuzzer runtimes
#          (libclang-rt-14-dev) and llvm-symbolizer: the clang, asan and fuzz
#          stages of scripts/test.sh, and scripts/fuzz.sh
#   cross  test + the ARM cross compilers, qemu-user and the arm64/armhf target
#          libraries (scripts/install-cross-deps.sh all)
#   plot   python3 with matplotlib and NumPy (scripts/plot_latency.py and the
#          plots of scripts/results.py)
#   peers  main + Google Benchmark and OpenCV (libopencv-dev): the StereoBM and
#          StereoSGBM rows of bench/bench_peers (scripts/perf_report.py). Only
#          that benchmark links OpenCV; the library never does
set -eu
here=$(cd "$(dirname "$0")" && pwd)
deps_name="install-deps"
# shellcheck source=scripts/deps-lib.sh
. "$here/deps-lib.sh"

main=0 test=0 fuzz=0 cross=0 plot=0 peers=0
[ $# -eq 0 ] && main=1
for arg in "$@"; do
  case "$arg" in
    main) main=1 ;;
    test) main=1 test=1 fuzz=1 ;;
    fuzz) main=1 fuzz=1 ;;
    cross|--cross) main=1 test=1 fuzz=1 cross=1 ;;
    plot) plot=1 ;;
    peers) main=1 peers=1 ;;
    -h|--help) sed -n '2,25p' "$0"; exit 0 ;;
    *) echo "install-deps: unknown profile '$arg' (expected main, test, fuzz, cross, plot or peers)" >&2; exit 2 ;;
  esac
done

pkgs=""
profiles=""
if [ "$main" -eq 1 ]; then
  pkgs="$pkgs g++ make cmake pkg-config libeigen3-dev libxsimd-dev libpng-dev zlib1g-dev libgpiod-dev"
  profiles="$profiles main"
fi
if [ "$test" -eq 1 ]; then
  # googletest: the sources the suite builds for every target (/usr/src/googletest).
  pkgs="$pkgs googletest libgtest-dev libgmock-dev libbenchmark-dev shellcheck"
  # The Python bindings and their tests (Debian's Python only).
  pkgs="$pkgs python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-opencv"
  profiles="$profiles test"
fi
if [ "$fuzz" -eq 1 ]; then
  # clang-14 brings libclang-common-14-dev (headers such as fuzzer/), but the
  # ASan/UBSan/libFuzzer runtimes are libclang-rt-14-dev; llvm-14 has the
  # symbolizer that turns sanitizer reports into file:line.
  pkgs="$pkgs clang-14 libclang-rt-14-dev llvm-14"
  profiles="$profiles fuzz"
fi
if [ "$plot" -eq 1 ]; then
  pkgs="$pkgs python3 python3-matplotlib python3-numpy"
  profiles="$profiles plot"
fi
if [ "$peers" -eq 1 ]; then
  pkgs="$pkgs libbenchmark-dev libopencv-dev"
  profiles="$profiles peers"
fi
# shellcheck disable=SC2086
deps_install $pkgs

# ---------------------------------------------------------------- what was promised
# shellcheck disable=SC2086
deps_need_pkg $pkgs
if [ "$main" -eq 1 ]; then
  deps_need_cmd g++ "C++ compiler"
  deps_need_cmd make "build tool"
  deps_need_cmd cmake "build system"
  deps_need_cmd pkg-config "library lookup"
  deps_need_file /usr/share/eigen3/cmake/Eigen3Config.cmake "Eigen's CMake package"
  deps_need_file /usr/include/xsimd/xsimd.hpp "xsimd headers"
  deps_need_file /usr/include/png.h "libpng headers"
  deps_need_file /usr/include/zlib.h "zlib headers"
  deps_need_file /usr/include/gpiod.h "libgpiod v1 headers"
fi
if [ "$test" -eq 1 ]; then
  deps_need_file /usr/src/googletest/CMakeLists.txt "GoogleTest sources"
  deps_need_file /usr/include/benchmark/benchmark.h "Google Benchmark headers"
  deps_need_cmd shellcheck "script linter"
  deps_need_file /usr/lib/cmake/pybind11/pybind11Config.cmake "pybind11's CMake package"
  if ! /usr/bin/python3 -c 'import numpy, pytest, pybind11, cv2' 2>/dev/null; then
    deps_problem "python3 modules numpy, pytest, pybind11 and cv2 for /usr/bin/python3"
  fi
fi
if [ "$fuzz" -eq 1 ]; then
  deps_need_cmd clang++-14 "clang C++ compiler"
  deps_need_cmd llvm-symbolizer-14 "sanitizer report symbolizer"
  for _rt in asan ubsan_standalone fuzzer fuzzer_no_main; do
    deps_need_file "$(clang-14 -print-resource-dir 2>/dev/null)/lib/linux/libclang_rt.$_rt-$(uname -m).a" \
      "clang's $_rt runtime (libclang-rt-14-dev)"
  done
fi
if [ "$plot" -eq 1 ]; then
  deps_need_cmd python3 "Python"
  # Debian's python3, the one the packages above serve (another python3 may come first on PATH).
  if ! /usr/bin/python3 -c 'import matplotlib, numpy' 2>/dev/null; then
    deps_problem "python3 modules matplotlib and numpy for /usr/bin/python3"
  fi
fi
if [ "$peers" -eq 1 ]; then
  deps_need_file /usr/include/benchmark/benchmark.h "Google Benchmark headers"
  deps_need_file /usr/include/opencv4/opencv2/calib3d.hpp "OpenCV's stereo matchers (calib3d)"
fi
deps_verify "profiles:$profiles"

if [ "$cross" -eq 1 ]; then
  exec "$here/install-cross-deps.sh" all
fi
