#!/usr/bin/env bash
# ctest's entry to the web checks that need Node and a browser: `ridge tiles` PMTiles read back
# by the pmtiles npm package (pmtiles-check.mjs), then `ridge serve` with the CesiumJS and
# MapLibre pages in Debian's headless chromium (run.mjs), on the Everest fixture built by the
# ridge under test. Exit 77 (ctest: skipped) when node, chromium or web/node_modules are
# missing: `bash scripts/install-web-deps.sh` installs them (scripts/test.sh does).
# Usage: run-ctest.sh PATH/TO/ridge
set -euo pipefail
ridge=$1
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
if ! command -v node >/dev/null; then
  echo "SKIP: no node (bash scripts/install-web-deps.sh installs it)"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$ridge" build "$root/tests/data/everest_crop.tif" -o "$work/everest.ridge" --patch 33 -q
node "$root/tests/browser/pmtiles-check.mjs" --ridge "$ridge" --archive "$work/everest.ridge" \
  --out "$work/pmtiles"
node "$root/tests/browser/run.mjs" --ridge "$ridge" --archive "$work/everest.ridge" --out "$work/out"
