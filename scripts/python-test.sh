#!/bin/sh
# The Python bindings' tests (python/tests, pytest from Debian's python3-pytest)
# against the module and the tristereo program of one build tree.
# Usage: scripts/python-test.sh [BUILD_DIR]     (default build)
# Exit: pytest's status; "no tests collected" (5) counts as a failure.
set -u
repo=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$repo/build}" && pwd) || exit 1
if [ ! -f "$build/python/tristereo/__init__.py" ]; then
  echo "python-test: no Python module in $build/python (configure with pybind11-dev installed, or -DTRISTEREO_BUILD_PYTHON=ON)" >&2
  exit 1
fi
cd "$repo" || exit 1
PYTHONPATH="$build/python" TRISTEREO_CLI="$build/tristereo" PYTHONDONTWRITEBYTECODE=1 \
  /usr/bin/python3 -m pytest -q -p no:cacheprovider python/tests
rc=$?
[ "$rc" -eq 5 ] && echo "python-test: pytest collected no tests" >&2
[ "$rc" -eq 0 ] || exit "$rc"

# Installed into a chosen folder, the package imports and runs from there.
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --component python --prefix "$prefix" >/dev/null || exit 1
# The folder configure chose (asked of the interpreter, or -DTRISTEREO_PYTHON_SITEARCH).
sitearch=$(sed -n 's/^TRISTEREO_PYTHON_SITEARCH:STRING=//p' "$build/CMakeCache.txt")
case "$sitearch" in
  /*) echo "python-test: TRISTEREO_PYTHON_SITEARCH is absolute ($sitearch): not installing it in a test" >&2
      exit 0 ;;
esac
site="$prefix/$sitearch"
# Under the default prefixes the interpreter imports from it without PYTHONPATH.
if ! /usr/bin/python3 -c '
import sys
want = ["/usr/local/" + sys.argv[1], "/usr/" + sys.argv[1]]
missing = [w for w in want if w not in sys.path]
assert not missing, "not on sys.path: %s" % missing
' "$sitearch"; then
  echo "installed package: FAILED (/usr/bin/python3 would not import it from /usr/local or /usr)"
  exit 1
fi
if (cd "$prefix" && PYTHONPATH="$site" /usr/bin/python3 -c '
import numpy as np, sys, tristereo
assert tristereo.__file__.startswith(sys.argv[1]), tristereo.__file__
import os
pkg = os.path.dirname(tristereo.__file__)
assert os.path.isfile(os.path.join(pkg, "_tristereo.pyi")) and os.path.isfile(os.path.join(pkg, "py.typed")), "no type stub"
img = (np.arange(48 * 32) % 251).astype(np.uint8).reshape(32, 48)
out = tristereo.Pipeline(48, 32, ndisp=8).process(img, img)
assert out.disparity.shape == (32, 48)
print("python-test: the installed package imports and runs from", sys.argv[1])
' "$site"); then
  echo "installed package: passed"
else
  echo "installed package: FAILED"
  exit 1
fi
