#!/usr/bin/env bash
# Installs dependencies, builds ridge, and runs the whole test suite:
#   1. layering check, and a library-only configure without the tools' dependencies,
#   2. Release build + ctest (the install test among them), 3. clang -O1 build with ASan/UBSan
#   and assertions + ctest (less the sweeps of scripts/sanitizer-skip.txt), 4. a short libFuzzer
#   run of the archive reader and the patch decoders (clang; its targets are built in the
#   sanitizer build of 3, so the library is compiled twice, not three times).
# Usage: bash scripts/test.sh   (RIDGE_SKIP_SANITIZE=1 skips 3, RIDGE_SKIP_FUZZ=1 skips 4)
set -euo pipefail
cd "$(dirname "$0")/.."
# Where CI's time goes (the whole run should stay under 40 minutes on 2 cores).
phase() { echo "== scripts/test.sh: $1 at $((SECONDS / 60)) min $((SECONDS % 60)) s"; }
phase "dependencies"
bash scripts/install-deps.sh
phase "web dependencies (chromium, node, npm packages)"
bash scripts/install-web-deps.sh
phase "checks"
bash scripts/check-layering.sh
bash scripts/check-library-only.sh

jobs=$(nproc)
phase "Release build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DRIDGE_WERROR=ON
cmake --build build -j "$jobs"
phase "Release tests"
ctest --test-dir build --output-on-failure -j "$jobs"

if [[ "${RIDGE_SKIP_SANITIZE:-0}" != "1" ]]; then
  # clang at -O1 with assertions on: about 2x faster tests than GCC at -O0 (ASan's own advice
  # is -O1), and a second compiler's warnings. Line tables only: the sanitizers' stack traces
  # keep file:line, at less compile and link time than full debug information. The GL sweeps of scripts/sanitizer-skip.txt
  # stay with the Release pass.
  phase "sanitizer build"
  CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug \
        "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -gline-tables-only" "-DCMAKE_C_FLAGS_DEBUG=-O1 -gline-tables-only" -DRIDGE_SANITIZE=ON \
        -DRIDGE_WERROR=ON -DRIDGE_BUILD_BENCH=OFF -DRIDGE_BUILD_FUZZERS=ON
  cmake --build build-asan -j "$jobs"
  phase "sanitizer tests"
  skip=$(grep -v -e '^#' -e '^$' scripts/sanitizer-skip.txt | paste -sd '|')
  # GDAL's own one-time allocations are not ours to fix; leaks of ridge code still fail.
  # intercept_tls_get_addr=0: the runtime takes a dynamic-TLS block (Mesa's, from the
  # dlopen'd driver) whose address is 16 mod 4096 for a glibc-2.19 header and reads garbage
  # through it, so LeakSanitizer's tracer crashes at exit now and then (google/sanitizers#1322).
  ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0 LSAN_OPTIONS=suppressions="$PWD/scripts/lsan.supp" \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure -j "$jobs" -E "$skip"
fi

if [[ "${RIDGE_SKIP_FUZZ:-0}" != "1" ]]; then
  # The fuzz targets come from the sanitizer build when there is one (libFuzzer's coverage
  # instrumentation, -fsanitize=fuzzer-no-link, is then on for its tests too: a few percent).
  phase "fuzzing"
  fuzz_build=""
  [[ "${RIDGE_SKIP_SANITIZE:-0}" != "1" ]] && fuzz_build=build-asan
  RIDGE_FUZZ_BUILD=$fuzz_build RIDGE_FUZZ_SECONDS=${RIDGE_FUZZ_SECONDS:-10} bash scripts/fuzz.sh
fi
phase "done"
