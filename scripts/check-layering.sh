#!/usr/bin/env bash
# Fails when a library's headers leak out of the modules that own them:
#   GDAL and PROJ only in src/io; GL, EGL and GLFW headers only in the GPU layer (src/gpu,
#   include/ridge/gpu) and the viewer's window code; the GPU layer (ridge/gpu/...) only in the
#   renderers and the tools that drive them (renderbench), the apps, benchmarks and tests — LOD, culling, error metrics and codecs stay
#   plain C++ that runs without a GL context; the public headers use only the standard library.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
report() {
  echo "layering: $1:" >&2
  echo "$2" >&2
  status=1
}
bad=$(grep -rlE '#include *[<"](gdal|ogr|cpl_)[a-z_]*\.h' src include apps | grep -v '^src/io/' || true)
[[ -z "$bad" ]] || report "GDAL headers outside src/io" "$bad"
bad=$(grep -rlE '#include *[<"]proj(\.h|/)' src include apps | grep -v '^src/io/' || true)
[[ -z "$bad" ]] || report "PROJ headers outside src/io" "$bad"
bad=$(grep -rlE '#include *[<"](epoxy|GL|EGL|GLFW)/' src include apps |
      grep -vE '^(src/gpu/|include/ridge/gpu/|apps/ridge/view_command\.cpp$)' || true)
[[ -z "$bad" ]] || report "GL/EGL/GLFW headers outside the GPU layer" "$bad"
bad=$(grep -rlE '#include *[<"]ridge/gpu/' src include |
      grep -vE '^(src/gpu/|src/render/|src/renderbench/|include/ridge/gpu/)' || true)
[[ -z "$bad" ]] || report "the GPU layer used outside the renderers" "$bad"
bad=$(grep -rlE '#include *[<"]ridge/(gpu|render)/' src/lod src/stream src/pyramid src/codec src/archive \
      src/io src/core include/ridge/lod include/ridge/stream 2>/dev/null || true)
[[ -z "$bad" ]] || report "GL-free stages include the GPU layer or the renderers" "$bad"
# The stream carries what LOD schemes prepare (stream::PatchProduct) without knowing any of them.
bad=$(grep -rlE '#include *[<"]ridge/lod/chunk_mesh\.h' src/stream include/ridge/stream 2>/dev/null || true)
[[ -z "$bad" ]] || report "the stream depends on a LOD scheme's product" "$bad"
# Schemes are found through the registry; only their own modules include the scheme interface,
# and the renderer's pieces that construct or drive them.
bad=$(grep -rlE '#include *"(\.\./)?terrain_scheme\.h"' src apps bench |
      grep -vE '^src/render/(schemes/[a-z_]+\.cpp|scheme_registry\.cpp|scheme_plan\.cpp|instance_buffer\.cpp|surface_capture\.cpp|terrain_renderer\.cpp|terrain_scheme\.h)$' || true)
[[ -z "$bad" ]] || report "the scheme interface used outside the renderer and the schemes" "$bad"
# The installed API (<ridge/ridge.h>, <ridge/error.h>) stands alone: standard headers only, so
# an embedding application needs no internal header and none of ridge's dependencies.
bad=$(grep -HE '^#include' include/ridge/ridge.h include/ridge/error.h |
      grep -vE ':#include (<[a-z_]+>|"ridge/error\.h")$' || true)
[[ -z "$bad" ]] || report "the public headers include more than the standard library" "$bad"
bad=$(grep -rhE '^#include *[<"]ridge/' examples | grep -vE '^#include <ridge/ridge\.h>$' || true)
[[ -z "$bad" ]] || report "the examples use more than <ridge/ridge.h>" "$bad"
((status == 0)) && echo "layering: ok"
exit $status
