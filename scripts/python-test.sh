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
exit "$rc"
