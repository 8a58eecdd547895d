#!/usr/bin/env bash
# Builds the libFuzzer targets with clang and runs each for RIDGE_FUZZ_SECONDS (default 30),
# seeded with real archives built from tests/data: the payload decoders, the archive reader on
# raw bytes, the archive reader and the renderer's CPU side on archives whose checksums are
# resealed after every mutation (fuzz_archive_fields), and the renderer's parameters
# (fuzz_render_params, on the seed archives). Needs a Release build of the CLI in
# ./build (scripts/test.sh makes one). Exit status is non-zero when a fuzzer finds a crash;
# the reproducer is left in the fuzz build directory. A long run by hand:
# RIDGE_FUZZ_SECONDS=3600 bash scripts/fuzz.sh
# RIDGE_FUZZ_BUILD=DIR uses an existing clang build configured with -DRIDGE_BUILD_FUZZERS=ON
# (scripts/test.sh passes its sanitizer build, which saves a third build of the library);
# without it the script configures its own in build-fuzz (-O2, no OpenMP).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${RIDGE_FUZZ_SECONDS:-30}
fuzz_build=$(realpath -m "${RIDGE_FUZZ_BUILD:-build-fuzz}")
if [[ -z "${RIDGE_FUZZ_BUILD:-}" ]]; then
  # RelWithDebInfo with line tables only: crash reports keep file:line, at less build time.
  cmake -S . -B "$fuzz_build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
        "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
        "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
        -DCMAKE_C_COMPILER=clang -DRIDGE_BUILD_FUZZERS=ON -DRIDGE_USE_OPENMP=OFF \
        -DRIDGE_BUILD_TESTS=OFF -DRIDGE_BUILD_BENCH=OFF >/dev/null
elif ! grep -q '^RIDGE_BUILD_FUZZERS:BOOL=ON' "$fuzz_build/CMakeCache.txt" 2>/dev/null; then
  echo "fuzz: RIDGE_FUZZ_BUILD=$fuzz_build is not a build configured with -DRIDGE_BUILD_FUZZERS=ON" >&2
  exit 2
fi
cmake --build "$fuzz_build" -j "$(nproc)" --target fuzz_lossless_decode fuzz_progressive_decode fuzz_jpeg2000_decode fuzz_fractal_decode fuzz_archive_reader \
      fuzz_archive_fields fuzz_render_params fuzz_quantized_mesh_decode fuzz_pmtiles_read fuzz_shard_files

# Seeds: small real archives, and their patch payloads prefixed with the patch-size byte.
seeds=$fuzz_build/seeds
rm -rf "$seeds" && mkdir -p "$seeds/archive" "$seeds/payload" "$seeds/params" "$seeds/jpeg2000"
for patch in 17 65; do
  ./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/everest_$patch.ridge" -q --patch $patch
done
./build/ridge build tests/data/rainier_voids.tif -o "$seeds/archive/rainier_33.ridge" -q --patch 33
# Validity masks (format v2): a warped collar kept as nodata, and every void kept.
./build/ridge build tests/data/everest_utm44.tif -o "$seeds/archive/utm44_17.ridge" -q --patch 17
./build/ridge build tests/data/rainier_voids.tif -o "$seeds/archive/rainier_none_17.ridge" -q --patch 17 \
  --fill-voids none
cp tests/data/v1_everest_40x30.ridge "$seeds/archive/" # format v1
# The whole Earth (2°, a wrap column, both poles): the renderer's CPU side on the ellipsoid.
./build/ridge build tests/data/etopo5_globe_181x91.tif -o "$seeds/archive/globe_17.ridge" -q --patch 17
for e in 1 4; do
  ./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/progressive_e${e}_17.ridge" -q --patch 17 \
      --codec progressive --max-error $e
done
# Payloads v2 and v3 beside the default v4 (their contexts differ).
for v in 2 3; do
  ./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/progressive_v${v}_e1_17.ridge" -q \
      --patch 17 --codec progressive-v$v --max-error 1
done
# jpeg2000 (OpenJPEG; HTJ2K is not decoded from untrusted bytes): archives for the field fuzzers, payloads for its decoder.
./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/jpeg2000_17.ridge" -q --patch 17 \
    --codec jpeg2000 --max-error 2
# fractal: range blocks, domain positions, s, o, edges and corrections to mutate.
./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/fractal_17.ridge" -q --patch 17 \
    --codec fractal --max-error 2
python3 - "$seeds" <<'PY'
import struct, sys, glob, os, subprocess
seeds = sys.argv[1]

