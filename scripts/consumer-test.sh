#!/bin/sh
# Uses tristereo the way a project of its users does: from the INSTALLED
# package, once through find_package(tristereo CONFIG REQUIRED) and once
# through pkg-config, building examples/consumer and running it (one frame on
# a generated scene, checked against its ground truth).
#
# Usage: scripts/consumer-test.sh native [BUILD_DIR]    (default build/, static)
#        scripts/consumer-test.sh aarch64 [BUILD_DIR]   (default build-cross-aarch64/)
#
# native:  installs BUILD_DIR into a temporary prefix (static library), runs
#          the installed program from it (synth, match), builds and runs both
#          consumers and README's example (examples/consumer/match_pair.cpp,
#          whose disparity must equal the program's byte for byte); then builds the library shared
#          (BUILD_SHARED_LIBS=ON, in build-shared/), checks that it exports
#          the tristereo API only, installs it, builds and runs both
#          consumers against it.
# aarch64: installs BUILD_DIR (the cross build of scripts/cross-test.sh) with
#          DESTDIR into a staging copy of the target libraries, builds both
#          consumers with the aarch64 toolchain (file / compiler) and runs them
#          under qemu-aarch64.
# Ends with one line per consumer and exits non-zero if any failed.
set -u
repo=$(cd "$(dirname "$0")/.." && pwd)
cd "$repo" || exit 1
target=${1:-native}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
results=""
failed=0
src="$repo/examples/consumer"

note() {  # note NAME STATUS
  results="$results
  $1: $2"
  [ "$2" = passed ] || failed=1
}

# run_consumer NAME COMMAND...: runs a built consumer, which must print "consumer: ok".
run_consumer() {
  name=$1
  shift
  if "$@" >"$work/$name.out" 2>&1 && grep -q "^consumer: ok$" "$work/$name.out"; then
    cat "$work/$name.out"
    note "$name" passed
  else
    cat "$work/$name.out"
    note "$name" FAILED
  fi
}

