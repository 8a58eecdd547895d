#!/usr/bin/env bash
# Fails when a library's headers leak out of the modules that own them:
#   GDAL and PROJ only in src/io; GL, EGL and GLFW headers only in the GPU layer (src/gpu,
#   include/ridge/gpu) and the viewer's window code; the GPU layer (ridge/gpu/...) only in the
#   renderers and the tools that drive them (renderbench), the apps, benchmarks and tests — LOD, culling, error metrics and codecs stay
#   plain C++ that runs without a GL context; the public headers use only the standard library;
#   a LOD scheme's name is spelt only by its own module, its own tests and the registry; and a
#   codec's id only by the codecs' modules.
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
# cpp-httplib only behind web::HttpServer: what is answered stays plain C++ (TileService).
bad=$(grep -rlE '#include *[<"]httplib\.h' src include apps | grep -v '^src/web/http_server\.cpp$' || true)
[[ -z "$bad" ]] || report "cpp-httplib outside src/web/http_server.cpp" "$bad"
bad=$(grep -rlE '#include *[<"]ridge/gpu/' src include |
      grep -vE '^(src/gpu/|src/render/|src/renderbench/|include/ridge/gpu/)' || true)
[[ -z "$bad" ]] || report "the GPU layer used outside the renderers" "$bad"
bad=$(grep -rlE '#include *[<"]ridge/(gpu|render)/' src/lod src/stream src/pyramid src/codec src/archive \
      src/io src/core src/web include/ridge/lod include/ridge/stream include/ridge/web 2>/dev/null || true)
[[ -z "$bad" ]] || report "GL-free stages include the GPU layer or the renderers" "$bad"
# The stream carries what LOD schemes prepare (stream::PatchProduct) without knowing any of them.
bad=$(grep -rlE '#include *[<"]ridge/lod/chunk_mesh\.h' src/stream include/ridge/stream 2>/dev/null || true)
[[ -z "$bad" ]] || report "the stream depends on a LOD scheme's product" "$bad"
# Schemes are found through the registry; only their own modules include the scheme interface,
# and the renderer's pieces that construct or drive them.
bad=$(grep -rlE '#include *"(\.\./)?terrain_scheme\.h"' src apps bench |
      grep -vE '^src/render/(schemes/[a-z_]+\.cpp|scheme_registry\.cpp|scheme_plan\.cpp|scheme_programs\.cpp|instance_buffer\.cpp|surface_capture\.cpp|terrain_renderer\.cpp|terrain_scheme\.h)$' || true)
[[ -z "$bad" ]] || report "the scheme interface used outside the renderer and the schemes" "$bad"
# The installed API (<ridge/ridge.h>, <ridge/error.h>) stands alone: standard headers only, so
# an embedding application needs no internal header and none of ridge's dependencies.
bad=$(grep -HE '^#include' include/ridge/ridge.h include/ridge/error.h |
      grep -vE ':#include (<[a-z_]+>|"ridge/error\.h")$' || true)
[[ -z "$bad" ]] || report "the public headers include more than the standard library" "$bad"
bad=$(grep -rhE '^#include *[<"]ridge/' examples | grep -vE '^#include <ridge/ridge\.h>$' || true)
[[ -z "$bad" ]] || report "the examples use more than <ridge/ridge.h>" "$bad"
# Nothing else names a LOD scheme: the CLI, benchmarks, examples, fuzzers and other tests take
# the registry's names (render::lodSchemeNames(), defaultLodScheme(), lodSchemeVariants()), so
# that adding or removing a scheme changes its module, its line in scheme_registry.cpp and its
# own tests alone. The names are read from the modules (`.name = "NAME"` in each
# src/render/schemes/*_scheme.cpp), so a new scheme is covered without editing this script. A
# scheme is named by a string literal "NAME" or a spec "NAME,KEY=VALUE...", or by --lod NAME
# (--renderer NAME) inside a literal or a script; only src/render/schemes/<module>.cpp,
# src/render/scheme_registry.cpp and tests/render/schemes/<module>_test.cpp may name it.
# Comments (from // to the end of the line) are not code and may.
# Allowed exceptions, each a name that is not a scheme:
#   - the debug mode `--mode tess` (the tessellation-factor heat map: render::DebugMode, not
#     the scheme), parsed in apps/ridge/render_args.h's parseDebugMode (`mode == "tess"`).
scheme_exceptions='^apps/ridge/render_args\.h:[0-9]+: *if \(mode == "tess"\)$'
scheme_sources=$(find src include apps bench tests examples fuzz scripts \
                   \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' -o -name '*.cc' \
                      -o -name '*.sh' -o -name '*.cmake' -o -name CMakeLists.txt \) \
                   -not -path scripts/check-layering.sh | sort)
for module in src/render/schemes/*_scheme.cpp; do
  name=$(grep -oE '\.name *= *"[^"]+"' "$module" | sed -E 's/.*"([^"]+)"$/\1/' || true)
  if [[ $(wc -l <<< "$name") -ne 1 || -z $name ]]; then
    report "a scheme module without exactly one '.name = \"NAME\"'" "$module"
    continue
  fi
  if [[ ! $name =~ ^[a-z0-9-]+$ ]]; then
    report "a scheme name that is not lower case, digits and '-'" "$module: $name"
    continue
  fi
  own_test="tests/render/schemes/$(basename "$module" .cpp)_test.cpp"
  named="\"$name(,[^\"]*)?\"|--(lod|renderer)[ =]'?$name([^a-z0-9-]|\$)"
  # shellcheck disable=SC2086
  bad=$(grep -HnE "$named" $scheme_sources |
        grep -vE "^($module|src/render/scheme_registry\.cpp|$own_test):" |
        sed -E 's#^([^:]*:[0-9]+:)(.*)$#\1\2#; s#//.*$##' | grep -E "$named" |
        grep -vE "$scheme_exceptions" || true)
  [[ -z "$bad" ]] || report "scheme '$name' named outside its module, its tests and the registry" "$bad"
done
# A codec's id (its module's kNameCodecId) is its own: the rest of ridge reaches codecs through
# the registry (ridge/codec/codec_registry.h: names, ids, lossiness, options, messages) and the
# HeightCodec interface, so a codec is its module and one line in src/codec/codec_registry.cpp.
bad=$(grep -rnE 'k[A-Z][A-Za-z0-9]*CodecId|CodecId *\{ *[0-9]' src apps include bench examples fuzz |
      grep -vE '^(src/codec/|include/ridge/codec/)' || true)
[[ -z "$bad" ]] || report "a codec's id used outside the codecs' modules" "$bad"
# Formatting is the repository's .clang-format, applied by clang-format 14 (Debian 12's; other
# versions format some constructs differently), so it is checked, not remembered. Fix with
#   git ls-files '*.cpp' '*.h' | xargs clang-format-14 -i
if command -v clang-format-14 >/dev/null; then
  bad=$(git ls-files '*.cpp' '*.h' '*.hpp' | while read -r f; do
          clang-format-14 --dry-run -Werror "$f" >/dev/null 2>&1 || echo "$f"
        done)
  [[ -z "$bad" ]] || report "C++ files not formatted by .clang-format (clang-format-14 -i)" "$bad"
else
  report "clang-format-14 is not installed (scripts/install-deps.sh installs it)" "formatting unchecked"
fi
((status == 0)) && echo "layering: ok"
exit $status