def index_entries(b, index):
    # Format 5 packs the index: one zstd frame of the 48-byte entries byte-transposed.
    raw = b[index:]
    if struct.unpack_from("<I", b, 8)[0] < 5:
        return raw
    t = subprocess.run(["zstd", "-d", "-c", "-q"], input=raw, stdout=subprocess.PIPE, check=True).stdout
    count = len(t) // 48
    return bytes(t[k * count + i] for i in range(count) for k in range(48))

os.makedirs(seeds + "/progressive", exist_ok=True)
os.makedirs(seeds + "/fractal", exist_ok=True)
for path in glob.glob(seeds + "/archive/*.ridge"):
    b = open(path, "rb").read()
    n = struct.unpack_from("<I", b, 24)[0]
    size_byte = {5: 0, 9: 1, 17: 2, 33: 3, 65: 4, 129: 5}[n]
    entries = index_entries(b, struct.unpack_from("<Q", b, 128)[0])
    for k in range(0, len(entries) // 48, 3):
        _, _, _, be, off, size, _ = struct.unpack_from("<IIIIQII", entries, 48 * k)
        lvl = struct.unpack_from("<I", entries, 48 * k)[0]
        payload = b[off + be: off + size]
        version = struct.unpack_from("<I", b, 8)[0]
        if version >= 2:  # the validity mask: kind 0, a patch without nodata (others skipped)
            if payload[:1] != b"\0":
                continue
            payload = payload[1:]
        if version >= 4:  # the sample flags: kind 0 or 1 alone, kind 2 and its zstd frame,
            # or kind 3, its plane byte and its stream
            skip = {2: lambda: 5 + struct.unpack_from("<I", payload, 1)[0],
                    3: lambda: 6 + struct.unpack_from("<I", payload, 2)[0]}.get(payload[0], lambda: 1)()
            payload = payload[skip:]
        if payload[:1] == b"J":  # jpeg2000: size, level | quadrant << 1 | HTJ2K << 3
            name = "%s/jpeg2000/%s_%d" % (seeds, os.path.basename(path), k)
            control = min(lvl, 1) | ((lvl and k % 4) << 1) | (8 if "htj2k" in path else 0)
            open(name, "wb").write(bytes([size_byte, control]) + payload)
        elif payload[:1] == b"F":  # fractal: size, then the payload
            name = "%s/fractal/%s_%d" % (seeds, os.path.basename(path), k)
            open(name, "wb").write(bytes([size_byte]) + payload)
        elif payload[:1] == b"P":  # progressive: size, level|quadrant, bound|variant, parent seed
            # The variant the payload was written with: v1 (cubic, contexts), or v2..v4 with
            # 32 nested levels and cubic prediction (byte 3's bits 6..7: the version).
            name = "%s/progressive/%s_%d" % (seeds, os.path.basename(path), k)
            v = payload[1]
            variant = (3 << 5) | 1 if v == 1 else (7 << 5) | 1
            open(name, "wb").write(bytes([size_byte, min(lvl, 3), variant, {3: 0x40, 4: 0x80}.get(v, 0)]) + payload)
        else:
            name = "%s/payload/%s_%d" % (seeds, os.path.basename(path), k)
            open(name, "wb").write(bytes([size_byte]) + payload)
PY
# More field layouts for the archive-field fuzzer (after the payload seeds: raw is no payload
# of the decoders above): raw codes, Neville levels with stored block errors.
./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/raw_33.ridge" -q --patch 33 --codec raw
./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/neville_blocks_33.ridge" -q --patch 33 \
    --filter neville --store-block-errors
# Small enough (99 patches) for fuzz_archive_fields to verify whole: jpeg2000 payloads (bytes
# after the EOC) and kept nodata (masks across levels).
./build/ridge build tests/data/everest_crop.tif -o "$seeds/archive/jpeg2000_33.ridge" -q --patch 33 \
    --codec jpeg2000 --max-error 2
./build/ridge build tests/data/rainier_voids.tif -o "$seeds/archive/rainier_none_neville_33.ridge" -q \
    --patch 33 --fill-voids none --filter neville

# A quantized-mesh tile (the golden tile of tests/web/quantized_mesh_test.cpp): header, 4
# vertices, 2 triangles, edges and the three extensions.
mkdir -p "$seeds/quantized_mesh"
python3 - "$seeds/quantized_mesh/square.terrain" <<'PY'
import struct, sys
head = struct.pack('<3d2f4d3d', 1, 2, 3, -10, 90, 1, 2, 3, 4, 0.5, 0.25, 0.125)
body = bytes.fromhex('04000000' '0000feff0000fdff' '00000000feff0000' '0000c80036fff3ff'
                     '02000000' '000000000000030001000000' '0200000000000300' '0200000000000100'
                     '0200000001000200' '0200000003000200' '01080000000102030405060708'
                     '0201000000ff' '0406000000020000007b7d')
open(sys.argv[1], 'wb').write(head + body)
PY

# PMTiles archives of the fixture as `ridge tiles` writes them: quantized-mesh (gzip tiles)
# and terrain-RGB.
mkdir -p "$seeds/pmtiles"
./build/ridge tiles "$seeds/archive/everest_17.ridge" -o "$seeds/pmtiles/mesh.pmtiles" -q --maxzoom 6
./build/ridge tiles "$seeds/archive/everest_17.ridge" -o "$seeds/pmtiles/rgb.pmtiles" -q \
    --format terrarium --maxzoom 4

# A sharded build's plan and files (lossless and progressive, so every section kind is there).
mkdir -p "$seeds/shard"
./build/ridge plan tests/data/everest_crop.tif --shard-level 1 --patch 33 -q \
    --codec progressive --max-error 1 -o "$seeds/shard/plan.json"
./build/ridge build --plan "$seeds/shard/plan.json" --shard 0 --summary -q -o "$seeds/shard/s0"
./build/ridge build --plan "$seeds/shard/plan.json" --shard 1 --summary -q -o "$seeds/shard/s1"
./build/ridge build --plan "$seeds/shard/plan.json" --coordinate -q \
    --summaries "$seeds/shard/s0" "$seeds/shard/s1" -o "$seeds/shard/top0"
./build/ridge build --plan "$seeds/shard/plan.json" --shard 0 --observe "$seeds/shard/top0" -q \
    -o "$seeds/shard/o0"
./build/ridge build --plan "$seeds/shard/plan.json" --shard 1 --observe "$seeds/shard/top0" -q \
    -o "$seeds/shard/o1"
./build/ridge build --plan "$seeds/shard/plan.json" --coordinate -q \
    --summaries "$seeds/shard/s0" "$seeds/shard/s1" --top "$seeds/shard/top0" \
    --observations "$seeds/shard/o0" "$seeds/shard/o1" -o "$seeds/shard/top1"
./build/ridge build --plan "$seeds/shard/plan.json" --shard 0 --top "$seeds/shard/top1" -q \
    -o "$seeds/shard/g0"

status=0
export RIDGE_FUZZ_ARCHIVES=$seeds/archive # the archives fuzz_render_params renders
for target in fuzz_lossless_decode fuzz_progressive_decode fuzz_jpeg2000_decode fuzz_fractal_decode fuzz_archive_reader \
              fuzz_archive_fields fuzz_render_params fuzz_quantized_mesh_decode fuzz_pmtiles_read \
              fuzz_shard_files; do
  seed_dir=$seeds/payload
  [[ $target == fuzz_archive_reader || $target == fuzz_archive_fields ]] && seed_dir=$seeds/archive
  [[ $target == fuzz_progressive_decode ]] && seed_dir=$seeds/progressive
  [[ $target == fuzz_jpeg2000_decode ]] && seed_dir=$seeds/jpeg2000
  [[ $target == fuzz_fractal_decode ]] && seed_dir=$seeds/fractal
  [[ $target == fuzz_render_params ]] && seed_dir=$seeds/params
  [[ $target == fuzz_quantized_mesh_decode ]] && seed_dir=$seeds/quantized_mesh
  [[ $target == fuzz_pmtiles_read ]] && seed_dir=$seeds/pmtiles
  [[ $target == fuzz_shard_files ]] && seed_dir=$seeds/shard
  corpus=$fuzz_build/corpus-$target # new inputs go here; the seeds stay as built
  mkdir -p "$corpus"
  echo "fuzz: $target for ${seconds}s"
  rc=0
  (cd "$fuzz_build" && ./fuzz/$target -max_total_time="$seconds" -max_len=400000 -rss_limit_mb=2048 \
      -print_final_stats=1 "$corpus" "$seed_dir" > "$target.log" 2>&1) || rc=$?
  grep -E "^Done|stat::number_of_executed_units|stat::peak_rss_mb|ERROR|SUMMARY" "$fuzz_build/$target.log" || true
  if [[ $rc -ne 0 ]]; then
    echo "fuzz: $target exited with $rc (full log: $fuzz_build/$target.log)" >&2
    status=1
  fi
done
exit $status