case "$target" in
  native)
    build=${2:-build}
    for kind in static shared; do
      prefix="$work/prefix-$kind"
      if [ "$kind" = shared ]; then
        build="build-shared"
        echo "==== consumer[native]: shared library in $build"
        if ! sh scripts/configure.sh "$build" -S . -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON \
               -DTRISTEREO_BUILD_TESTS=OFF -DTRISTEREO_BUILD_BENCH=OFF -DTRISTEREO_BUILD_APPS=OFF \
               -DTRISTEREO_BUILD_PYTHON=OFF -DTRISTEREO_WERROR=ON >"$work/shared-build.log" 2>&1 ||
           ! cmake --build "$build" -j"$(nproc)" --target tristereo >>"$work/shared-build.log" 2>&1; then
          cat "$work/shared-build.log"
          note "shared library build" FAILED
          continue
        fi
        lib=$(find "$build" -maxdepth 1 -name 'libtristereo.so.*.*' | head -n 1)
        total=$(nm -D --defined-only "$lib" | wc -l)
        foreign=$(nm -D --defined-only "$lib" | c++filt | awk '{ $1 = ""; $2 = ""; print }' | grep -vc '^ *tristereo::')
        echo "consumer[native]: $lib exports $total symbols, $foreign outside namespace tristereo"
        if [ "$total" -gt 0 ] && [ "$foreign" -eq 0 ]; then note "shared exports ($total, tristereo:: only)" passed
        else note "shared exports ($total, $foreign foreign)" FAILED; fi
      fi
      echo "==== consumer[native]: cmake --install $build --prefix $prefix ($kind)"
      cmake --install "$build" --prefix "$prefix" >"$work/install-$kind.log" 2>&1 ||
        { cat "$work/install-$kind.log"; note "install ($kind)" FAILED; continue; }
      if [ "$kind" = static ]; then
        # The installed program, run from the prefix: a generated pair, matched.
        if "$prefix/bin/tristereo" synth "$work/scene" --width 160 --height 120 --ndisp 24 >"$work/prog.log" 2>&1 &&
           "$prefix/bin/tristereo" match "$work/scene/left.png" "$work/scene/right.png" --ndisp 24 \
             --disp "$work/prog_disp.pfm" >>"$work/prog.log" 2>&1; then
          note "installed program ($prefix/bin/tristereo synth, match)" passed
        else
          cat "$work/prog.log"
          note "installed program" FAILED
        fi
      fi
      if cmake -S "$src" -B "$work/cmake-$kind" -DCMAKE_PREFIX_PATH="$prefix" >"$work/c-$kind.log" 2>&1 &&
         cmake --build "$work/cmake-$kind" >>"$work/c-$kind.log" 2>&1; then
        run_consumer "find_package ($kind)" env LD_LIBRARY_PATH="$prefix/lib" "$work/cmake-$kind/consumer"
        # README's example on the same pair: the same disparity file as the program's.
        if env LD_LIBRARY_PATH="$prefix/lib" "$work/cmake-$kind/match_pair" "$work/scene/left.png" \
             "$work/scene/right.png" 24 "$work/example_$kind.pfm" &&
           cmp "$work/example_$kind.pfm" "$work/prog_disp.pfm"; then
          note "README example ($kind): the program's disparity, byte for byte" passed
        else
          note "README example ($kind)" FAILED
        fi
      else
        cat "$work/c-$kind.log"
        note "find_package ($kind)" "FAILED (configure or build)"
      fi
      pc_static=""
      [ "$kind" = static ] && pc_static="--static"
      # shellcheck disable=SC2046,SC2086
      if flags=$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config $pc_static --cflags --libs tristereo) &&
         g++ -std=c++17 -O2 "$src/main.cpp" -o "$work/pc-$kind" $flags >"$work/pc-$kind.log" 2>&1; then
        run_consumer "pkg-config ($kind)" env LD_LIBRARY_PATH="$prefix/lib" "$work/pc-$kind"
      else
        cat "$work/pc-$kind.log"
        note "pkg-config ($kind)" "FAILED (build)"
      fi
    done
    ;;
  aarch64)
    build=${2:-build-cross-aarch64}
    triple=aarch64-linux-gnu
    deps="${TRISTEREO_CROSS_DEPS_ROOT:-/opt/tristereo/cross-deps}/$triple"
    stage="$work/sysroot"
    echo "==== consumer[aarch64]: DESTDIR=$stage cmake --install $build --prefix /usr"
    cp -a "$deps" "$stage"
    if ! DESTDIR="$stage" cmake --install "$build" --prefix /usr >"$work/install.log" 2>&1; then
      cat "$work/install.log"
      note "install (aarch64)" FAILED
    else
      libdirs="$stage/lib/$triple:$stage/usr/lib/$triple:$stage/usr/lib"
      config=$(find "$stage/usr" -name tristereoConfig.cmake | head -n 1)
      if cmake -S "$src" -B "$work/cmake" --toolchain "$repo/toolchains/$triple.cmake" \
           -DTRISTEREO_CROSS_DEPS="$stage" -Dtristereo_DIR="$(dirname "$config")" >"$work/c.log" 2>&1 &&
         cmake --build "$work/cmake" >>"$work/c.log" 2>&1; then
        run_consumer "find_package (aarch64, static)" \
          qemu-aarch64 -L "/usr/$triple" -E LD_LIBRARY_PATH="$libdirs" "$work/cmake/consumer"
      else
        cat "$work/c.log"
        note "find_package (aarch64, static)" "FAILED (configure or build)"
      fi
      pcdirs="$stage/usr/lib/pkgconfig:$stage/usr/lib/$triple/pkgconfig:$stage/usr/share/pkgconfig"
      # shellcheck disable=SC2086
      if flags=$(PKG_CONFIG_SYSROOT_DIR="$stage" PKG_CONFIG_LIBDIR="$pcdirs" pkg-config --static --cflags --libs tristereo) &&
         "$triple-g++" -std=c++17 -O2 "$src/main.cpp" -o "$work/pc" $flags -L"$stage/lib/$triple" >"$work/pc.log" 2>&1; then
        run_consumer "pkg-config (aarch64, static)" \
          qemu-aarch64 -L "/usr/$triple" -E LD_LIBRARY_PATH="$libdirs" "$work/pc"
      else
        cat "$work/pc.log"
        note "pkg-config (aarch64, static)" "FAILED (build)"
      fi
    fi
    ;;
  *)
    echo "consumer-test: unknown target '$target' (expected native or aarch64)" >&2
    exit 2
    ;;
esac

echo
echo "==== consumer-test summary ($target)$results"
exit "$failed"
