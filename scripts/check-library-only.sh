#!/usr/bin/env bash
# Configures ridge as a library only (-DRIDGE_LIBRARY_ONLY=ON) where the command line's,
# tests' and benchmarks' dependencies cannot be found, to show that libridge needs none of
# them: pkg-config sees every installed module except the anchor codecs, PLplot and Dear
# ImGui, and CMake may not find ZFP, GoogleTest, Google Benchmark or CLI11.
#   bash scripts/check-library-only.sh [BUILD_DIR]   (default: a temporary directory)
set -euo pipefail
cd "$(dirname "$0")/.."

work=$(mktemp -d "${TMPDIR:-/tmp}/ridge-libonly.XXXXXX")
trap 'rm -rf "$work"' EXIT
build=${1:-$work/build}

hidden='^(Lerc|charls|libjxl.*|plplot.*|imgui)\.pc$'
mkdir -p "$work/pkgconfig"
IFS=: read -r -a dirs <<< "$(pkg-config --variable pc_path pkg-config)"
for dir in "${dirs[@]}"; do
  [[ -d $dir ]] || continue
  for pc in "$dir"/*.pc; do
    [[ -e $pc ]] || continue
    name=$(basename "$pc")
    [[ $name =~ $hidden ]] && continue
    [[ -e $work/pkgconfig/$name ]] || ln -s "$pc" "$work/pkgconfig/$name"
  done
done
for module in Lerc charls libjxl plplot imgui; do
  if PKG_CONFIG_LIBDIR=$work/pkgconfig pkg-config --exists "$module"; then
    echo "check-library-only: could not hide $module from pkg-config" >&2
    exit 1
  fi
done

PKG_CONFIG_LIBDIR=$work/pkgconfig cmake -S . -B "$build" -G Ninja -DRIDGE_LIBRARY_ONLY=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_zfp=ON -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON \
  > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
# Only the library: no CLI, test or bench target was generated (the CLI's output is "ridge",
# stage archives are lib<name>.a).
if grep -qE '^build ((tests|bench)/[a-z_]+|ridge|libridge_(codecbench|renderbench|plot)\.a)[: ]' \
     "$build/build.ninja"; then
  echo "check-library-only: the library-only configuration still generates tool targets" >&2
  exit 1
fi
grep -q '^build libridge.so' "$build/build.ninja" || {
  echo "check-library-only: no libridge.so target" >&2; exit 1; }
echo "ridge: library-only configuration needs none of the tools' dependencies"
