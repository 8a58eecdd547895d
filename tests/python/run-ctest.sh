#!/usr/bin/env bash
# ctest's entry to the tests of python/ridge_dask (the sharded build on Dask): the driver run
# on a four-tile mosaic of tests/data/everest_crop.tif by the ridge under test, against
# `ridge build` of the same mosaic. Exit 77 (ctest: skipped) when there is no ridge binary,
# no python3 that imports distributed (apt-get install python3-distributed), or no
# gdal_translate (apt-get install gdal-bin).
#
# Proposed for tests/CMakeLists.txt:
#   # python/ridge_dask against the real CLI (tests/python/): skipped (77) without
#   # python3-distributed.
#   add_test(NAME python.ridge_dask COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/python/run-ctest.sh
#            $<TARGET_FILE:ridge_cli>)
#   set_tests_properties(python.ridge_dask PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 900)
#
# Usage: run-ctest.sh PATH/TO/ridge [unittest arguments, e.g. RidgeDaskTest.test_bad_...]
# RIDGE_DASK_PYTHON=/path/to/python3 picks the interpreter; RIDGE_DASK_TEST_KEEP=1 keeps the
# temporary directory.
set -euo pipefail
ridge=${1:-}
shift || true
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
if [[ -z "$ridge" || ! -x "$ridge" ]]; then
  echo "SKIP: no ridge binary at '${ridge}'"
  exit 77
fi
# The first python3 that imports distributed: PATH's may be a pyenv or virtualenv one without
# Debian's dist-packages, where python3-distributed lives.
python=""
for candidate in ${RIDGE_DASK_PYTHON:-} python3 /usr/bin/python3; do
  if command -v "$candidate" >/dev/null 2>&1 && "$candidate" -c "import distributed" 2>/dev/null
  then
    python=$candidate
    break
  fi
done
if [[ -z "$python" ]]; then
  echo "SKIP: no python3 that imports distributed (apt-get install python3-distributed)"
  exit 77
fi
if ! command -v gdal_translate >/dev/null; then
  echo "SKIP: no gdal_translate (apt-get install gdal-bin)"
  exit 77
fi
RIDGE_BIN=$(cd "$(dirname "$ridge")" && pwd)/$(basename "$ridge")
export RIDGE_BIN
export PYTHONPATH="$root/python${PYTHONPATH:+:$PYTHONPATH}"
# No __pycache__ in the source tree (.gitignore does not list it).
export PYTHONDONTWRITEBYTECODE=1
cd "$root"
exec "$python" "$root/tests/python/test_ridge_dask.py" -v "$@"
