#!/usr/bin/env bash
# Fails when GDAL (or, later, GL) headers leak out of the modules that own them.
set -euo pipefail
cd "$(dirname "$0")/.."
bad=$(grep -rlE '#include *[<"](gdal|ogr|cpl_)[a-z_]*\.h' src include apps | grep -v '^src/io/' || true)
if [[ -n "$bad" ]]; then
  echo "layering: GDAL headers outside src/io:" >&2
  echo "$bad" >&2
  exit 1
fi
echo "layering: ok"
