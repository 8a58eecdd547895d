#!/usr/bin/env bash
# Installs every build, test and demo dependency of ridge from Debian 12 packages.
# Idempotent: re-running only installs what is missing. Must run as root (or via sudo).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libgdal-dev gdal-bin           # ingest: any raster GDAL reads; extract writes GeoTIFF
  libproj-dev                    # longitude/latitude ↔ archive CRS (queries, cameras, info)
  libzstd-dev                    # archive payload compression (later codecs)
  libopenjp2-7-dev libopenjph-dev  # the jpeg2000 codec: JPEG 2000 (OpenJPEG) and HTJ2K (OpenJPH)
  libpng-dev                     # hillshade PNG output, terrain-RGB PNG tiles
  libfmt-dev libcli11-dev nlohmann-json3-dev
  libmeshoptimizer-dev           # web tiles: vertex order for quantized-mesh index coding
  libcpp-httplib-dev             # ridge serve: HTTP/1.1 server (cpp-httplib)
  libwebp-dev                    # terrain-RGB tiles as lossless WebP
  libgtest-dev libgmock-dev libbenchmark-dev
  python3                        # bench and fuzz helper scripts
  zstd                           # fuzz seeds: scripts/fuzz.sh unpacks archive indexes (format 5)
  python3-distributed            # sharded builds: python3 -m ridge_dask on Dask distributed
  clang libclang-rt-14-dev       # libFuzzer targets (scripts/fuzz.sh), the sanitizer build
  libomp-dev                     # OpenMP for clang (the sanitizer build)
  clang-format-14                # the formatting scripts/check-layering.sh checks
  # ridge codec-bench: anchor codecs (LERC, JPEG-LS, JPEG 2000, JPEG XL, ZFP) and its PNG plot
  liblerc-dev libcharls-dev libjxl-dev libzfp-dev
  libplplot-dev plplot-driver-cairo
  # GPU layer and renderer: OpenGL 4.5 core through libepoxy, headless EGL (Mesa llvmpipe on CI),
  # windows through GLFW, GLM maths, Dear ImGui overlay; xvfb + xauth for the windowed smoke test
  libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libglm-dev libimgui-dev
  xvfb xauth
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  SUDO=""
  [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
echo "ridge: all dependencies present"
